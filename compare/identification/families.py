"""The candidate contact-law families, written here: each a closed form with its parameters."""
from __future__ import annotations

from dataclasses import dataclass
from collections.abc import Callable

import numpy as np


@dataclass(frozen=True)
class Family:
    """One closed form: `params` its parameters (in the [contact] table's names), `force` the
    formula: force(inputs..., params tuple), vectorised over numpy arrays."""

    effect: str            # "normal" | "friction" | "rolling"
    name: str
    params: tuple[str, ...]
    force: Callable


def _compression(d, vn, p):
    k, c = p
    return k * d + c * np.maximum(0.0, -vn)


def _linear(d, vn, p):
    k, c = p
    return np.maximum(0.0, k * d - c * vn)


def _unclamped(d, vn, p):
    k, c = p
    return k * d - c * vn


def _hunt_crossley(d, vn, p):
    k, dissipation = p
    return np.maximum(0.0, k * d * (1.0 - dissipation * vn))


def _tanh(fn, v, p):
    mu, alpha = p
    return -mu * fn * np.tanh(alpha * v)


def _ramp(fn, v, p):
    mu, alpha = p
    return -mu * fn * np.clip(alpha * v, -1.0, 1.0)


def _smooth_coulomb(fn, v, p):
    mu, alpha = p
    return -mu * fn * v / np.sqrt(v * v + 1.0 / (alpha * alpha))


def _sign(fn, v, p):
    (mu,) = p
    return -mu * fn * np.sign(v)


def _no_force(fn, v, p):
    return np.zeros(np.broadcast(fn, v).shape)


def _roll_tanh(fn, om, p):
    mu_roll, sharpness = p
    return -mu_roll * fn * np.tanh(sharpness * om)


def _roll_sign(fn, om, p):
    (mu_roll,) = p
    return -mu_roll * fn * np.sign(om)


NORMAL = (
    Family("normal", "compression", ("k", "c"), _compression),
    Family("normal", "linear", ("k", "c"), _linear),
    Family("normal", "unclamped", ("k", "c"), _unclamped),
    Family("normal", "hunt_crossley", ("k", "dissipation"), _hunt_crossley),
)
FRICTION = (
    Family("friction", "tanh", ("mu", "alpha"), _tanh),
    Family("friction", "ramp", ("mu", "alpha"), _ramp),
    Family("friction", "smooth_coulomb", ("mu", "alpha"), _smooth_coulomb),
    Family("friction", "sign", ("mu",), _sign),
    Family("friction", "none", (), _no_force),
)
ROLLING = (
    Family("rolling", "tanh", ("mu_roll", "roll_sharpness"), _roll_tanh),
    Family("rolling", "sign", ("mu_roll",), _roll_sign),
    Family("rolling", "none", (), _no_force),
)
FAMILIES = {"normal": NORMAL, "friction": FRICTION, "rolling": ROLLING}
BY_NAME = {(f.effect, f.name): f for fams in FAMILIES.values() for f in fams}

# The scene's [contact] field naming each effect's family.
LAW_FIELD = {"normal": "damping_law", "friction": "friction_law", "rolling": "roll_law"}


def family(effect: str, name: str) -> Family:
    return BY_NAME[(effect, name)]


def scene_family(scene, effect: str) -> tuple[Family, tuple[float, ...]]:
    """The family the scene names for `effect` and its parameters (a tuple in Family.params order)."""
    ct = scene.contact
    fam = family(effect, getattr(ct, LAW_FIELD[effect]))
    return fam, tuple(float(getattr(ct, p)) for p in fam.params)
