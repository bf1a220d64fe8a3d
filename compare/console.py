"""The console command `contact-harness` (pyproject [project.scripts]): `python -m compare` by
another name, with the same arguments, output and exit status."""
from __future__ import annotations


def main() -> int:
    """The command line (compare/cli.py) on sys.argv; the exit status is returned for sys.exit."""
    import gc

    from .cli import main as cli_main

    status = cli_main()
    gc.freeze()   # as `python -m compare`: the objects left are not walked at shutdown (compare/__main__.py)
    return status
