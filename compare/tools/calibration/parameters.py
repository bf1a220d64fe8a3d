"""The contact settings a calibration may fit, each with its bounds and what it multiplies.

    gain    a factor on the base mapping's value for each scene (dimensionless, 1 = the mapping):
            solref.stiffness, solref.damping (direct form, on the penalty mapping),
            solref.timeconst, solref.dampratio (positive form, on the physical mapping),
            solreffriction.damping, friction.slide, friction.roll
    value   one number shared by every scene: the five solimp entries and impratio

The two solref forms cannot be mixed in one fit; the fit runs in z = ln(p / p0). Why gains,
and what each sets: docs/calibration.md#calibrate-fit-the-twin-to-custom_sim.
"""
from __future__ import annotations

from dataclasses import dataclass

from scene_types import BadInput


@dataclass(frozen=True)
class Parameter:
    """One fittable setting: field of the <pair> (or option) it writes, entries, bounds."""

    name: str
    kind: str                  # "gain" | "value"
    field: str                 # solref | solimp | solreffriction | friction | impratio
    index: tuple[int, ...]     # entries of the field it sets
    lower: float
    upper: float
    form: str | None           # solref form it needs: "direct" | "positive" | None
    doc: str


# Gains may move an order of magnitude either way: beyond that the mapping is not being
# corrected but replaced, and the bound flags it.
GAIN_BOUNDS = (0.1, 10.0)
PARAMETERS = {p.name: p for p in (
    Parameter("solref.stiffness", "gain", "solref", (0,), *GAIN_BOUNDS, "direct",
              "spring of the direct form: solref[0] = -gain k A_hat"),
    Parameter("solref.damping", "gain", "solref", (1,), *GAIN_BOUNDS, "direct",
              "damper of the direct form: solref[1] = -gain c A_hat"),
    Parameter("solref.timeconst", "gain", "solref", (0,), *GAIN_BOUNDS, "positive",
              "time constant of the positive form: solref[0] = gain / (wn zeta) s"),
    Parameter("solref.dampratio", "gain", "solref", (1,), *GAIN_BOUNDS, "positive",
              "damping ratio of the positive form: solref[1] = gain zeta"),
    Parameter("solreffriction.damping", "gain", "solreffriction", (1,), *GAIN_BOUNDS, None,
              "friction rows' damping: solreffriction[1] = gain x the penalty mapping's"),
    Parameter("friction.slide", "gain", "friction", (0, 1), *GAIN_BOUNDS, None,
              "sliding friction coefficient: gain x mu"),
    Parameter("friction.roll", "gain", "friction", (3, 4), *GAIN_BOUNDS, None,
              "rolling friction length: gain x mu_roll"),
    # solimp bounds: MuJoCo clamps the impedance to [mjMINIMP, mjMAXIMP] = [1e-4, 0.9999]
    Parameter("solimp.d0", "value", "solimp", (0,), 1e-4, 0.9999, None, "impedance at zero depth"),
    Parameter("solimp.dwidth", "value", "solimp", (1,), 1e-4, 0.9999, None, "impedance at depth width"),
    Parameter("solimp.width", "value", "solimp", (2,), 1e-5, 0.1, None, "depth over which d0 -> dwidth, m"),
    Parameter("solimp.midpoint", "value", "solimp", (3,), 0.01, 0.99, None, "midpoint of the sigmoid"),
    Parameter("solimp.power", "value", "solimp", (4,), 1.0, 10.0, None, "power of the sigmoid"),
    # impratio: 1 is MuJoCo's default; the penalty mapping uses 1e4 (friction.py)
    Parameter("impratio", "value", "impratio", (0,), 1.0, 1e6, None,
              "ratio of friction to normal impedance (option, shared by every pair)"),
)}

# The few that matter (docs/calibration.md): the normal spring and damper of the direct form,
# the friction rows' viscous slope, and the friction coefficient; all start at the penalty
# mapping, the best of the three on the scenes it was derived for.
DEFAULT_FIT = ("solref.stiffness", "solref.damping", "solreffriction.damping", "friction.slide")


def parse_fit(text: str | None) -> tuple[Parameter, ...]:
    """The --fit list (comma separated names) -> parameters; BadInput names a wrong one."""
    names = DEFAULT_FIT if not text else tuple(n.strip() for n in text.split(",") if n.strip())
    if not names:
        raise BadInput(f"--fit: empty list (expected names from: {', '.join(PARAMETERS)})")
    unknown = [n for n in names if n not in PARAMETERS]
    if unknown:
        raise BadInput(f"--fit: unknown parameter {unknown[0]!r} (expected names from: {', '.join(PARAMETERS)})")
    if len(set(names)) != len(names):
        raise BadInput(f"--fit: a parameter is named twice in {text!r}")
    params = tuple(PARAMETERS[n] for n in names)
    forms = {p.form for p in params if p.form}
    if len(forms) > 1:
        raise BadInput("--fit: solref.stiffness/solref.damping (direct form) and solref.timeconst/"
                       "solref.dampratio (positive form) cannot be fitted together (expected one form)")
    return params


def base_mapping(params) -> str:
    """The mapping a fit starts from: physical for the positive solref form, else penalty."""
    return "physical" if any(p.form == "positive" for p in params) else "penalty"
