"""Which integrator a step is, from how it moves the body and where it reads the force."""
from __future__ import annotations

import numpy as np

from .fit import worst
from .integrators import NAMES, POSITION_SHARE, position_residual
from .model import Law
from .probes import Probes
from .roundoff import inertias, position_bound, rate_bound

# A velocity change enters the measured position share beta only where h |v1 - v0| is this many
# times the position update's round-off (beta's uncertainty is then at most 1 / BETA_SIGNAL).
BETA_SIGNAL = 1e3
# A force of the state stepped by any consistent method differs between steps h and h/2 by O(h):
# from h/2 to h/4 the difference halves (first order) or quarters; 0.75 leaves room for the
# law's curvature over the step. A force that depends on h itself (a clamp at m v / h, a bias
# over h) changes as much or more.
CONVERGENCE = 0.75


def _rel(resid: np.ndarray, bound: np.ndarray) -> float:
    return worst(resid, bound)[1]


def rates(P: Probes) -> np.ndarray:
    return (P.Z1[:, 3:] - P.Z0[:, 3:]) / P.H[:, None]


def restart_states(P: Probes) -> tuple[np.ndarray, np.ndarray]:
    """For the pairs' dt/2 rows: (z0', h') that implicit Euler maps onto the dt row's z1."""
    Z0, Z1, H = P.Z0[0::2], P.Z1[0::2], P.H[1::2]
    a = (Z1[:, 3:] - Z0[:, 3:]) / P.H[0::2, None]
    return np.hstack([Z1[:, :3] - H[:, None] * Z1[:, 3:], Z1[:, 3:] - H[:, None] * a]), H


def position_share(Z0: np.ndarray, Z1: np.ndarray, H: np.ndarray, rounding=None) -> tuple[float | None, float]:
    """(beta, its uncertainty) from steps under a constant force (flight): q1 = q0 + h v0 + beta h
    (v1 - v0), measured on every channel whose velocity changes beyond the update's round-off
    (None: no velocity changed)."""
    if not len(Z0):
        return None, np.inf
    Hc = np.asarray(H, dtype=float)[:, None]
    num = Z1[:, :3] - Z0[:, :3] - Hc * Z0[:, 3:]
    den = Hc * (Z1[:, 3:] - Z0[:, 3:])
    bound = position_bound("explicit_euler", Z0, Z1, H, rounding)
    use = np.abs(den) > BETA_SIGNAL * bound
    if not use.any():
        return None, np.inf
    num, den, bound = num[use], den[use], bound[use]
    w = (den / bound) ** 2
    beta = float(np.sum(w * num / den) / np.sum(w))
    return beta, float(np.max(bound / np.abs(den)))


def integrator_tests(law: Law, flight: Probes, pairs: Probes | None, restart: tuple | None,
                     quarter: np.ndarray | None = None) -> dict:
    """Each integrator's largest residual over its round-off bound in the law-free tests
    (<= 1: passes), and the measurements they rest on: `parts` per integrator (its position
    update, and for the Euler steps whether the force is read at the start or the end of the
    step), `beta` (the position-update share measured in flight, with `beta_uncertainty`),
    `reads_at_start`, `reads_at_end` and `depends_on_dt` (None: no contact pair). quarter: the
    user's step from the pairs' dt rows with dt/4 (a force of the state, however stepped, changes
    the velocity change over h by O(h): the difference between h/2 and h/4 is at most
    CONVERGENCE of that between h and h/2; a force that depends on h does not converge)."""
    out, parts = {}, {}
    M = inertias(law)
    start = end = None
    if pairs is not None and len(pairs):
        a = rates(pairs)
        b = rate_bound(law, "semi_implicit_euler", pairs.Z0, pairs.Z1, pairs.H) / M
        start = _rel(a[0::2] - a[1::2], b[0::2] + b[1::2])
        if restart is not None:
            (Zr, Hr), Zr1 = restart
            Zend = pairs.Z1[0::2]
            bi = rate_bound(law, "implicit_euler", pairs.Z0, pairs.Z1, pairs.H) / M
            br = rate_bound(law, "implicit_euler", Zr, Zr1, Hr) / M + bi[0::2]
            end = _rel((Zr1[:, 3:] - Zend[:, 3:]) / Hr[:, None], br)
        converges = None
        if quarter is not None:
            Hq = 0.25 * pairs.H[0::2]
            aq = (quarter[:, 3:] - pairs.Z0[0::2, 3:]) / Hq[:, None]
            bq = rate_bound(law, "semi_implicit_euler", pairs.Z0[0::2], quarter, Hq) / M
            d1, d2 = np.abs(a[0::2] - a[1::2]), np.abs(a[1::2] - aq)
            converges = bool(np.all(d2 <= CONVERGENCE * d1 + b[1::2] + bq))
    for name in NAMES:
        share = POSITION_SHARE[name]
        mine = {}
        if len(flight):
            mine["position"] = _rel(position_residual(flight.Z0, flight.Z1, flight.H, share),
                                    position_bound(name, flight.Z0, flight.Z1, flight.H))
        if pairs is not None and len(pairs) and name != "rk4":
            in_pairs = _rel(position_residual(pairs.Z0, pairs.Z1, pairs.H, share),
                            position_bound(name, pairs.Z0, pairs.Z1, pairs.H))
            mine["position"] = max(mine.get("position", 0.0), in_pairs)
            read = end if name == "implicit_euler" else start
            if read is not None:
                mine["read"] = read
        parts[name] = mine
        out[name] = max(mine.values()) if mine else None
    beta, unc = position_share(flight.Z0, flight.Z1, flight.H) if flight is not None and len(flight) \
        else (None, np.inf)
    out["parts"] = parts
    out["beta"], out["beta_uncertainty"] = beta, unc
    out["reads_at_start"] = None if start is None else bool(start <= 1.0)
    out["reads_at_end"] = None if end is None else bool(end <= 1.0)
    out["depends_on_dt"] = None if start is None else bool(
        start > 1.0 and not (end is not None and end <= 1.0) and converges is not True)
    return out


def beta_words(beta: float | None) -> str:
    """What a measured position-update share is: a method's own, or where it lies between them."""
    if beta is None:
        return "beta not measured (no velocity changed in flight)"
    text = f"beta = {beta:.6g}"
    between = "between explicit and semi-implicit Euler, as substeps moving"
    for lo, hi, words in ((-np.inf, 0.0, "below explicit Euler's 0"),
                          (0.0, 0.5, f"{between} positions first give"),
                          (0.5, 1.0, f"{between} velocities first give"),
                          (1.0, np.inf, "above semi-implicit Euler's 1")):
        if lo < beta < hi:
            return f"{text} ({words})"
    return text


def contact_shown(law: Law, flight: Probes, pairs: Probes) -> bool:
    """Whether some pair's steps differ from free flight by more than round-off (a force acts):
    one is enough to tell the integrators apart (a law may leave the others free, as
    Hunt-Crossley does above its dissipation's speed 1 / dissipation)."""
    if pairs is None or not len(pairs):
        return False
    free = rates(flight)[0] if len(flight) else np.zeros(3)
    M = inertias(law)
    b = rate_bound(law, "semi_implicit_euler", pairs.Z0, pairs.Z1, pairs.H) / M
    return bool(np.any(np.max(np.abs(rates(pairs) - free) / np.maximum(b, np.finfo(float).tiny), axis=1) > 1.0))


def _share_matches(tests: dict, name: str) -> bool:
    return tests["parts"].get(name, {}).get("position", np.inf) <= 1.0


def decide(tests: dict) -> tuple[str | None, str, float, str]:
    """(name or None, closest, its residual, why) from integrator_tests. A method is named only
    where both its position update (beta) and where it reads the force match it; RK4 (beta 1/2,
    the force read at neither end) stays a candidate ("rk4?") for the law fit to confirm.
    `closest` (where none is named): the method whose position update (beta) is nearest, by the
    one test every method has in flight and contact alike; its residual is that test's."""
    names = [k for k in NAMES if tests.get(k) is not None]
    passing = [k for k in names if k != "rk4" and tests[k] <= 1.0]
    # nearest first in beta (the one measurement every method has), then in its largest test
    closest = min(names, key=lambda k: (tests["parts"][k].get("position", np.inf), tests[k]), default="rk4")
    near = tests["parts"].get(closest, {}).get("position", tests.get(closest))
    if len(passing) == 1:
        return passing[0], passing[0], tests[passing[0]], "law-free tests"
    if len(passing) > 1:
        return None, closest, tests[closest], f"not told apart: {', '.join(passing)} all pass (no force acts)"
    if _share_matches(tests, "rk4") and not tests.get("reads_at_start") and not tests.get("reads_at_end"):
        return "rk4?", "rk4", tests["rk4"], "no Euler step; RK4 to be confirmed by the law fit"
    beta = tests.get("beta")
    why = "none: " + beta_words(beta)
    share = next((k for k in ("explicit_euler", "semi_implicit_euler") if _share_matches(tests, k)), None)
    if share is not None:
        why = f"none: beta = {POSITION_SHARE[share]:g} ({share}'s)"
    if tests.get("depends_on_dt"):
        why += ", and the force depends on the step size (dt and dt/2 read different forces at one state)"
    return None, closest, near, why
