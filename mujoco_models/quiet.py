"""MuJoCo's warnings counted, not printed: installed by the first twin built, not on import.

Every run here reads its warnings from mjData.warning (a bad acceleration, ...). MuJoCo's
default handler would also print each one and write MUJOCO_LOG.TXT into the user's working
folder. The handler is process-wide, so it is set when a twin is first built (importing
mujoco_models changes nothing), and only where nobody else has set one.
"""
from __future__ import annotations

import mujoco


def _counted_only(message: str) -> None:
    """A warning MuJoCo raised: already counted in mjData.warning, where every run reads it."""


def count_warnings_quietly() -> None:
    """Install _counted_only unless a handler of the program's own is in place."""
    if mujoco.get_mju_user_warning() is None:
        mujoco.set_mju_user_warning(_counted_only)
