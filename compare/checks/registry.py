"""Every check, in the order their rows appear in metrics.json: one line each (the Check
protocol, check.py). `run` walks them all; `validate` those needing neither MuJoCo nor the
converged reference (compare/run/scenario.py judge)."""
from __future__ import annotations

from .check import Check
from .ground_check import Ground
from .units import Contact, Dynamics, Energy, Identical, Native, Reference, Step

CHECKS: dict[str, Check] = {
    "identical": Identical(),    # a user's run against custom_sim's, same integrator and dt
    "step": Step(),              # each step against one independent step
    "dynamics": Dynamics(),      # against MuJoCo integrating the same contact law
    "contact": Contact(),        # against MuJoCo's own contact, friction off
    "reference": Reference(),    # against the converged reference (shown)
    "native": Native(),          # against MuJoCo's own contact, every effect on (shown)
    "energy": Energy(),          # the simulator's own energy column against its states
    "ground": Ground(),          # no body falls through the ground
}


def without(*needs: str) -> dict[str, Check]:
    """The checks that need none of `needs` ("mujoco", "reference"), in order."""
    return {name: c for name, c in CHECKS.items() if not (c.needs & set(needs))}
