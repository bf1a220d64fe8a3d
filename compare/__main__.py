"""`python -m compare`: see compare/cli.py."""
import gc
import sys

from .cli import main

status = main()
# Python's shutdown walks every object left (a run holds some 200,000: trajectories, MuJoCo,
# numba, matplotlib) in a last collection, 0.4 s of a run; frozen, they are left to the OS.
# atexit handlers and finalizers still run.
gc.freeze()
sys.exit(status)
