"""One module per command of `python -m compare` (see compare/cli.py); tools/ holds the developer
tools, `python -m compare tools TOOL`."""
