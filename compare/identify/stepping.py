"""Which integrator a step is, from how it moves the body and where it reads the force."""
from __future__ import annotations

import numpy as np

from .fit import worst
from .integrators import NAMES, POSITION_SHARE, position_residual
from .model import Law
from .probes import Probes
from .roundoff import inertias, position_bound, rate_bound


def _rel(resid: np.ndarray, bound: np.ndarray) -> float:
    return worst(resid, bound)[1]


def rates(P: Probes) -> np.ndarray:
    return (P.Z1[:, 3:] - P.Z0[:, 3:]) / P.H[:, None]


def restart_states(P: Probes) -> tuple[np.ndarray, np.ndarray]:
    """For the pairs' dt/2 rows: (z0', h') that implicit Euler maps onto the dt row's z1."""
    Z0, Z1, H = P.Z0[0::2], P.Z1[0::2], P.H[1::2]
    a = (Z1[:, 3:] - Z0[:, 3:]) / P.H[0::2, None]
    return np.hstack([Z1[:, :3] - H[:, None] * Z1[:, 3:], Z1[:, 3:] - H[:, None] * a]), H


def integrator_tests(law: Law, flight: Probes, pairs: Probes | None, restart: tuple | None) -> dict:
    """Each integrator's largest residual over its round-off bound in the law-free tests
    (<= 1: passes); `pairs_in_contact`: whether the contact pairs showed a force at all."""
    out = {}
    for name in NAMES:
        tests = []
        share = POSITION_SHARE[name]
        if len(flight):
            tests.append(_rel(position_residual(flight.Z0, flight.Z1, flight.H, share),
                              position_bound(name, flight.Z0, flight.Z1, flight.H)))
        if pairs is not None and len(pairs) and name != "rk4":
            tests.append(_rel(position_residual(pairs.Z0, pairs.Z1, pairs.H, share),
                              position_bound(name, pairs.Z0, pairs.Z1, pairs.H)))
            M = inertias(law)
            b = rate_bound(law, name, pairs.Z0, pairs.Z1, pairs.H) / M
            a = rates(pairs)
            if name == "implicit_euler" and restart is not None:
                (Zr, Hr), Zr1 = restart
                Zend = pairs.Z1[0::2]
                br = rate_bound(law, name, Zr, Zr1, Hr) / M + b[0::2]
                tests.append(_rel((Zr1[:, 3:] - Zend[:, 3:]) / Hr[:, None], br))
            elif name != "implicit_euler":
                tests.append(_rel(a[0::2] - a[1::2], b[0::2] + b[1::2]))
        out[name] = max(tests) if tests else None
    return out


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


def decide(tests: dict) -> tuple[str | None, str, float, str]:
    """(name or None, closest, its residual, why) from integrator_tests. The Euler steps are
    named on their tests; RK4 stays a candidate ("rk4?") for the law fit to confirm."""
    euler = {k: v for k, v in tests.items() if k != "rk4" and v is not None}
    passing = [k for k, v in euler.items() if v <= 1.0]
    closest = min((k for k, v in tests.items() if v is not None), key=lambda k: tests[k], default="rk4")
    if len(passing) == 1:
        return passing[0], passing[0], euler[passing[0]], "law-free tests"
    if len(passing) > 1:
        return None, closest, tests[closest], f"not told apart: {', '.join(passing)} all pass (no force acts)"
    rk4 = tests.get("rk4")
    if rk4 is None or rk4 <= 1.0:
        return "rk4?", "rk4", rk4 or 0.0, "no Euler step; RK4 to be confirmed by the law fit"
    return None, closest, tests[closest], "none of the four integrators' tests passes"
