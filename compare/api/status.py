"""A scenario's status and the exit status of a whole judgement: compare/checks/status.py's,
named here for the API."""
from __future__ import annotations

from ..checks.status import Status, exit_status

__all__ = ["Status", "exit_status"]
