"""The interactive window: real time, keys in, frames out. All the game is in `Game`.

Each frame (a timer, about 60 per second) the physics runs up to the step of the wall
clock, t / dt, then the view blits. A key event is stamped with the step the physics has
reached, so it acts from the first step of the next frame: within one frame. If drawing
ever falls behind by more than MAX_LAG the clock is held back (the game slows down rather
than jumping); the recording holds steps, so a replay is exact either way.
"""
from __future__ import annotations

import os
import sys
import time

from .game import DIRECTIONS, KEYS, QUIT, Game
from .recording import Recording, Replay

FRAME_PERIOD = 1.0 / 60.0  # s: the frame rate asked for (the timer waits the rest of it)
MAX_LAG = 0.1            # s of physics one frame may catch up at most
NON_INTERACTIVE = {"agg", "cairo", "pdf", "pgf", "ps", "svg", "template"}


def display_problem() -> str | None:
    """Why no window can open here, or None if one can."""
    if sys.platform.startswith(("linux", "freebsd", "openbsd")) and not (
            os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        return "no display is available (neither DISPLAY nor WAYLAND_DISPLAY is set)"
    import matplotlib
    backend = matplotlib.get_backend().lower()
    if backend in NON_INTERACTIVE:
        return f"matplotlib's backend {backend!r} cannot open a window"
    return None


class Window:
    """Plays `game` live (keys drive it), or a `replay` in real time (keys ignored but Q)."""

    def __init__(self, game: Game, replay: Replay | None = None, record_path=None,
                 engine_name: str = "custom"):
        self.game, self.replay, self.record_path, self.engine_name = game, replay, record_path, engine_name
        self._released: set[str] = set()   # releases held back one frame (key auto-repeat)
        self._clock0 = None
        self._step0 = 0
        self._saved = False

    def run(self) -> None:
        import matplotlib.pyplot as plt

        from .view import GameView

        fig = plt.figure(num="Kick the ball into the goal")
        manager = fig.canvas.manager
        if manager is not None and getattr(manager, "key_press_handler_id", None) is not None:
            fig.canvas.mpl_disconnect(manager.key_press_handler_id)  # 's' would save, 'q' quit...
        self.fig = fig
        self.view = GameView(fig, self.game)
        fig.canvas.mpl_connect("key_press_event", self._on_press)
        fig.canvas.mpl_connect("key_release_event", self._on_release)
        fig.canvas.mpl_connect("close_event", self._on_close)
        self.timer = fig.canvas.new_timer(interval=int(1000 * FRAME_PERIOD))
        self.timer.add_callback(self._frame)
        self.timer.start()
        plt.show()
        self._save()

    # ------------------------------------------------------------------------- keys
    @staticmethod
    def _key(event) -> str | None:
        key = (event.key or "").lower()
        return key if key in KEYS else None

    def _on_press(self, event) -> None:
        key = self._key(event)
        if key is None:
            return
        if self.replay is not None:
            if key == QUIT:
                self._close()
            return
        if key in self._released:
            self._released.discard(key)   # auto-repeat sends release + press: the key never left
            return
        self.game.press(key)
        if self.game.quit:
            self._close()

    def _on_release(self, event) -> None:
        key = self._key(event)
        if key in DIRECTIONS and self.replay is None:
            self._released.add(key)

    # ----------------------------------------------------------------------- frames
    def _frame(self) -> None:
        for key in sorted(self._released):
            self.game.release(key)
        self._released.clear()
        now = time.perf_counter()
        if self._clock0 is None:
            self._clock0, self._step0 = now, self.game.step
        target = self._step0 + int((now - self._clock0) / self.game.dt)
        lag = target - self.game.step - int(MAX_LAG / self.game.dt)
        if lag > 0:                      # too far behind: hold the clock back
            self._clock0 += lag * self.game.dt
            target -= lag
        if self.replay is not None:
            self.replay.advance_to(target)
            if self.replay.done:
                self.timer.stop()
        else:
            self.game.advance_to(target)
        self.view.render()
        # timers count their interval from the end of the callback: wait only what is left
        spent = time.perf_counter() - now
        self.timer.interval = max(1, int(1000 * (FRAME_PERIOD - spent)))

    def _close(self) -> None:
        import matplotlib.pyplot as plt
        self.timer.stop()
        self._save()
        plt.close(self.fig)

    def _on_close(self, event) -> None:
        self.timer.stop()
        self._save()

    def _save(self) -> None:
        if self.record_path and not self._saved and self.replay is None:
            Recording.of(self.game, engine=self.engine_name).save(self.record_path)
            self._saved = True
            print(f"recorded {len(self.game.events)} key events, {self.game.step} steps -> {self.record_path}")
