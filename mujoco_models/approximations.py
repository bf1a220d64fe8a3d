"""Every way a twin differs from the hand-written simulator, as sentences a user reads.

Brax's io/mjcf refuses what it cannot map; the twin maps everything and says here what it
could only approximate: geometry, each contact law the scene names (damping, friction,
rolling: one line each), the solref mapping's known error, the integrator and the step.
run.py stores the list in Trajectory.meta.
"""
from __future__ import annotations

from scene_types.integrators import SAME_UPDATE
from scene_types.schema import Scene

from .geometry import CONTACT_SPHERE_RADIUS



def approximations(twin) -> list[str]:
    """Sentences for a built twin (spec.Twin)."""
    scene = twin.scene
    out = [geometry_note(scene)]
    if scene.has("contact"):
        out += damping_note(scene, twin.contact.mapping)
        out += friction_law_notes(scene)
        out += roll_law_notes(scene)
        out += twin.contact.notes
        out += rolling_notes(scene, twin)
        if twin.cone == "pyramidal" and scene.has("friction"):
            out.append("cone: pyramidal, the friction cone cut into 2 (condim - 1) planes; the "
                       "rolling-resistance deceleration is about 4 % off")
    out += stepping_notes(scene, twin.integrator, twin.dt)
    return out


def geometry_note(scene: Scene) -> str:
    shape = scene.body.shape
    if shape == "point":
        return ("geometry: a sphere whose lowest point is our contact point (0, -h): one contact, "
                "at our depth (the point mass never turns)")
    if shape == "circle":
        R = scene.body.radius
        depth = scene.body.mass * scene.g / scene.contact.k if scene.has("gravity") else 0.0
        return (f"geometry: a sphere of radius R = {R:g} m stands in for the seed's cylinder (radius R, "
                f"length 2R), which lying on its side would give two contacts, one at each end of its "
                f"touching line, each with the full depth; the sphere gives one contact straight below "
                f"the centre, as ours. MuJoCo applies it mid-way through the overlap, R - d/2 below the "
                f"centre where ours is at R: at the resting depth d = m g / k = {depth * 1e3:.2g} mm the "
                f"friction's lever arm is {depth / 2 / R * 100:.2g} % shorter")
    what = "box corner" if shape == "box" else "corner of every part"
    return (f"geometry: one sphere of radius {CONTACT_SPHERE_RADIUS:g} m at each {what} (a box geom "
            f"gives two contacts per 2D corner, one at each face in y): one contact per corner as ours, "
            f"touching {CONTACT_SPHERE_RADIUS:g} m before ours. contact point: MuJoCo puts it mid-way "
            f"through the penetration, d/2 above our corner (d reaches about a centimetre at an impact), and "
            f"applies the friction force and measures the slip there: the friction's lever arm about the "
            f"centre of mass differs from ours by d/2, which changes the spin each landing leaves. The "
            f"normal force is the same wherever along the normal it acts")


def damping_note(scene: Scene, mapping: str = "penalty") -> list[str]:
    """The line on the scene's damping_law: what MuJoCo's soft contact (a spring-damper on the
    constraint, never pulling: our linear law) makes of it."""
    law = scene.contact.damping_law
    if law == "linear":
        return ["damping law: linear, max(0, k d - c v), which is MuJoCo's own: its soft contact is a "
                "spring-damper on the constraint whose force never pulls"]
    if law == "compression":
        return ["damping law: the scene's 'compression' law (c acts only while the point approaches the "
                "ground) cannot be reproduced: MuJoCo's contact damps both ways and never pulls (our "
                "'linear' law), so its bodies leave the ground slower and bounce lower"]
    if law == "unclamped":
        return ["damping law: the scene's 'unclamped' law, k d - c v, pulls a point that leaves faster than "
                "k d / c back towards the ground, which MuJoCo's contact cannot: its force is a constraint "
                "force that never pulls (our 'linear' law), so its bodies leave sooner and bounce higher"]
    if law == "hunt_crossley":
        dissipation = scene.contact.dissipation
        damper = ("so MuJoCo's contact is an undamped spring: every bounce elastic" if mapping != "seed" else
                  "which the seed mapping replaces by MuJoCo's default solref (a damping that does not "
                  "follow the impact speed)")
        return [f"damping law: the scene's 'hunt_crossley' law, max(0, k d (1 - {dissipation:g} v)), damps in "
                f"proportion to the depth (not at first touch) and takes more of a faster impact (restitution "
                f"about 1 - (2/3) {dissipation:g} v at impact speed v); MuJoCo's damping is one constant of "
                f"the contact (solref), not a function of depth: the twin gets the scene's c = 0, {damper}"]
    raise ValueError(f"no approximation note for damping_law = {law!r}")


def friction_law_notes(scene: Scene) -> list[str]:
    """The line on the scene's friction_law (when friction is an effect): MuJoCo's friction is a
    cone, a hard Coulomb law its constraint solver solves, not a function of the slip."""
    if not scene.has("friction"):
        return []
    law, alpha = scene.contact.friction_law, scene.contact.alpha
    cone = "MuJoCo's friction is a cone, |f_t| <= mu Fn, solved by its constraint solver with the other rows"
    if law == "tanh":
        return [f"friction law: tanh, mu Fn tanh(alpha v) (1/alpha = {1 / alpha:.3g} m/s), the seed's; {cone}, "
                f"not a function of the slip: the mapping's friction rows stand in for the tanh"]
    if law == "ramp":
        return [f"friction law: the scene's 'ramp', mu Fn clamp(alpha v, -1, 1), viscous with slope mu Fn alpha "
                f"up to the slip 1/alpha = {1 / alpha:.3g} m/s, then Coulomb with a kink; {cone}, which has "
                f"no such ramp of its own (the penalty mapping's viscous row capped at mu Fn is one, but with "
                f"a fixed slope, where ours follows Fn)"]
    if law == "smooth_coulomb":
        return [f"friction law: the scene's 'smooth_coulomb', mu Fn v / sqrt(v^2 + 1/alpha^2) (1/alpha = "
                f"{1 / alpha:.3g} m/s), reaches mu Fn only slowly (90 % at v = 2.1/alpha, tanh at 1.5/alpha); "
                f"{cone}: no row of it follows this approach to the cap"]
    if law == "sign":
        return [f"friction law: the scene's 'sign', bare Coulomb mu Fn sign(v) with no regularisation; {cone}, "
                f"a hard Coulomb law that holds a slow contact still (static friction), where ours applies "
                f"its full mu Fn against the slip every step and a stopped body chatters (by about "
                f"mu g dt = {scene.contact.mu * scene.g * scene.dt:.2g} m/s a step on a point mass)"]
    raise ValueError(f"no approximation note for friction_law = {law!r}")


def roll_law_notes(scene: Scene) -> list[str]:
    """The line on the scene's roll_law (when rolling_friction is an effect)."""
    if not scene.has("rolling_friction"):
        return []
    law = scene.contact.roll_law
    if law == "tanh":
        return [f"rolling law: tanh, mu_roll Fn tanh(roll_sharpness omega) (roll_sharpness "
                f"{scene.contact.roll_sharpness:g} s/rad); MuJoCo's rolling rows are part of its friction "
                f"cone, capped at mu_roll Fn, not a function of omega (below)"]
    if law == "sign":
        return ["rolling law: the scene's 'sign', bare mu_roll Fn sign(omega) with no regularisation; MuJoCo's "
                "rolling rows, capped at mu_roll Fn in its friction cone, hold a slow disk still (rolling "
                "stiction) where ours flips the full torque each step"]
    raise ValueError(f"no approximation note for roll_law = {law!r}")


def rolling_notes(scene: Scene, twin) -> list[str]:
    if not scene.has("rolling_friction"):
        return []
    notes = ["rolling resistance: MuJoCo's rolling rows share one cone with the sliding ones, "
             "(f_t / mu)^2 + (tau / mu_roll)^2 <= Fn^2 (elliptic): while the disk slides, the sliding "
             "force takes the whole cone and the rolling torque is about 0, where ours applies "
             "mu Fn and mu_roll Fn together"]
    if twin.contact.mapping == "penalty" and twin.contact.friction_damping and scene.contact.mu_roll > 0.0:
        mu, roll = scene.contact.mu, scene.contact.mu_roll
        notes.append(f"rolling resistance (penalty): below its cap mu_roll Fn the rolling torque is "
                     f"viscous, its regularisation being mu^2 / mu_roll^2 = {(mu / roll) ** 2:.3g} times the "
                     f"sliding rows' (mujoco_models/friction.py): it stops a slow disk smoothly where "
                     + ("ours keeps mu_roll Fn sign(omega)" if scene.contact.roll_law == "sign" else
                        f"ours keeps about mu_roll Fn down to |omega| ~ 1/roll_sharpness = "
                        f"{1 / scene.contact.roll_sharpness:.2g} rad/s"))
    return notes


def stepping_notes(scene: Scene, integrator: str, dt: float) -> list[str]:
    notes = []
    if SAME_UPDATE[integrator] != scene.integrator:
        notes.append(f"integrator: MuJoCo's {integrator} takes the step of our {SAME_UPDATE[integrator]} "
                     f"(contact forces explicit), the scene runs {scene.integrator}")
    if dt != scene.dt:
        notes.append(f"step: MuJoCo runs dt = {dt:g} s, ours {scene.dt:g} s")
    return notes
