"""The contact settings of one scene's twin: what every <pair> carries, plus the option impratio.

    read_model(model)             the settings a compiled MjModel holds (pair_* arrays, opt.impratio)
    write_model(model, s)         set them on a compiled model (a copy per finite-difference column)
    write_spec(spec, s)           set them on the MjSpec (the calibrated MJCF a user takes)
    calibrated(base, params, v)   the base mapping's settings with fitted gains and values applied

All pairs of a twin are the ground against one contact geom of the body, so they carry the
same settings; read_model checks that and returns pair 0's.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class ContactSettings:
    """solref (2), solimp (5), solreffriction (2; 0 0 = use solref), friction (5: slide, slide,
    torsion, roll, roll) of every pair, and the option impratio."""

    solref: tuple[float, ...]
    solimp: tuple[float, ...]
    solreffriction: tuple[float, ...]
    friction: tuple[float, ...]
    impratio: float

    def field(self, name: str) -> tuple[float, ...]:
        return (self.impratio,) if name == "impratio" else getattr(self, name)

    def as_dict(self) -> dict:
        return {"solref": list(self.solref), "solimp": list(self.solimp),
                "solreffriction": list(self.solreffriction), "friction": list(self.friction),
                "impratio": self.impratio}


@dataclass(frozen=True)
class BaseSettings:
    """What a fit starts from for one scene: the base mapping's settings and the base of
    solreffriction.damping: the penalty mapping's solreffriction[1], rescaled by the base's
    dwidth so that the friction row's damping B = -solreffriction[1] / dwidth is the penalty's."""

    mapping: str
    settings: ContactSettings
    penalty_friction_damping: float


def read_model(model) -> ContactSettings:
    """The settings of a compiled model's pairs (all equal: ValueError otherwise)."""
    if model.npair == 0:
        return ContactSettings((0.0, 0.0), (0.0,) * 5, (0.0, 0.0), (0.0,) * 5, float(model.opt.impratio))
    fields = {"solref": model.pair_solref, "solimp": model.pair_solimp,
              "solreffriction": model.pair_solreffriction, "friction": model.pair_friction}
    for name, array in fields.items():
        if not np.all(array == array[0]):
            raise ValueError(f"pairs differ in {name}: {array.tolist()}")
    return ContactSettings(**{k: tuple(float(x) for x in v[0]) for k, v in fields.items()},
                           impratio=float(model.opt.impratio))


def write_model(model, s: ContactSettings) -> None:
    """Write the settings into every pair of a compiled model (and opt.impratio)."""
    if model.npair:
        model.pair_solref[:] = s.solref
        model.pair_solimp[:] = s.solimp
        model.pair_solreffriction[:] = s.solreffriction
        model.pair_friction[:] = s.friction
    model.opt.impratio = s.impratio


def write_spec(spec, s: ContactSettings) -> None:
    """Write the settings into every <pair> of a spec (and option impratio)."""
    for pair in spec.pairs:
        pair.solref = list(s.solref)
        pair.solimp = list(s.solimp)
        pair.solreffriction = list(s.solreffriction)
        pair.friction = list(s.friction)
    spec.option.impratio = s.impratio


def calibrated(base: BaseSettings, params, values) -> ContactSettings:
    """The base settings with each parameter's gain or value (values: one per parameter)."""
    fields = {name: list(base.settings.field(name))
              for name in ("solref", "solimp", "solreffriction", "friction", "impratio")}
    for p, v in zip(params, values):
        for i in p.index:
            if p.kind == "value":
                fields[p.field][i] = float(v)
            elif p.field == "solreffriction":
                fields[p.field][0] = 0.0
                fields[p.field][i] = float(v) * base.penalty_friction_damping
            else:
                fields[p.field][i] = float(v) * base.settings.field(p.field)[i]
    impratio = fields.pop("impratio")[0]
    return ContactSettings(**{k: tuple(v) for k, v in fields.items()}, impratio=impratio)
