"""The command line: `python -m compare <command>`; each command lives in its own module.

A command module has a one-line docstring (the help), `add_arguments(parser)` and
`main(args) -> int` (the exit status: 0 ok, 1 outside tolerance, 2 bad input). A command
reports bad input by raising SceneError or BadInput: `main` below turns either into one line
on stderr and exit status 2, before anything is written. Heavy imports (mujoco, matplotlib)
stay inside a command's `main` so that `--help` and `list` start fast.
"""
from __future__ import annotations

import argparse
import importlib
import os
import sys
from pathlib import Path

from scene_types import BadInput, SceneError

COMMANDS = {
    "list": "compare.commands.list_scenes",
    "run": "compare.commands.run",
    "mjcf": "compare.commands.mjcf",
    "scene": "compare.commands.scene",
    "sweep": "compare.commands.sweep",
    "bench": "compare.commands.bench",
    "play": "compare.commands.play",
    "calibrate": "compare.commands.calibrate",
    "solref": "compare.commands.solref",
    "attribute": "compare.commands.attribute",
    "study": "compare.commands.study",
    "identify": "compare.commands.identify",
}

EXIT_OK, EXIT_TOLERANCE, EXIT_BAD_INPUT = 0, 1, 2
EXIT_INTERRUPTED = 130   # Ctrl-C, as a shell reports a process stopped by SIGINT


def output_folder(out: str) -> Path:
    """The --out folder: a folder or a path still free, never an existing file, nor a path
    under one (`somefile.txt/sub`), checked on every existing ancestor before anything is
    written; the nearest existing one must be a folder this process can write into."""
    path = Path(out)
    if path.exists() and not path.is_dir():
        raise BadInput(f"{path}: --out: is a file (expected a folder)")
    # Path.exists() is False under a file (NotADirectoryError), so walk up to what exists
    for ancestor in [path, *path.parents]:
        try:
            ancestor.stat()
        except FileNotFoundError:
            continue
        except NotADirectoryError:   # a file further up: keep walking to find it
            continue
        except OSError as exc:
            raise BadInput(f"{path}: --out: {ancestor} cannot be read ({exc.strerror or exc}); "
                           "expected a folder or a path that can be created") from None
        if not ancestor.is_dir():
            raise BadInput(f"{path}: --out: {ancestor} is a file, so no folder can be made under it "
                           "(expected a folder or a path that can be created)")
        if not os.access(ancestor, os.W_OK | os.X_OK):
            raise BadInput(f"{path}: --out: {ancestor} is a folder this user cannot write into "
                           "(expected a writable folder or a path that can be created)")
        break
    return path


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="python -m compare",
        description="Compare a hand-written 2D contact simulator with its MuJoCo twin.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, module_name in COMMANDS.items():
        try:
            module = importlib.import_module(module_name)
        except ModuleNotFoundError as exc:
            if exc.name != module_name:
                raise
            continue  # a command not built yet
        summary = (module.__doc__ or "").strip().splitlines()[0]
        p = sub.add_parser(name, help=summary, description=module.__doc__,
                           formatter_class=argparse.RawDescriptionHelpFormatter)
        module.add_arguments(p)
        p.set_defaults(_main=module.main)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args._main(args)
    except KeyboardInterrupt:
        print(f"interrupted: python -m compare {args.command} stopped (Ctrl-C)", file=sys.stderr)
        return EXIT_INTERRUPTED
    except (SceneError, BadInput) as exc:
        details = getattr(exc, "details", "")  # a user's simulator raised: its own frames, once
        if details:
            print(details, file=sys.stderr)
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT


if __name__ == "__main__":
    sys.exit(main())
