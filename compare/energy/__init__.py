"""The work-energy balance of a run (docs/energy-balance.md): energy, dissipated work, residual."""
from .balance import Balance, balance, metrics_block

__all__ = ["Balance", "balance", "metrics_block"]
