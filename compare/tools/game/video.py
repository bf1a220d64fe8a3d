"""A replay rendered to a video file (.mp4 through imageio-ffmpeg, .gif through Pillow), no screen.

Frame i shows the game at physics step i * steps_per_frame (steps_per_frame = 1 / (fps dt)),
so the video runs in real time; the last frame is held for a second.
"""
from __future__ import annotations

from pathlib import Path

from .recording import Replay
from .view import offscreen_view

FORMATS = (".mp4", ".gif")
DEFAULT_FPS = {".mp4": 50.0, ".gif": 25.0}   # GIF delays are in 1/100 s; 25 fps keeps files small
HOLD_LAST = 1.0                               # s the final frame stays on screen


GAME_EXTRA = "pip install -e '.[game]'"   # what installs the video writer


def require_writer(out: str | Path) -> None:
    """Bad input, one line, when the writer `out` needs is not installed: imageio for both
    formats, imageio-ffmpeg (its ffmpeg) for .mp4."""
    import importlib.util

    needed = ["imageio"] + (["imageio_ffmpeg"] if Path(out).suffix.lower() == ".mp4" else [])
    missing = [name.replace("_", "-") for name in needed if importlib.util.find_spec(name) is None]
    if missing:
        from scene_types import BadInput
        raise BadInput(f"play --video needs {' and '.join(missing)}: {GAME_EXTRA}")


def render_video(replay: Replay, out: str | Path, fps: float | None = None) -> int:
    """Play `replay` to its end into the video `out`; returns the number of frames written."""
    import imageio.v2 as imageio

    out = Path(out)
    suffix = out.suffix.lower()
    if suffix not in FORMATS:
        raise ValueError(f"{out}: unknown video format {suffix!r} (expected one of: {', '.join(FORMATS)})")
    fps = fps or DEFAULT_FPS[suffix]
    game = replay.game
    steps_per_frame = max(1, int(round(1.0 / (fps * game.dt))))
    fps = 1.0 / (steps_per_frame * game.dt)      # exactly real time
    view = offscreen_view(game)
    if suffix == ".mp4":
        writer = imageio.get_writer(out, fps=fps, codec="libx264", quality=7,
                                    pixelformat="yuv420p", macro_block_size=16)
    else:
        writer = imageio.get_writer(out, mode="I", duration=1000.0 / fps, loop=0)
    # ffmpeg takes RGBA as it is; Pillow would turn alpha into GIF transparency: drop it
    pixels = view.rgba if suffix == ".mp4" else (lambda: view.rgba()[..., :3])
    frames = 0
    with writer:
        while True:
            replay.advance_to(frames * steps_per_frame)
            view.render()
            writer.append_data(pixels())
            frames += 1
            if replay.done:
                break
        last = pixels()
        for _ in range(int(HOLD_LAST * fps)):
            writer.append_data(last)
            frames += 1
    return frames
