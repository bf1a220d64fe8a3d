"""The report a user reads: index.md, one page per scenario, plots (written atomically)."""
from .pages import write_index, write_scenario

__all__ = ["write_index", "write_scenario"]
