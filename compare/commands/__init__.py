"""One module per command of `python -m compare` (see compare/cli.py)."""
