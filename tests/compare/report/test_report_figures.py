"""The report's figures: the line thinning keeps what a reader must see (every extreme of every
run of samples, the first and last sample, in time order); a frame built ahead draws the same
PNG as one built on the spot; each figure keeps its title, axis labels, legend and data; the
PNG writer keeps every pixel savefig would write."""
from __future__ import annotations

import numpy as np

from compare.report.plots import MAX_POINTS, _envelope
from compare.checks.step_check import step_trace


def test_short_lines_are_drawn_whole():
    y = np.arange(MAX_POINTS, dtype=float)
    assert _envelope(y) == slice(None)


def test_a_one_sample_spike_and_each_runs_extremes_survive():
    rng = np.random.default_rng(1)
    y = rng.normal(size=100_003)
    spike = 54_321
    y[spike] = 50.0                      # one sample, far above the rest
    k = _envelope(y)
    assert len(k) <= MAX_POINTS + 2
    assert np.all(np.diff(k) > 0), "indices in time order, none twice"
    assert k[0] == 0 and k[-1] == len(y) - 1
    assert spike in k
    assert y[k].max() == y.max() and y[k].min() == y.min()
    # every run of samples keeps its own lowest and highest point
    runs = MAX_POINTS // 2
    width = -(-len(y) // runs)
    for start in range(0, len(y), width * 97):   # a spread of runs
        run = y[start:start + width]
        assert start + int(np.argmax(run)) in k and start + int(np.argmin(run)) in k


# ---- the figures drawn into their frames (compare/report/frames.py) ----

def _figures(tmp, scene):
    """The six figures of a page, for a synthetic run of `scene` drawn by custom_sim and MuJoCo:
    name -> function drawing it into the folder tmp (as compare/report/pages.py calls them)."""
    from types import SimpleNamespace

    from compare.report import plots
    from custom_sim import Trajectory

    steps = 30_000   # longer than MAX_POINTS: every line goes through its envelope
    t = scene.dt * np.arange(steps + 1)
    wave = np.exp(-t) * np.cos(12 * t)

    def run(simulator, shift):
        x, y, theta = 0.2 * t + shift, 0.1 + 0.2 * np.abs(wave), 0.3 * wave
        zero = np.zeros_like(t)
        return Trajectory(t, x, y, theta, zero, zero, zero, zero, 9.81 * y, zero, simulator=simulator)

    custom, mujoco = run("custom", 0.0), run("mujoco", 1e-3)
    energy = 9.81 * (custom.y - custom.y.min())
    balances = {name: SimpleNamespace(t=t, E=energy, dissipated=energy[0] - energy, R=1e-6 * wave)
                for name in ("custom_sim", "mujoco", "reference")}
    diffs = {"t": t, "position": np.abs(1e-3 * wave) + 1e-14, "angle": np.abs(1e-2 * wave)}
    r = 1e-17 * (1 + np.abs(wave[1:]))[:, None] * np.ones(6)
    residuals = {"semi_implicit_euler": step_trace(r, np.full_like(r, 1e-15))}
    shown = (custom, mujoco)
    return {"states": lambda: plots.states(scene, shown, tmp / "states.png", custom.states()),
            "path": lambda: plots.path_in_plane(scene, shown, tmp / "path.png"),
            "error": lambda: plots.error(scene, diffs, tmp / "error.png"),
            "energy": lambda: plots.energy(scene, balances, tmp / "energy.png"),
            "snapshots": lambda: plots.snapshots(scene, custom, mujoco, tmp / "snapshots.png"),
            "residuals": lambda: plots.step_residuals(scene, residuals, tmp / "residuals.png")}


def test_a_prebuilt_frame_draws_the_same_figure_as_a_new_one(tmp_path):
    """prebuild() draws each frame once ahead (for the forked scenario processes): the PNGs
    drawn into those frames are byte for byte those drawn into frames built on the spot."""
    from compare.report import frames
    from compare.report.plots import draw_all
    from compare.scenarios import load

    scene = load("box_drop")
    (tmp_path / "new").mkdir()
    (tmp_path / "prebuilt").mkdir()
    warnings = []
    frames._ready.clear()
    assert all(draw_all(_figures(tmp_path / "new", scene), warnings).values())
    frames.prebuild()
    assert all(draw_all(_figures(tmp_path / "prebuilt", scene), warnings).values())
    assert not frames._ready, "each prebuilt frame was handed out, once"
    assert not warnings
    for new in sorted((tmp_path / "new").iterdir()):
        assert new.read_bytes() == (tmp_path / "prebuilt" / new.name).read_bytes(), new.name


def test_a_second_prebuild_builds_only_the_frames_handed_out():
    """A process that runs twice (a test, a notebook) prebuilds before each run; the frames
    its forked processes inherited and it never drew into are kept, not built again."""
    from compare.report import frames

    frames._ready.clear()
    frames.prebuild()
    waiting = dict(frames._ready)
    taken = frames.frame("energy")
    frames.prebuild()
    assert frames._ready.keys() == frames.FRAMES.keys()
    assert all(frames._ready[n] is waiting[n] for n in frames.FRAMES if n != "energy")
    assert frames._ready["energy"] is not taken
    frames._ready.clear()


def test_every_figure_has_its_title_axis_labels_and_legend(tmp_path, monkeypatch):
    from compare.report import frames, plots
    from compare.scenarios import load

    saved = {}
    real_save = frames.save

    def keep(fig, path):
        saved[path.stem] = fig
        return real_save(fig, path)

    monkeypatch.setattr(plots, "save", keep)
    scene = load("box_drop")
    warnings = []
    drawn = plots.draw_all(_figures(tmp_path, scene), warnings)
    assert drawn == {name: f"{name}.png" for name in ("states", "path", "error", "energy", "snapshots",
                                                        "residuals")} and not warnings
    for name, fig in saved.items():
        titles = [ax.get_title() for ax in fig.axes] + [fig._suptitle.get_text() if fig._suptitle else ""]
        assert any(title.startswith(f"{scene.name}:") for title in titles), name
        assert all(ax.get_ylabel() or ax is not fig.axes[0] for ax in fig.axes), name
        assert all(ax.get_xlabel() for ax in fig.axes[-1:]), name
        assert any(ax.get_legend() for ax in fig.axes), name
        assert all(any(line.get_xydata().size for line in ax.get_lines()) for ax in fig.axes), name
    legend = [t.get_text() for t in saved["states"].axes[0].get_legend().get_texts()]
    assert legend == ["custom_sim", "MuJoCo", "converged reference"]
    assert [ax.get_ylabel() for ax in saved["states"].axes] == ["x (m)", "y (m)", "theta (rad)"]
    assert saved["error"].axes[0].get_yscale() == "log" and saved["residuals"].axes[0].get_yscale() == "log"
    assert [ax.get_title() for ax in saved["snapshots"].axes][0] == "t = 0.00 s"


def test_a_png_holds_exactly_the_pixels_written(tmp_path):
    from PIL import Image

    from compare.report.png import write_rgb

    rgb = np.random.default_rng(2).integers(0, 256, size=(37, 53, 3), dtype=np.uint8)
    rgb[5:9] = 255                                   # flat rows, as a figure's white
    write_rgb(tmp_path / "a.png", rgb)
    with Image.open(tmp_path / "a.png") as image:
        assert image.mode == "RGB" and np.array_equal(np.asarray(image), rgb)


def test_a_saved_figure_has_the_pixels_savefig_writes(tmp_path):
    from PIL import Image

    from compare.report import frames

    with frames.harness_rc():
        fig, axes = frames.frame("error")
        axes[0].plot([0.0, 1.0, 2.0], [1e-12, 1e-3, 1e-6], label="a line")
        axes[0].legend()
        axes[0].set_title("a title")
        frames.save(fig, tmp_path / "error.png")
        fig.savefig(tmp_path / "savefig.png")
    with Image.open(tmp_path / "error.png") as ours, Image.open(tmp_path / "savefig.png") as theirs:
        assert ours.size == theirs.size == (800, 550)
        assert np.array_equal(np.asarray(ours), np.asarray(theirs.convert("RGB")))


def test_an_omega_only_failure_shows_in_the_residual_figure(tmp_path, monkeypatch):
    """Before: the figure drew the position residual alone, so a step off in omega only (a
    friction torque's sign) looked like a pass. One step of 200,000 over its round-off in omega
    is kept by the trace and drawn as a cross in the omega panel, and nowhere else."""
    from compare.report import frames, plots
    from compare.scenarios import load

    steps, bad = 200_000, 123_457
    r = np.full((steps, 6), 1e-17)
    b = np.full((steps, 6), 1e-15)
    r[bad, 5] = 3e-4                                   # rad/s, the newcomer's box at its touchdown
    trace = step_trace(r, b)
    assert len(trace.steps) <= 1000 and bad + 1 in trace.steps[:, 5]
    saved = {}
    real_save = frames.save
    monkeypatch.setattr(plots, "save", lambda fig, path: saved.setdefault("fig", fig) and real_save(fig, path))
    scene = load("box_drop")
    assert plots.step_residuals(scene, {"semi_implicit_euler": trace}, tmp_path / "residuals.png")
    axes = saved["fig"].axes
    assert [ax.get_ylabel() for ax in axes] == ["x (m)", "vx (m/s)", "y (m)", "vy (m/s)", "theta (rad)",
                                                "omega (rad/s)"]
    crosses = {ax.get_ylabel(): [ln for ln in ax.get_lines() if ln.get_marker() == "x"] for ax in axes}
    assert [k for k, v in crosses.items() if v] == ["omega (rad/s)"]
    (line,) = crosses["omega (rad/s)"]
    assert line.get_xydata().tolist() == [[(bad + 1) * scene.dt, 3e-4]]
