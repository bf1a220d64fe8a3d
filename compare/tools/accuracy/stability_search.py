"""The largest stable step of each integrator, found by bisection, beside the linear theory.

    custom_limit(scene, integrator, scale) / mujoco_limit(...) -> StabilityLimit (h_max in s)
    largest_stable_step(is_stable, h_start)    bisection on log h, then a scan below the threshold
    theory(scene, integrator)                  custom_sim/stability.py's limits, by what sets them

A run is stable when it does not diverge (for MuJoCo: no reset), does not chatter
(custom_sim/chatter.py; MuJoCo's runs are not watched) and its energy at quiet samples does not
rise above E(0) by more than ENERGY_GROWTH_LIMIT of the motion's largest kinetic energy (J).
Why each criterion, and how the bisection copes with interleaved stable and unstable steps:
docs/stability.md#how-the-search-measures-a-stable-step.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from custom_sim import (Scene, SimulationChattered, SimulationDiverged, mass_properties, simulate,
                        stable_step)
from scene_types.schema import Body

# far above a stable integrator's drift at quiet samples (< 1 % per bounce), far below what an
# unstable one reaches within a run (docs/stability.md#how-the-search-measures-a-stable-step)
ENERGY_GROWTH_LIMIT = 0.10
QUIET_CONTACT_SHARE = 0.01  # energy is read where the contact holds less than this share of it

BISECTION_RATIO = 1.01      # bracket ends within 1 %
SCAN_RATIO = 1.02           # the scan below a threshold: steps 2 % apart ...
SCAN_POINTS = 20            # ... down to 1.02^-20 = 0.67 of it
MAX_STEP = 0.05             # s: beyond this a 1-3 s scene has too few steps to mean anything
MIN_STEP = 1e-7             # s


@dataclass(frozen=True)
class StabilityLimit:
    """h_max (s): the largest stable step found; runs: how many simulations it took."""

    simulator: str
    integrator: str
    h_max: float
    capped: bool = False    # stable up to MAX_STEP: h_max is a lower bound
    below: bool = False     # unstable even at MIN_STEP: h_max is an upper bound
    runs: int = 0
    reason: str = ""        # why the first unstable step above h_max failed
    first_threshold: float = math.nan  # the first bisection's threshold, before the scans (s)

    def text(self) -> str:
        if self.capped:
            return f">= {self.h_max:.3g}"
        if self.below:
            return f"< {self.h_max:.3g}"
        return f"{self.h_max:.3g}"


def energy_scale(reference_states: np.ndarray, scene: Scene) -> float:
    """The largest kinetic energy (J) along a reference motion (states (T, 6))."""
    props = mass_properties(scene.body)
    v2 = reference_states[:, 3] ** 2 + reference_states[:, 4] ** 2
    ke = 0.5 * props.mass * v2 + 0.5 * props.inertia * reference_states[:, 5] ** 2
    return float(ke.max())


def energy_verdict(energy: np.ndarray, contact_energy: np.ndarray, scale: float) -> tuple[bool, str]:
    """(stable, reason) from energies (J) along a run: criterion 3 of docs/stability.md, at quiet samples."""
    if not np.all(np.isfinite(energy)):
        return False, "non-finite energy"
    quiet = contact_energy <= QUIET_CONTACT_SHARE * scale
    quiet[0] = True
    growth = float(np.max(energy[quiet]) - energy[0])
    if growth > ENERGY_GROWTH_LIMIT * scale:
        return False, f"energy rose by {growth:.3g} J (> {ENERGY_GROWTH_LIMIT:.0%} of {scale:.3g} J)"
    return True, ""


def custom_stable(scene: Scene, integrator: str, h: float, scale: float) -> tuple[bool, str]:
    """Is custom_sim's `integrator` stable on `scene` with step h (s)?"""
    try:
        traj = simulate(dataclasses.replace(scene, integrator=integrator, dt=h))
    except SimulationDiverged as exc:
        return False, failure_reason(exc)
    return energy_verdict(traj.energy, traj.energy_contact, scale)


def failure_reason(exc: SimulationDiverged) -> str:
    """The criterion a stopped run failed, in a few words (for the tables)."""
    if isinstance(exc, SimulationChattered):
        return f"chatter: point {exc.point} {exc.quantity} at step {exc.step}"
    return f"diverged at step {exc.step}"


def mujoco_stable(scene: Scene, integrator: str, h: float, scale: float) -> tuple[bool, str]:
    """Is MuJoCo's `integrator` stable on the scene's twin with step h (s)?

    MuJoCo does not stop on a blow-up: when an acceleration goes bad it warns and resets the
    state (mjWARN_BADQACC). So besides non-finite values a reset counts as a divergence: the
    twin reports it in meta (`warnings`), and failing that it shows as a jump of the state
    back to the model's rest pose, which no finite force can produce in one step."""
    from mujoco_models import MujocoDiverged, simulate_mujoco

    try:
        traj = simulate_mujoco(scene, integrator=integrator, dt=h)
    except MujocoDiverged:
        return False, "MuJoCo reset a bad acceleration"
    except (SimulationDiverged, FloatingPointError, OverflowError) as exc:
        return False, f"diverged ({type(exc).__name__})"
    warnings = traj.meta.get("warnings") or {}
    bad = {k: v for k, v in warnings.items() if v and k.lower() not in ("contactfull", "cnstrfull")}
    if bad:
        return False, "MuJoCo warned: " + ", ".join(f"{k} x{v}" for k, v in bad.items())
    states = traj.states()
    if not np.all(np.isfinite(states)):
        return False, "non-finite state"
    jump = np.max(np.abs(np.diff(states[:, :2], axis=0)), initial=0.0)
    if jump > RESET_JUMP_SPEED * h:
        return False, f"state jumped {jump:.3g} m in one step (reset)"
    return energy_verdict(traj.energy, traj.energy_contact, scale)


# No motion of these scenes comes near 1e3 m/s: a larger jump in one step is a reset.
RESET_JUMP_SPEED = 1e3      # m/s


def largest_stable_step(is_stable, h_start: float, max_step: float = MAX_STEP,
                        min_step: float = MIN_STEP, ratio: float = BISECTION_RATIO,
                        simulator: str = "", integrator: str = "",
                        scan_points: int = SCAN_POINTS) -> StabilityLimit:
    """Largest h with is_stable(h) -> (bool, reason) true at h and at every scan step below it.

    Bisection on log h finds *a* threshold; near the limit a bouncing body spends only a few
    steps in each contact, and stable and unstable steps can interleave. So each threshold is
    followed by a scan of SCAN_POINTS steps SCAN_RATIO apart below it: an unstable one becomes
    the new upper end and the bisection resumes below it, until the scan is clean."""
    runs = 0
    first = math.nan

    def check(h):
        nonlocal runs
        runs += 1
        return is_stable(h)

    def result(h, why="", **flags):
        return StabilityLimit(simulator, integrator, h, runs=runs, reason=why,
                              first_threshold=h if math.isnan(first) else first, **flags)

    ok, reason = check(h_start)
    if ok:
        lo, hi, why = h_start, None, ""
        while lo < max_step:
            h = min(2.0 * lo, max_step)
            ok, reason = check(h)
            if not ok:
                hi, why = h, reason
                break
            lo = h
        if hi is None:
            return result(lo, capped=True)
    else:
        hi, why, lo = h_start, reason, None
    while True:
        while lo is None:  # walk down to a stable step
            if hi <= min_step:
                return result(hi, why, below=True)
            h = max(0.5 * hi, min_step)
            ok, reason = check(h)
            if ok:
                lo = h
            else:
                hi, why = h, reason
        while hi / lo > ratio:
            mid = math.sqrt(lo * hi)
            ok, reason = check(mid)
            if ok:
                lo = mid
            else:
                hi, why = mid, reason
        if math.isnan(first):
            first = lo
        clean = True
        for j in range(1, scan_points + 1):
            h = lo / SCAN_RATIO ** j
            ok, reason = check(h)
            if not ok:
                hi, why, lo, clean = h, reason, None, False
                break
        if clean:
            return result(lo, why)


def custom_limit(scene: Scene, integrator: str, scale: float, **bisection) -> StabilityLimit:
    return largest_stable_step(lambda h: custom_stable(scene, integrator, h, scale), scene.dt,
                               simulator="custom", integrator=integrator, **bisection)


def mujoco_limit(scene: Scene, integrator: str, scale: float, **bisection) -> StabilityLimit:
    return largest_stable_step(lambda h: mujoco_stable(scene, integrator, h, scale), scene.dt,
                               simulator="mujoco", integrator=integrator, **bisection)


def theory(scene: Scene, integrator: str) -> dict:
    """custom_sim/stability.py's theory, split by what sets it (s; inf: no limit):

    spring        the contact modes (the stiffest of the body on one or two lowest points)
    spring_point  the same as if the whole mass sat at the contact point
    friction      the tanh law's stiff rate at the largest load a point carries
    combined      custom_sim.stable_step: the smallest of the scene's effects' limits
    plus every effect of custom_sim.stability.limits (contact, friction, rolling_friction)
    """
    from custom_sim.stability import limits

    frictionless = dataclasses.replace(
        scene, effects=tuple(e for e in scene.effects if e not in ("friction", "rolling_friction")))
    as_point = dataclasses.replace(frictionless, body=Body(shape="point", mass=scene.body.mass,
                                                           contact_height=0.0))
    by_effect = limits(scene, integrator)
    return {"spring": by_effect.get("contact", math.inf),
            "spring_point": stable_step(as_point, integrator),
            "friction": by_effect.get("friction", math.inf),
            "combined": stable_step(scene, integrator), **by_effect}
