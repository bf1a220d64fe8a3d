"""The picture: pitch, goal, 1 m line and rules drawn once; ball, arrow and texts blitted each frame.

`GameView(fig, game)` draws on any matplotlib figure: the window's (interactive backend)
or an off-screen Agg canvas (`offscreen_view`) for videos and the frame-rate measurement.
Blitting: the static picture is rendered once into a background buffer (again after a
resize, on "draw_event"); each frame restores it and draws only the animated artists.

`python -m compare tools game-fps` measures the frame rate headless (Agg): print_fps below.
"""
from __future__ import annotations

import math
import time

import numpy as np
from matplotlib.transforms import Bbox

from .game import Game
from .rules import GOAL, NO_KICK, OUT, OVER, TIME, TOO_CLOSE

WIDTH, HEIGHT, DPI = 960, 432, 100     # px; both multiples of 16 for the video encoder
X_RANGE = (-0.7, 11.0)                 # m shown; the height follows at 1:1
Y_BOTTOM = -0.45                       # m: a strip of ground below y = 0
ARROW_LENGTH = 0.7                     # m, the player's force arrow for one key

SKY, GRASS, LINE, LIMIT = "#cfe8f7", "#4f9a3a", "#ffffff", "#d08a00"
MESSAGE_COLOURS = {GOAL: "#0b6e1c", TOO_CLOSE: "#c0392b", OVER: "#8a5a00", NO_KICK: "#8a5a00",
                   OUT: "#555555", TIME: "#555555", None: "#1b3a5c"}

RULES = ("W A S D push the ball (up, left, down, right)   R new pass   Q quit\n"
         "A goal counts when your last kick is taken from at least 1 m (dashed line) and the "
         "whole ball crosses the line under the bar")


class GameView:
    """Draws `game` on `fig` (a matplotlib Figure with a canvas)."""

    def __init__(self, fig, game: Game, offscreen: bool = False):
        from matplotlib.lines import Line2D
        from matplotlib.patches import Circle

        self.fig, self.game, self.offscreen = fig, game, offscreen
        self.canvas = fig.canvas
        fig.set_size_inches(WIDTH / DPI, HEIGHT / DPI)
        fig.set_dpi(DPI)
        ax = fig.add_axes((0.0, 0.0, 1.0, 1.0))
        width = X_RANGE[1] - X_RANGE[0]
        ax.set_xlim(*X_RANGE)
        ax.set_ylim(Y_BOTTOM, Y_BOTTOM + width * HEIGHT / WIDTH)
        ax.set_axis_off()
        ax.set_facecolor(SKY)
        fig.patch.set_facecolor(SKY)
        self.ax = ax
        self._draw_pitch()

        r = game.radius
        self.ball = Circle((0.0, r), r, facecolor="white", edgecolor="black", lw=1.2,
                           zorder=5, animated=True)
        self.seams = Line2D([], [], color="black", lw=1.0, zorder=6, animated=True)
        self.arrow = Line2D([], [], color="#d62728", lw=2.5, zorder=7, animated=True)
        self.score = ax.text(0.01, 0.97, "", transform=ax.transAxes, va="top", ha="left",
                             fontsize=12, family="monospace", weight="bold", animated=True)
        self.kick = ax.text(0.01, 0.905, "", transform=ax.transAxes, va="top", ha="left",
                            fontsize=12, family="monospace", weight="bold", animated=True)
        self.message = ax.text(0.5, 0.80, "", transform=ax.transAxes, va="center", ha="center",
                               fontsize=16, weight="bold", animated=True)
        for artist in (self.ball, self.seams, self.arrow):
            ax.add_artist(artist)
        self.moving = (self.ball, self.seams, self.arrow)             # drawn every frame
        self.texts = (self.score, self.kick, self.message)            # drawn when they change
        self.animated = self.moving + self.texts
        self._background = self._text_layer = self._text_key = self._last_boxes = None
        self.canvas.mpl_connect("draw_event", self._on_draw)

    # ------------------------------------------------------------------- the static picture
    def _draw_pitch(self) -> None:
        from matplotlib.patches import Arc, Circle, Rectangle

        ax, f = self.ax, self.game.field
        ax.add_patch(Rectangle((X_RANGE[0], Y_BOTTOM), X_RANGE[1] - X_RANGE[0], -Y_BOTTOM,
                               facecolor=GRASS, edgecolor="none", zorder=1))
        g, h, top, back = f.goal_line, f.crossbar_height, f.mouth_top, f.back
        # the goal: net, far post (behind the ball's plane), back stanchion, roof, crossbar
        ax.add_patch(Rectangle((g, 0.0), f.depth, h, facecolor="none", edgecolor="#b8c4cc",
                               hatch="++", lw=0, zorder=2))
        ax.plot([g, g], [0.0, h], color="#9aa5ad", lw=5, solid_capstyle="butt", zorder=2)
        ax.plot([back, back], [0.0, h], color="#f4f4f4", lw=6, zorder=3)
        ax.plot([g, back], [h, h], color="#dde3e8", lw=2, zorder=3)
        ax.add_patch(Circle((g, h), f.bar_radius, facecolor="white", edgecolor="#333333",
                            lw=1.2, zorder=4))
        ax.plot([g, g], [Y_BOTTOM, 0.0], color=LINE, lw=2, zorder=1)   # the goal line
        # the 1 m limit: every point at min_kick_distance from the mouth segment
        d = f.min_kick_distance
        style = dict(color=LIMIT, lw=1.6, ls=(0, (5, 4)), zorder=2)
        ax.plot([g - d, g - d], [0.0, top], **style)
        ax.add_patch(Arc((g, top), 2 * d, 2 * d, theta1=90, theta2=180, **style))
        ax.text(g - d - 0.08, 0.5 * top, f"{d:g} m from the goal mouth", ha="right", va="center",
                rotation=90, color=LIMIT, fontsize=9, weight="bold", zorder=2)
        self._draw_teammate()
        ax.text(0.5, 0.012, RULES, transform=ax.transAxes, ha="center", va="bottom",
                fontsize=8.5, color="white", zorder=8, linespacing=1.3)

    def _draw_teammate(self) -> None:
        """A stick figure at the left edge: the teammate who passes."""
        ax = self.ax
        x, hip, shoulder = -0.35, 0.85, 1.45
        kw = dict(color="#1f4e79", lw=3, solid_capstyle="round", zorder=3)
        ax.plot([x - 0.2, x, x + 0.25], [0.0, hip, 0.05], **kw)          # legs, one kicking
        ax.plot([x, x], [hip, shoulder], **kw)                              # body
        ax.plot([x - 0.3, x, x + 0.3], [1.05, shoulder - 0.05, 1.15], **kw)  # arms
        from matplotlib.patches import Circle
        ax.add_patch(Circle((x, shoulder + 0.16), 0.13, color="#1f4e79", zorder=3))

    # ------------------------------------------------------------------------ each frame
    def update(self) -> None:
        """Move the animated artists to the game's current state."""
        game, ref = self.game, self.game.referee
        x, y, theta = (float(v) for v in game.engine.state[:3])
        r = game.radius
        self.ball.center = (x, y)
        # two seams at right angles show the spin
        c, s = math.cos(theta) * r, math.sin(theta) * r
        self.seams.set_data([x - c, x + c, np.nan, x + s, x - s], [y - s, y + s, np.nan, y - c, y + c])
        fx, fy = game.player_force()
        if fx or fy:
            scale = ARROW_LENGTH / game.key_force
            tx, ty = x + fx * scale, y + fy * scale
            ang = math.atan2(fy, fx)
            hx = [tx - 0.18 * math.cos(ang + a) for a in (0.5, -0.5)]
            hy = [ty - 0.18 * math.sin(ang + a) for a in (0.5, -0.5)]
            self.arrow.set_data([x, tx, hx[0], tx, hx[1]], [y, ty, hy[0], ty, hy[1]])
        else:
            self.arrow.set_data([], [])
        if game.held:
            last = "(kicking)"   # the kick's distance is known when it ends; and text is costly
        elif ref.last_kick_distance is None:
            last = "-"
        else:
            last = f"{ref.last_kick_distance:.2f} m"
        self.score.set_text(f"Goals {ref.goals}   Shots {ref.shots}   Too close {ref.too_close}"
                            f"   Round {game.round + 1}")
        self.kick.set_text(f"Last kick from goal: {last}")
        self.message.set_text(ref.message)
        self.message.set_color(MESSAGE_COLOURS.get(ref.outcome, "#1b3a5c"))

    def _on_draw(self, event) -> None:
        self._background = self.canvas.copy_from_bbox(self.fig.bbox)
        self._text_key = self._last_boxes = None
        for artist in self.animated:
            self.ax.draw_artist(artist)

    def render(self) -> None:
        """One frame: restore the background, draw the moving parts, blit.

        Text is what costs (about 0.1 ms a glyph in Agg: 10 ms for the three lines), so the
        texts live in a second layer, the background plus the texts, rebuilt only on the
        frames where one changes (a key pressed or released, an outcome, a new round)."""
        self.update()
        if self._background is None:
            self.canvas.draw()          # renders the static picture; _on_draw saves it
        key = tuple(t.get_text() for t in self.texts) + (self.message.get_color(),)
        whole = key != self._text_key
        if whole:
            self.canvas.restore_region(self._background)
            for text in self.texts:
                self.ax.draw_artist(text)
            self._text_layer = self.canvas.copy_from_bbox(self.fig.bbox)
            self._text_key = key
        else:
            self.canvas.restore_region(self._text_layer)
        for artist in self.moving:
            self.ax.draw_artist(artist)
        # A window shows only what is blitted: the whole figure when a text changed, else the
        # box around the moving parts now and in the last frame (the full 960 x 432 image
        # costs ~8 ms through Tk on a virtual display, the ball's box a fraction of that).
        if self.offscreen:
            return                       # nothing to show: the pixels are in the Agg buffer
        boxes = self._moving_boxes()
        dirty = self.fig.bbox if whole or self._last_boxes is None else Bbox.union(boxes + self._last_boxes)
        self._last_boxes = boxes
        self.canvas.blit(dirty)

    def _moving_boxes(self) -> list:
        """Pixel boxes of the moving artists, padded for line widths and antialiasing."""
        renderer = self.canvas.get_renderer()
        boxes = []
        for artist in self.moving:
            box = artist.get_window_extent(renderer)
            if np.all(np.isfinite(box.get_points())) and box.width >= 0 and box.height >= 0:
                boxes.append(box.padded(4.0))
        return boxes

    def rgba(self) -> np.ndarray:
        """The frame's pixels (HEIGHT, WIDTH, 4) uint8 (off-screen canvas). RGBA, as Agg holds
        them: a contiguous copy (0.2 ms), where dropping alpha would cost a strided one (6 ms)."""
        return np.array(self.canvas.buffer_rgba(), copy=True)


def offscreen_view(game: Game) -> GameView:
    """A GameView on an Agg canvas: no screen needed."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure()
    FigureCanvasAgg(fig)
    return GameView(fig, game, offscreen=True)


def measure_fps(seconds: float = 6.0, frame_rate: float = 50.0, seed: int = 0,
                held_fraction: float = 0.2, redraw_text: bool = False) -> dict:
    """Frames per second of what the window does each frame: the physics for 1/frame_rate s,
    then the blitted drawing, here on an off-screen Agg canvas (a window adds pushing the
    blitted box to the screen; a video adds reading the pixels, timed apart as video_ms).
    D is held for `held_fraction` of each second (its kick distance, a text, changes every
    frame then); redraw_text re-renders all texts on every frame (the worst case)."""
    game = Game(seed=seed)
    view = offscreen_view(game)
    view.render()                                   # the static picture, once
    steps_per_frame = int(round(1.0 / (frame_rate * game.dt)))
    frames = int(seconds * frame_rate)
    period = int(frame_rate)
    physics = drawing = pixels = 0.0
    for i in range(frames):
        want = (i % period) < held_fraction * period
        if want and not game.held:
            game.press("d")
        elif not want and game.held:
            game.release("d")
        t0 = time.perf_counter()
        game.advance_to(game.step + steps_per_frame)
        t1 = time.perf_counter()
        if redraw_text:
            view._text_key = None
        view.render()
        t2 = time.perf_counter()
        view.rgba()
        t3 = time.perf_counter()
        physics += t1 - t0
        drawing += t2 - t1
        pixels += t3 - t2
    return {"frames": frames, "held_fraction": held_fraction, "redraw_text": redraw_text,
            "fps": frames / (physics + drawing), "physics_ms": 1e3 * physics / frames,
            "drawing_ms": 1e3 * drawing / frames, "video_ms": 1e3 * pixels / frames}


def print_fps() -> int:
    """The frame rate in three cases, one line each; 0."""
    for held, redraw in ((0.2, False), (1.0, False), (0.2, True)):
        r = measure_fps(held_fraction=held, redraw_text=redraw)
        case = "texts re-rendered every frame" if redraw else f"D held {held:.0%} of the time"
        print(f"{case:30s} {r['frames']} frames: {r['fps']:4.0f} fps (physics {r['physics_ms']:.2f} "
              f"+ drawing {r['drawing_ms']:.2f} ms/frame; reading pixels for a video "
              f"{r['video_ms']:.2f} ms more), matplotlib Agg with blitting")
    return 0
