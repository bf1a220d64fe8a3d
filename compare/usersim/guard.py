"""The boundary around a user's code: it may fail, but it cannot end, steer or reconfigure the harness.

Inside `user_code(where)`:
- sys.exit, os._exit and a KeyboardInterrupt the code raises become EndedProcess (bad input,
  exit 2) naming `where`: the function and the step;
- numpy's error state, matplotlib's settings and the working folder are put back on leaving,
  so a module that calls np.seterr(all="raise"), sets text.usetex or os.chdir changes only
  what its own code sees.
"""
from __future__ import annotations

import contextlib
import os
import sys

import numpy as np

from .errors import UserCodeError


class EndedProcess(UserCodeError):
    """The user's code tried to end the process (sys.exit, os._exit) or raised KeyboardInterrupt."""


class _ExitCalled(BaseException):
    """Raised in place of os._exit(code) while user code runs."""

    def __init__(self, code):
        super().__init__(code)
        self.code = code


# Set by the harness's own SIGINT handler (mark_interrupted): a KeyboardInterrupt then comes
# from the terminal, not from the user's code.
INTERRUPTED = False


def mark_interrupted(signum=None, frame=None):
    """SIGINT handler: remember that the terminal asked to stop, then stop."""
    global INTERRUPTED
    INTERRUPTED = True
    raise KeyboardInterrupt


def _text(where) -> str:
    return where() if callable(where) else where


def _no_exit(code=0):
    raise _ExitCalled(code)


@contextlib.contextmanager
def user_code(where):
    """Run the enclosed user code; `where` (a string, or a function giving one when needed)
    names it: "my_sim.py:step at step 12", "importing my_sim.py"."""
    errors = np.geterr()
    folder = os.getcwd()
    mpl = sys.modules.get("matplotlib")
    rc = dict(mpl.rcParams) if mpl is not None else None
    real_exit = os._exit
    os._exit = _no_exit
    try:
        yield
    except KeyboardInterrupt:
        if INTERRUPTED:  # Ctrl-C at the terminal, not the user's code: the harness stops
            raise
        raise EndedProcess(f"{_text(where)} raised KeyboardInterrupt (expected it to return a state; "
                           "to stop a run, press Ctrl-C: the harness stops itself)") from None
    except SystemExit as exc:
        raise EndedProcess(f"{_text(where)} called sys.exit({'' if exc.code is None else repr(exc.code)}) "
                           "(expected it to return; the harness decides when the run ends)") from None
    except _ExitCalled as exc:
        raise EndedProcess(f"{_text(where)} called os._exit({exc.code!r}) "
                           "(expected it to return; the harness decides when the run ends)") from None
    finally:
        os._exit = real_exit
        np.seterr(**errors)
        with contextlib.suppress(OSError):
            os.chdir(folder)
        if rc is not None or "matplotlib" in sys.modules:
            _restore_matplotlib(rc)


def _restore_matplotlib(rc: dict | None) -> None:
    import matplotlib
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if rc is None:
            matplotlib.rcdefaults()
        else:
            matplotlib.rcParams.update(rc)
