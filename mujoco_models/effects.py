"""What the scene's effect list becomes in MuJoCo: gravity, condim and the friction vector.

Only listed effects go in (docs/scene-format.md): no gravity -> option gravity 0 0 0; no contact -> no
contact pair; condim 1 (contact) / 3 (+ friction) / 6 (+ rolling_friction, the seed's choice
for the rolling circle). friction = "slide torsion roll": mu (-), 0 (m: no joint lets the body
spin about the ground normal, so torsion never acts), mu_roll (m).
"""
from __future__ import annotations

from scene_types.schema import Scene


def gravity_vector(scene: Scene) -> tuple[float, float, float]:
    """MuJoCo's option gravity (m/s^2): -g along z (our -y), or 0."""
    return (0.0, 0.0, -scene.g if scene.has("gravity") else 0.0)


def condim_for(scene: Scene) -> int:
    """1 normal only, 3 + sliding friction, 6 + torsional and rolling friction."""
    if scene.has("rolling_friction"):
        return 6
    return 3 if scene.has("friction") else 1


def friction_for(scene: Scene) -> tuple[float, float, float]:
    """(slide, torsion, roll): mu (-), 0 m, mu_roll (m); 0 for an effect the scene does not
    list (MuJoCo floors each at 1e-5, and condim leaves the row out anyway)."""
    mu = scene.contact.mu if scene.has("friction") else 0.0
    roll = scene.contact.mu_roll if scene.has("rolling_friction") else 0.0
    return (mu, 0.0, roll)


def pair_friction(scene: Scene) -> tuple[float, float, float, float, float]:
    """The 5-vector of a <pair>: slide, slide, torsion, roll, roll (isotropic)."""
    mu, torsion, roll = friction_for(scene)
    return (mu, mu, torsion, roll, roll)
