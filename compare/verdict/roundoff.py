"""How far round-off alone moves a scene's trajectory: the envelope the `identical` check allows.

Two faithful implementations of the same integrator at the same dt differ only in rounding:
each step, each state component may come out a few ulps apart (other order of the sums,
m g against g / (1/m), a library tanh against a series). Those per-step differences are then
carried by the motion: kept as they are in flight, damped while friction sticks, amplified at
a touchdown (the step at which a corner first touches can move, and the compression law's
force jumps by c |v_y| there) and by tumbling, whose sensitivity grows with every impact.

The envelope is measured on custom_sim itself, the way the motion carries it:

1. ensemble: custom_sim stepped with INJECTED_ULPS of random rounding added to every
   component at every step (INJECTION_SEEDS seeds), against the plain run;
2. initial state: each component of the initial state moved by one ulp (both signs), against
   the plain run (this alone reaches the touchdown switch and tumbling amplification).

The tolerance is SAFETY times the largest position (angle) difference seen, and never below
FLOOR_ULPS ulps of the motion's size: an ensemble is a sample, not a bound (seeds spread by
a factor of about 2 here), and SAFETY covers the spread between a sample's largest
difference and the unseen ones.
"""
from __future__ import annotations

import dataclasses
from functools import lru_cache

import numpy as np

from custom_sim import Scene, Stepper, simulate
from custom_sim.integrators import NEWTON_TOL
from custom_sim.scene import Initial

INJECTED_ULPS = 2        # per component per step: a sum of a few rounded terms in another order
INJECTION_SEEDS = (1, 2)
# Implicit Euler's Newton solve stops once its update is below NEWTON_TOL (m/s): a faithful
# implicit Euler with its own solver may land anywhere within that of custom_sim's velocity.
IMPLICIT_VELOCITY_SPREAD = NEWTON_TOL
SAFETY = 10.0
FLOOR_ULPS = 64          # a run where round-off never grows still differs by a few ulps per step
MAX_INJECTED_STEPS = 100_000   # longer runs: every k-th step, k ulps' random walk sqrt(k) each


@dataclasses.dataclass(frozen=True)
class Envelope:
    """Round-off envelope of one scene, integrator and dt: position (m), angle (rad)."""

    position: float
    angle: float
    ensemble_position: float     # largest difference measured by per-step injection
    ensemble_angle: float
    initial_position: float      # largest difference from a 1-ulp initial state
    initial_angle: float
    reason: str


def _with_initial(scene: Scene, z: np.ndarray) -> Scene:
    return dataclasses.replace(scene, initial=Initial((z[0], z[1]), (z[3], z[4]), z[2], z[5]))


def _initial_state(scene: Scene) -> np.ndarray:
    i = scene.initial
    return np.array([*i.position, i.angle, *i.velocity, i.angular_velocity], dtype=float)


def _deviation(a: np.ndarray, b: np.ndarray) -> tuple[float, float]:
    d = a - b
    return float(np.max(np.hypot(d[:, 0], d[:, 1]))), float(np.max(np.abs(d[:, 2])))


def _injected_run(scene: Scene, seed: int, implicit: bool) -> np.ndarray:
    """custom_sim stepped with random per-step rounding added to each component."""
    n = scene.steps
    stride = max(1, -(-n // MAX_INJECTED_STEPS))
    ulps = INJECTED_ULPS * np.sqrt(stride)
    rng = np.random.default_rng(seed)
    stepper = Stepper(scene)
    out = np.empty((n + 1, 6))
    out[0] = stepper.state
    turns = scene.body.shape != "point"
    done = 0
    while done < n:
        k = min(stride, n - done)
        z = stepper.advance(k)
        kick = rng.uniform(-ulps, ulps, 6) * np.spacing(np.abs(z))
        if implicit:
            kick[3:] += rng.uniform(-1.0, 1.0, 3) * IMPLICIT_VELOCITY_SPREAD
        if not turns:
            kick[2] = kick[5] = 0.0
        z += kick
        done += k
        out[done] = z
    if stride > 1:  # rows between injections: the plain steps, recorded only at the injections
        rows = np.arange(0, n + 1, stride)
        rows = np.append(rows, n) if rows[-1] != n else rows
        return out[rows], rows
    return out, None


@lru_cache(maxsize=64)
def roundoff_envelope(scene: Scene) -> Envelope:
    """The envelope of `scene` as given (its integrator and dt)."""
    plain = simulate(scene).states()
    implicit = scene.integrator == "implicit_euler"
    ens_p = ens_a = 0.0
    for seed in INJECTION_SEEDS:
        run, rows = _injected_run(scene, seed, implicit)
        p, a = _deviation(run, plain if rows is None else plain[rows])
        ens_p, ens_a = max(ens_p, p), max(ens_a, a)
    z0 = _initial_state(scene)
    turns = scene.body.shape != "point"
    ini_p = ini_a = 0.0
    for j in range(6):
        if not turns and j in (2, 5):
            continue
        for direction in (np.inf, -np.inf):
            z = z0.copy()
            z[j] = np.nextafter(z[j], direction)
            p, a = _deviation(simulate(_with_initial(scene, z)).states(), plain)
            ini_p, ini_a = max(ini_p, p), max(ini_a, a)
    size = float(np.max(np.abs(plain[:, :2])))
    floor_p = FLOOR_ULPS * float(np.spacing(max(size, 1e-3)))
    floor_a = FLOOR_ULPS * float(np.spacing(max(float(np.max(np.abs(plain[:, 2]))), 1.0)))
    position = max(SAFETY * max(ens_p, ini_p), floor_p)
    angle = max(SAFETY * max(ens_a, ini_a), floor_a) if turns else 0.0
    what = ("Newton's stopping tolerance" if implicit else f"{INJECTED_ULPS} ulps of rounding")
    reason = (f"round-off carried by the motion: custom_sim with {what} added to every component "
              f"at every step moved by {ens_p:.1e} m, {ens_a:.1e} rad; a 1-ulp initial state by "
              f"{ini_p:.1e} m, {ini_a:.1e} rad; tolerance {SAFETY:g} x the largest "
              f"(at least {FLOOR_ULPS} ulps of the motion's size)")
    return Envelope(position, angle, ens_p, ens_a, ini_p, ini_a, reason)
