"""The contact law's families, as data: each effect's law names and the parameters each takes.

    damping_law    compression (the seed's), linear, unclamped, hunt_crossley   Fn (N)
    friction_law   tanh (the seed's), ramp, smooth_coulomb, sign                Ft (N)
    roll_law       tanh (the seed's), sign                                      tau (N m)

Each simulator side (custom_sim, the independent oracle, the MuJoCo twin) writes the formulas
itself (docs/contact-laws.md#the-families); this module only names them, so that a scene, a
`--law` file and an identified law speak the same words.
"""
from __future__ import annotations

DAMPING_LAWS = ("compression", "linear", "unclamped", "hunt_crossley")
FRICTION_LAWS = ("tanh", "ramp", "smooth_coulomb", "sign")
ROLL_LAWS = ("tanh", "sign")

# the [contact] field that names each effect's law, and the parameters each family takes
# beyond the ones every family of that effect shares (k for the normal force, mu, mu_roll)
LAW_PARAMETERS: dict[str, dict[str, tuple[str, ...]]] = {
    "damping_law": {"compression": ("c",), "linear": ("c",), "unclamped": ("c",),
                    "hunt_crossley": ("dissipation",)},
    "friction_law": {"tanh": ("alpha",), "ramp": ("alpha",), "smooth_coulomb": ("alpha",), "sign": ()},
    "roll_law": {"tanh": ("roll_sharpness",), "sign": ()},
}
LAW_NAMES = {"damping_law": DAMPING_LAWS, "friction_law": FRICTION_LAWS, "roll_law": ROLL_LAWS}

# the seed's law: what a scene gets when it names none
SEED_LAW = {"damping_law": "compression", "friction_law": "tanh", "roll_law": "tanh"}


def is_seed_law(contact) -> bool:
    """True when a scene's [contact] uses the seed's three families (any parameters)."""
    return all(getattr(contact, field) == name for field, name in SEED_LAW.items())


def effect_texts(contact) -> dict[str, str]:
    """Each effect's family and parameters in words: {"normal": "linear (k 1e+04 N/m, c 20 N s/m)", ...}."""
    normal = (f"dissipation {contact.dissipation:g} s/m" if contact.damping_law == "hunt_crossley"
              else f"c {contact.c:g} N s/m")
    friction = f", alpha {contact.alpha:g} s/m" if contact.alpha is not None else ""
    rolling = f", roll_sharpness {contact.roll_sharpness:g} s/rad" if contact.roll_sharpness is not None else ""
    return {"normal": f"{contact.damping_law} (k {contact.k:g} N/m, {normal})",
            "friction": f"{contact.friction_law} (mu {contact.mu:g}{friction})",
            "rolling": f"{contact.roll_law} (mu_roll {contact.mu_roll:g} m{rolling})"}


def law_text(contact) -> str:
    """One line naming a [contact]'s three laws and their parameters, for pages and messages."""
    return "; ".join(f"{effect} {text}" for effect, text in effect_texts(contact).items())
