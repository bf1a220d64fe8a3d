"""The empty frame of each report figure: its axes with their labels, scales, ticks and grid.

Building a frame (the axes, and the tick objects a first drawing makes) is about a third of
what a figure costs to draw. prebuild() builds every frame with its ticks in the process the
scenario processes are forked from; frame(name) hands out such a ready frame once, and builds
a new one otherwise (a second scenario in one process, a test): the same frame either way.

    with harness_rc(): ...       matplotlib's defaults plus HARNESS_RC, whatever a user set
    frame(name)                  (figure, axes) of FRAMES[name], to draw the data into
    save(fig, path)              the PNG (compare/report/png.py); returns the file's name
"""
from __future__ import annotations

import contextlib
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.font_manager import FontProperties  # noqa: E402
from matplotlib.transforms import ScaledTranslation  # noqa: E402
from matplotlib.ticker import FuncFormatter, LogLocator, MaxNLocator, NullLocator  # noqa: E402

from scene_types.state import STATE_COMPONENTS, UNIT_OF  # noqa: E402

from .png import write_rgb  # noqa: E402

DPI = 100   # 800 pixels across the 8-inch figures: 10-point text stays sharp
# Fixed margins (fractions of the figure) that hold the axis labels and titles of these
# figures: matplotlib's tight_layout measured every tick label and took a third of a report.
MARGINS = dict(left=0.14, right=0.97, top=0.92, hspace=0.3, wspace=0.25)
X_LABEL_ROOM = 0.55   # inches under the axes for the tick labels and the x label (10-point text)
# Titles at a fixed height above their axes: placed automatically, each title measures the
# bounding box of every tick label of its axes first, which was 40 % of drawing a figure.
# Glyphs drawn unhinted: the same letters to the eye at 10 points, without running each
# glyph's TrueType hinting program, which was a sixth of drawing a figure.
HARNESS_RC = {"axes.titley": 1.0, "text.hinting": "no_hinting"}
# At most this many intervals between labelled ticks of a linear axis (matplotlib's default
# fits up to 9 on an 8-inch axis): every tick is a handful of artists to build and draw. On
# the x axis one more, for a tick every 0.5 s over the built-ins' runs of 2 to 3 s.
LINEAR_BINS, X_BINS = 6, 7
NICE_STEPS = (1, 2, 2.5, 5, 10)   # tick spacings (times a power of ten): matplotlib's default's
# Labelled ticks of a log axis, a decade or a few apart, none between them: a log axis over 15
# decades otherwise builds some hundred tick objects that are never drawn.
LOG_TICKS = 8
SNAPSHOTS = 6   # bodies drawn side by side in the snapshots figure
SNAPSHOT_TICK_SIZE = 7   # points: the tick labels of the snapshots' narrow axes

_ready: dict[str, tuple] = {}   # name -> a prebuilt (figure, axes), each handed out once


@contextlib.contextmanager
def harness_rc():
    """matplotlib's defaults plus HARNESS_RC inside the block, whatever a user's module set
    (text.usetex, a style); the settings before it are back after it."""
    with matplotlib.rc_context():
        matplotlib.rcdefaults()
        matplotlib.rcParams.update(HARNESS_RC)
        yield


def _power_of_ten(value: float, _position) -> str:
    """A log axis's tick label as plain text, 1e-12: the default typesets each one as TeX."""
    return f"1e{round(np.log10(value)):d}" if value > 0 else ""


def _figure(size: tuple, rows: int, cols: int, **shared):
    """A figure of rows x cols axes outside pyplot (nothing to register or close), with the
    fixed margins; axes as a flat array."""
    fig = Figure(figsize=size, dpi=DPI)
    FigureCanvasAgg(fig)
    axes = fig.subplots(rows, cols, squeeze=False, **shared).ravel()
    fig.subplots_adjust(bottom=X_LABEL_ROOM / size[1], **MARGINS)
    for ax in axes:
        ax.xaxis.set_major_locator(_ticks(X_BINS))
        ax.yaxis.set_major_locator(_ticks())
        _x_label_under_ticks(ax)
    return fig, axes


def _ticks(bins: int = LINEAR_BINS) -> MaxNLocator:
    """Ticks of a linear axis: at most `bins` intervals, each a NICE_STEPS spacing."""
    return MaxNLocator(bins, steps=NICE_STEPS)


def _x_label_under_ticks(ax, tick_label_size=None) -> None:
    """Fix ax's x label where matplotlib places it under one row of tick labels (of
    tick_label_size, default the rc's): tick, pad, labels and label pad under the axes. Placed
    automatically, it measures every tick label of the axis at each drawing (a tenth of drawing
    a figure)."""
    rc = matplotlib.rcParams
    size = FontProperties(size=tick_label_size or rc["xtick.labelsize"]).get_size_in_points()
    drop = rc["xtick.major.size"] + rc["xtick.major.pad"] + size + rc["axes.labelpad"]   # points
    ax.xaxis.set_label_coords(0.5, 0.0, ax.transAxes + ScaledTranslation(0.0, -drop / 72, ax.figure.dpi_scale_trans))


def _log_y(ax) -> None:
    """A log y axis labelled by decades, in plain text."""
    ax.set_yscale("log")
    ax.yaxis.set_major_locator(LogLocator(numticks=LOG_TICKS))
    ax.yaxis.set_minor_locator(NullLocator())
    ax.yaxis.set_major_formatter(FuncFormatter(_power_of_ten))


def _labelled(axes, ylabels: tuple, xlabel: str, **grid) -> None:
    """Each axes' y label, the bottom one's x label, a light grid."""
    for ax, label in zip(axes, ylabels):
        ax.set_ylabel(label)
        ax.grid(alpha=0.3, **grid)
    axes[-1].set_xlabel(xlabel)


def _states():
    fig, axes = _figure((8, 7), 3, 1, sharex=True)
    _labelled(axes, ("x (m)", "y (m)", "theta (rad)"), "time (s)")
    return fig, axes


def _path():
    fig, axes = _figure((8, 4), 1, 1)
    _labelled(axes, ("y (m)",), "x (m)")
    return fig, axes


def _error():
    fig, axes = _figure((8, 5.5), 2, 1, sharex=True)
    for ax in axes:
        _log_y(ax)
    _labelled(axes, ("position difference (m)", "angle difference (rad)"), "time (s)", which="both")
    return fig, axes


def _energy():
    fig, axes = _figure((8, 5.5), 2, 1, sharex=True)
    _labelled(axes, ("energy (J)", "R = E - E(0) + W (J)"), "time (s)")
    return fig, axes


def _snapshots():
    fig, axes = _figure((2.2 * SNAPSHOTS, 3.2), 1, SNAPSHOTS, sharey=True)
    for ax in axes:
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)", fontsize=8)
        ax.tick_params(labelsize=SNAPSHOT_TICK_SIZE)
        _x_label_under_ticks(ax, SNAPSHOT_TICK_SIZE)
        ax.xaxis.set_major_locator(_ticks(3))
    axes[0].set_ylabel("y (m)")
    return fig, axes


# The residual figure's panels, in its axes' order (rows of positions | velocities).
RESIDUAL_PANELS = tuple(c for pair in zip(STATE_COMPONENTS[:3], STATE_COMPONENTS[3:]) for c in pair)
RESIDUAL_UNITS = UNIT_OF


def _residuals():
    fig, axes = _figure((8, 7), 3, 2, sharex=True)
    for ax, name in zip(axes, RESIDUAL_PANELS):
        _log_y(ax)
        ax.set_ylabel(f"{name} ({RESIDUAL_UNITS[name]})")
        ax.grid(alpha=0.3, which="both")
    for ax in axes[-2:]:
        ax.set_xlabel("time (s)")
    return fig, axes


FRAMES = {"states": _states, "path": _path, "error": _error, "energy": _energy,
          "snapshots": _snapshots, "residuals": _residuals}
# The spans over which prebuild counts the ticks an axis may need: a linear span just past its
# ticks at each end has the most a locator gives, its bins + 2 (the first span for 3 and 6
# bins, the second for 7); a log axis's 15 decades, LOG_TICKS + 2.
PRIMING_LINEAR, PRIMING_LOG = ((-0.01, 1.01), (-0.01, 0.61)), ((1e-15, 1.0),)


def _make_ticks(ax) -> None:
    """Make the tick objects each axis of ax may need, which drawing would make otherwise."""
    for axis in (ax.xaxis, ax.yaxis):
        locator = axis.get_major_locator()
        spans = PRIMING_LOG if axis.get_scale() == "log" else PRIMING_LINEAR
        axis.get_major_ticks(max(len(locator.tick_values(*span)) for span in spans))


def prebuild() -> None:
    """Build every frame with its tick objects, for frame() to hand out: call it before forking
    the processes that draw figures, which then inherit them. A frame still waiting (the parent
    of a run draws none) is kept."""
    with harness_rc():
        for name, build in FRAMES.items():
            if name in _ready:
                continue
            fig, axes = build()
            for ax in axes:
                _make_ticks(ax)
            _ready[name] = (fig, axes)


def frame(name: str):
    """(figure, axes) of the frame `name`: prebuilt if one is waiting, else built now."""
    ready = _ready.pop(name, None)
    return ready if ready is not None else FRAMES[name]()


def save(fig, path: Path) -> str:
    """Draw fig and write it as the PNG path; returns the file's name. The pixels savefig
    would write (the figure is at DPI, on its own background), through a quicker encoder."""
    fig.canvas.draw()
    write_rgb(path, np.asarray(fig.canvas.buffer_rgba())[:, :, :3])
    return path.name
