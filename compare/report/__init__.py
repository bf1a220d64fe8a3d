"""The report a user reads: index.md, one page per scenario, plots (written atomically)."""
from .frames import prebuild as prebuild_figures
from .pages import write_index, write_scenario, write_skipped

__all__ = ["prebuild_figures", "write_index", "write_scenario", "write_skipped"]
