"""solref and solimp from the scene's k (N/m) and c (N s/m): the three mappings of docs/physics.md.

    penalty   flat solimp d = PENALTY_IMPEDANCE, solref = (-k A_hat, -c A_hat): our linear-law
              force up to a relative d (A / A_hat - 1); friction rows: friction.py
    physical  timeconst = 1 / (wn zeta), dampratio = zeta, MuJoCo's default solimp
    seed      timeconst = sqrt(m / k), dampratio = zeta: right only at zeta = 1

solref_for(scene, mapping) -> ContactParameters; a_hat(model) reads MuJoCo's A_hat (1/kg) from
body_invweight0. The derivation from MuJoCo's constraint equations:
docs/physics.md#how-the-mappings-are-derived.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from .rigid_body import RigidBody, rigid_body
from scene_types.schema import Scene

from .effects import condim_for
from .friction import penalty_friction_rows, resting_contacts

MAPPINGS = ("penalty", "physical", "seed")
PENALTY_IMPEDANCE = 1e-4   # MuJoCo's mjMINIMP: the smallest impedance it allows
# solimp (d0, dwidth, width, midpoint, power)
PENALTY_SOLIMP = (PENALTY_IMPEDANCE, PENALTY_IMPEDANCE, 0.001, 0.5, 2.0)
MUJOCO_DEFAULT_SOLIMP = (0.9, 0.95, 0.001, 0.5, 2.0)
MUJOCO_DEFAULT_SOLREF = (0.02, 1.0)


@dataclass(frozen=True)
class ContactParameters:
    """What every contact pair gets: solref (2), solimp (5), solreffriction (2; 0 0 = use
    solref), the option impratio, and sentences on the mapping's known error."""

    mapping: str
    solref: tuple[float, float]
    solimp: tuple[float, float, float, float, float]
    a_hat: float                       # 1/kg, MuJoCo's diagonal inverse inertia of a contact row
    solreffriction: tuple[float, float] = (0.0, 0.0)
    impratio: float = 1.0
    friction_damping: float | None = None  # N s/m, viscous slope of a friction row (penalty)
    notes: list[str] = field(default_factory=list)


def a_hat(model, body_id: int = 1) -> float:
    """MuJoCo's A_hat (1/kg) of a contact between the body and the world: the body's
    translational inverse weight at qpos0 (the world adds 0)."""
    return float(model.body_invweight0[body_id, 0])


def solref_for(scene: Scene, mapping: str | None = None, model_or_a_hat=None,
               dt: float | None = None) -> ContactParameters:
    """The contact parameters of `mapping` (default scene.mujoco.solref) for the scene, given
    the twin's compiled model or A_hat (1/kg); without either, A_hat is built and read."""
    mapping = mapping or scene.mujoco.solref
    props = rigid_body(scene.body)
    if model_or_a_hat is None:
        from .spec import build_model
        model_or_a_hat = build_model(scene, mapping)
    value = float(model_or_a_hat) if isinstance(model_or_a_hat, (int, float)) else a_hat(model_or_a_hat)
    return contact_parameters(scene, mapping, value, dt or scene.mujoco.dt or scene.dt, props)


def natural_frequency(scene: Scene) -> tuple[float, float]:
    """(wn rad/s, zeta) of the point-mass spring-damper k, c on the body's mass."""
    m, k, c = scene.body.mass, scene.contact.k, scene.contact.c
    return math.sqrt(k / m), c / (2.0 * math.sqrt(k * m))


def pyramid_scale(scene: Scene) -> float:
    """Factor on the penalty solref that gives back the normal force with the pyramidal cone."""
    n = condim_for(scene)
    if scene.mujoco.cone != "pyramidal" or n == 1:
        return 1.0
    mu = max(scene.contact.mu, 1e-5)   # MuJoCo's mjMINMU floor
    return mu * mu * (1.0 + mu * mu) / (n - 1)


def contact_parameters(scene: Scene, mapping: str, a_hat: float, dt: float,
                       props: RigidBody) -> ContactParameters:
    """solref/solimp of `mapping` for the scene's k and c (a_hat 1/kg, dt s for MuJoCo's refsafe)."""
    if mapping not in MAPPINGS:
        raise ValueError(f"unknown solref mapping {mapping!r} (expected one of: {', '.join(MAPPINGS)})")
    if mapping == "penalty":
        return _penalty(scene, a_hat, props, dt)
    k, c, m = scene.contact.k, scene.contact.c, scene.body.mass
    wn, zeta = natural_frequency(scene)
    if mapping == "physical":
        if zeta > 0.0:
            solref, notes = (1.0 / (wn * zeta), zeta), []
        else:  # timeconst = 1/(wn zeta) is infinite: the same gains in the direct form
            solref = (-k / m, -c / m)
            notes = ["solref physical: zeta = 0 makes timeconst infinite; the same gains are written "
                     "in MuJoCo's direct form (-k/m, -c/m), stiffness and damping per unit mass"]
        return ContactParameters(mapping, solref, MUJOCO_DEFAULT_SOLIMP, a_hat, notes=notes + [
            f"solref physical: timeconst = 1/(wn zeta), dampratio = zeta (wn = {wn:.4g} rad/s, "
            f"zeta = {zeta:.3g}) give the spring-damper per unit mass of a point of mass m; MuJoCo's "
            f"impedance d = 0.9..0.95 lets (1 - d) of the unconstrained acceleration through, so a body "
            f"at rest sinks only about (1 - d) m g / k, and MuJoCo divides by its own A_hat = "
            f"{a_hat:.4g} 1/kg, not by the contact's true inverse inertia, which a rotating body changes "
            f"with its pose"] + _refsafe(solref, dt) + _default_friction(scene))
    if zeta > 0.0:
        solref = (math.sqrt(m / k), zeta)
        notes = [f"solref seed: timeconst = sqrt(m/k), dampratio = c/(2 sqrt(mk)) = {zeta:.3g}: MuJoCo's "
                 f"spring is then k / zeta^2 = {1.0 / (zeta * zeta):.3g} k and its damping 2 sqrt(k m) "
                 f"= {1.0 / zeta:.3g} c (exact only at zeta = 1)"]
    else:
        solref = MUJOCO_DEFAULT_SOLREF
        notes = ["solref seed: c = 0 gives dampratio 0, which MuJoCo rejects (mixed solref format) and "
                 f"replaces by its default solref {MUJOCO_DEFAULT_SOLREF}; the twin writes that default"]
    return ContactParameters(mapping, solref, MUJOCO_DEFAULT_SOLIMP, a_hat,
                             notes=notes + _refsafe(solref, dt) + _default_friction(scene))


def _penalty(scene: Scene, a_hat: float, props: RigidBody, dt: float) -> ContactParameters:
    k, c, d = scene.contact.k, scene.contact.c, PENALTY_IMPEDANCE
    scale = pyramid_scale(scene)
    solref = (-k * a_hat * scale, -c * a_hat * scale)
    a0 = f"d g / A_hat = {d * scene.g / a_hat:.2g} N" if scene.has("gravity") else "d a0 / A_hat (0 here)"
    notes = [f"solref penalty: flat impedance d = {d:g} and solref = (-k A_hat, -c A_hat) with A_hat = "
             f"{a_hat:.6g} 1/kg make each contact the spring-damper max(0, k depth - c v) of our linear "
             f"law, up to a relative d (A/A_hat - 1) (A: the contact's true inverse inertia) and an "
             f"extra force {a0} while touching"]
    if scale != 1.0:
        mu, n = scene.contact.mu, condim_for(scene)
        notes.append(f"pyramidal cone: solref scaled by mu^2 (1 + mu^2) / (condim - 1) = {scale:.4g} so the "
                     f"normal force is ours; friction is then viscous mu^2 c / (condim - 1) = "
                     f"{mu * mu * c / (n - 1):.3g} N s/m capped by the pyramid, not the scene's "
                     f"{scene.contact.friction_law} law")
        return ContactParameters("penalty", solref, PENALTY_SOLIMP, a_hat, notes=notes)
    if not scene.has("friction"):
        return ContactParameters("penalty", solref, PENALTY_SOLIMP, a_hat, notes=notes)
    rows = penalty_friction_rows(scene, props, a_hat, d, dt)
    if scene.contact.friction_law == "sign":
        load = (f"1 / (A_ref dt), A_ref = {rows.a_ref:.4g} 1/kg: the bare sign law's infinite slope, "
                f"as stiff as a step resolves")
        ours = ("ours is mu Fn sign(v), which no viscous row reaches: at a slip below mu Fn / c_t the "
                "row holds the point where ours flips its full force each step")
    else:
        load = (f"mu alpha N_ref, N_ref = m g / {resting_contacts(scene)} = {rows.reference_load:.3g} N "
                f"per resting contact" if rows.reference_load else "the normal damping c: no gravity, no resting load")
        ours = (f"ours is the {scene.contact.friction_law} law mu Fn s(alpha v), whose slope mu Fn alpha "
                f"follows Fn, so during an impact (Fn >> N_ref) ours grips harder")
    notes.append(
        f"friction (penalty): MuJoCo's friction row is viscous, c_t v with c_t = {rows.damping:.4g} N s/m "
        f"({load}), capped at mu Fn by the {scene.mujoco.cone} cone; {ours}; below the "
        f"cap the row also cancels part of the other tangential accelerations (partial stiction); "
        f"impratio = {rows.impratio:g} and solreffriction keep MuJoCo's cone projection from raising "
        f"the normal force while sliding (only by about 2 mu c_t v / impratio, see docs/physics.md)")
    return ContactParameters("penalty", solref, PENALTY_SOLIMP, a_hat, rows.solreffriction,
                             rows.impratio, rows.damping, notes)


def _default_friction(scene: Scene) -> list[str]:
    if not scene.has("friction"):
        return []
    creep = ("our bare sign law flips its full force each step" if scene.contact.friction_law == "sign"
             else f"our {scene.contact.friction_law} law lets the body creep")
    return ["friction: MuJoCo's friction rows use the normal's solref and impratio 1: a soft "
            f"constraint that drives the slip to zero inside the cone mu Fn (static friction), where "
            f"{creep}; while sliding, the elliptic cone's projection raises "
            "the normal force above the spring's"]


def _refsafe(solref, dt: float) -> list[str]:
    if solref[0] > 0.0 and solref[0] < 2.0 * dt:
        return [f"MuJoCo raises timeconst {solref[0]:.3g} s to 2 dt = {2 * dt:.3g} s (refsafe)"]
    return []
