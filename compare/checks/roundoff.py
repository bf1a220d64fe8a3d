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

The tolerance up to each row is SAFETY times the largest position (angle) difference seen so
far, and never below FLOOR_ULPS ulps of the motion's size. An ensemble is a sample, not a bound:
over eight seeds on the built-in scenes the largest difference was at most 3.4 times the largest
of the two seeds used (point_drop; 1.0 to 3.1 elsewhere), which SAFETY covers. Where the
tolerance passes HORIZON_FRACTION of the motion's size, the rows from there on are not judged.
"""
from __future__ import annotations

import dataclasses
from collections.abc import Callable
from functools import cache, lru_cache

import numpy as np

from numba import njit

from custom_sim import Scene, simulate
from custom_sim.integrators import NEWTON_TOL, euler_step, implicit_euler_step, rk4_step
from custom_sim.model import build_model, initial_state
from scene_types.schema import Initial

INJECTED_ULPS = 2        # per component per step, relative (eps |z|): a few rounded terms in another order
INJECTION_SEEDS = (1, 2)
# Implicit Euler's Newton solve stops once its update is below NEWTON_TOL (m/s): a faithful
# implicit Euler with its own solver may land anywhere within that of custom_sim's velocity.
IMPLICIT_VELOCITY_SPREAD = NEWTON_TOL
SAFETY = 10.0
FLOOR_ULPS = 64          # a run where round-off never grows still differs by a few ulps per step
# Where round-off alone has grown to this fraction of the motion's size (the larger of the
# body's extent and the distance its centre travels), the motion has forgotten its last digits:
# a mistake could hide in what round-off does there. Rows from that divergence horizon on are
# not judged (corner_landing and stiff_contact reach it; every built-in scene never does).
HORIZON_FRACTION = 1e-3
EPS = float(np.finfo(float).eps)


@cache
def _clear_stale_kernel() -> None:
    """The kernel below inlines custom_sim's step functions, and numba checks a cached function
    against its own file only: clear its cache when this file or any custom_sim source changes
    (as custom_sim/compile_cache.py does for custom_sim's own); once per process, before the
    first kernel runs."""
    from pathlib import Path

    import custom_sim
    from custom_sim.compile_cache import clear_stale

    here = Path(__file__).resolve()
    sources = sorted(Path(custom_sim.__file__).resolve().parent.glob("*.py")) + [here]
    try:  # numba's folder for this file: __pycache__ beside it, or under NUMBA_CACHE_DIR
        cache = Path(_euler_rounded._cache._cache_path)  # type: ignore[attr-defined]  # numba types no _cache
    except Exception:  # another numba layout: its default, in-tree
        cache = here.parent / "__pycache__"
    clear_stale(cache, sources, "roundoff_numba_sources.sha256", "roundoff.*")


@dataclasses.dataclass(frozen=True)
class Envelope:
    """Round-off envelope of one scene, integrator and dt.

    position_t, angle_t (steps + 1,): the tolerance up to each row (m, rad), never decreasing;
    horizon: the first row where position_t exceeds HORIZON_FRACTION of the motion's size
    (steps + 1 when it never does): rows from there on cannot be judged, round-off alone
    could move them as much as a mistake. position, angle: the tolerance at the last row judged.
    The four measured maxima are over the rows judged."""

    position: float
    angle: float
    position_t: np.ndarray
    angle_t: np.ndarray
    horizon: int
    motion_size: float
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


def _deviation(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position (m) and angle (rad) differences per row."""
    d = a - b
    return np.hypot(d[:, 0], d[:, 1]), np.abs(d[:, 2])


@njit(cache=True, inline="always")
def _add_rounding(z, noise, i, out):
    """noise[i, j] * eps * |z_j| added to each component (relative rounding), noise[i, 3 + j] to
    each velocity (absolute: a Newton tolerance); the state into out[i]."""
    for j in range(6):
        z[j] += noise[i, j] * EPS * abs(z[j])
        if j >= 3:
            z[j] += noise[i, 3 + j]
        out[i, j] = z[j]


# One compiled kernel per step body (a scene compiles only the one it uses; the two Euler
# methods share theirs): n steps of custom_sim's own step function from z, each followed by
# _add_rounding.
@njit(cache=True)
def _euler_rounded(model, points, z, h, n, noise, out, semi):
    """Explicit Euler (semi False) or semi-implicit Euler (semi True): custom_sim's one step
    body for both."""
    counters = np.zeros(4, dtype=np.int64)
    for i in range(n):
        euler_step(model, points, z, h, 0.0, 0.0, 0.0, counters, semi)
        _add_rounding(z, noise, i, out)


@njit(cache=True)
def _implicit_euler_rounded(model, points, z, h, n, noise, out):
    counters = np.zeros(4, dtype=np.int64)
    work = np.zeros((18, 6))
    for i in range(n):
        implicit_euler_step(model, points, z, h, 0.0, 0.0, 0.0, counters, work)
        _add_rounding(z, noise, i, out)


@njit(cache=True)
def _rk4_rounded(model, points, z, h, n, noise, out):
    counters = np.zeros(4, dtype=np.int64)
    work = np.zeros((18, 6))
    for i in range(n):
        rk4_step(model, points, z, h, 0.0, 0.0, 0.0, counters, work)
        _add_rounding(z, noise, i, out)


# numba's Dispatcher is typed by its first signature only, hence the ignores on the Euler pair
_ROUNDED: dict[str, Callable[..., None]] = {
    "explicit_euler": lambda *run: _euler_rounded(*run, False),  # type: ignore[call-arg]
    "semi_implicit_euler": lambda *run: _euler_rounded(*run, True),  # type: ignore[call-arg]
    "implicit_euler": _implicit_euler_rounded, "rk4": _rk4_rounded}


def _injected_run(scene: Scene, seed: int, implicit: bool) -> np.ndarray:
    """custom_sim stepped with random per-step rounding added to each component."""
    _clear_stale_kernel()
    n = scene.steps
    rng = np.random.default_rng(seed)
    noise = np.zeros((n, 9))
    noise[:, :6] = rng.uniform(-INJECTED_ULPS, INJECTED_ULPS, (n, 6))
    if implicit:
        noise[:, 6:] = rng.uniform(-IMPLICIT_VELOCITY_SPREAD, IMPLICIT_VELOCITY_SPREAD, (n, 3))
    if scene.body.shape == "point":
        noise[:, 2] = noise[:, 5] = noise[:, 8] = 0.0
    model, points = build_model(scene)
    out = np.empty((n + 1, 6))
    z = initial_state(scene)
    out[0] = z
    _ROUNDED[scene.integrator](model, points, z, scene.dt, n, noise, out[1:])
    return out


def roundoff_envelope(scene: Scene, plain: np.ndarray | None = None) -> Envelope:
    """The envelope of `scene` as given (its integrator and dt); plain: custom_sim's states of
    it, if already run (a Case passes its own run, and keeps the envelope itself)."""
    return _cached_envelope(scene) if plain is None else _envelope(scene, plain)


@lru_cache(maxsize=16)
def _cached_envelope(scene: Scene) -> Envelope:
    return _envelope(scene, simulate(scene).states())


def _envelope(scene: Scene, plain: np.ndarray) -> Envelope:
    implicit = scene.integrator == "implicit_euler"
    n_rows = plain.shape[0]
    ens_p, ens_a = np.zeros(n_rows), np.zeros(n_rows)
    for seed in INJECTION_SEEDS:
        p, a = _deviation(_injected_run(scene, seed, implicit), plain)
        ens_p, ens_a = np.maximum(ens_p, p), np.maximum(ens_a, a)
    z0 = _initial_state(scene)
    turns = scene.body.shape != "point"
    ini_p, ini_a = np.zeros(n_rows), np.zeros(n_rows)
    for j in range(6):
        if not turns and j in (2, 5):
            continue
        for direction in (np.inf, -np.inf):
            z = z0.copy()
            z[j] = np.nextafter(z[j], direction)
            p, a = _deviation(simulate(_with_initial(scene, z)).states(), plain)
            ini_p, ini_a = np.maximum(ini_p, p), np.maximum(ini_a, a)
    size = float(np.max(np.abs(plain[:, :2])))
    floor_p = FLOOR_ULPS * float(np.spacing(max(size, 1e-3)))
    floor_a = FLOOR_ULPS * float(np.spacing(max(float(np.max(np.abs(plain[:, 2]))), 1.0)))
    # the tolerance up to each row: the largest difference seen so far, never decreasing
    position_t = np.maximum(SAFETY * np.maximum.accumulate(np.maximum(ens_p, ini_p)), floor_p)
    angle_t = (np.maximum(SAFETY * np.maximum.accumulate(np.maximum(ens_a, ini_a)), floor_a)
               if turns else np.zeros(n_rows))
    from custom_sim import mass_properties
    props = mass_properties(scene.body)
    extent = float(np.max(np.hypot(props.points[:, 0], props.points[:, 1])))
    motion = max(extent, float(np.max(np.ptp(plain[:, :2], axis=0))))
    beyond = np.flatnonzero(position_t > HORIZON_FRACTION * motion)
    horizon = int(beyond[0]) if beyond.size else n_rows
    last = max(horizon - 1, 0)
    judged = slice(0, max(horizon, 1))
    what = ("Newton's stopping tolerance" if implicit else f"{INJECTED_ULPS} ulps of rounding")
    reason = (f"round-off carried by the motion: custom_sim with {what} added to every component "
              f"at every step moved by {ens_p[judged].max():.1e} m, {ens_a[judged].max():.1e} rad; "
              f"a 1-ulp initial state by {ini_p[judged].max():.1e} m, {ini_a[judged].max():.1e} rad; "
              f"tolerance {SAFETY:g} x the largest so far (at least {FLOOR_ULPS} ulps of the motion's size)")
    if horizon < n_rows:
        reason += (f"; judged up to t = {last * scene.dt:.4g} s only: from there round-off alone moves this "
                   f"motion by more than {HORIZON_FRACTION:g} of its size {motion:.3g} m")
    return Envelope(float(position_t[last]), float(angle_t[last]), position_t, angle_t, horizon, motion,
                    float(ens_p[judged].max()), float(ens_a[judged].max()),
                    float(ini_p[judged].max()), float(ini_a[judged].max()), reason)
