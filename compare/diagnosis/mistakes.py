"""A catalogue of known simulator mistakes, and a diagnosis that names the one a trajectory made.

Each entry is a variant of the reference step that differs from it in one line of the seed:
a field of the force law replaced (force_law.Law), the geometry changed (inertia, contact points)
or the integrator's update order swapped. The variant's one-step function is `Mistake.step`.

    diagnose(scene, states, integrator, dt) -> dict
        the step residual of the trajectory, then for each mistake the residual of the
        trajectory against that variant's step; a mistake *explains* the trajectory when every
        step is within round-off of the variant's step while the correct step's residual is not.
    diagnose_step(step_fn, scene, moments, integrator, dt) -> dict
        a user's step function f(state, scene_dict, dt) called from chosen states, compared with
        the reference step and each variant's.
    force_difference(eq, z0, dz, dt) -> dict
        a step's velocity difference as the force that makes it, m dv / dt (N) and
        I domega / dt (N m), at the points touching.

Neither guesses: where no variant (and no pair of variants) explains the residual to round-off,
the answer says so and gives the residual. Where several explain it equally, all are named. A
variant that explains all steps but N is kept in the dict (not_named), never named nor printed.
"""
from __future__ import annotations

import dataclasses
import itertools
from dataclasses import dataclass, field
from collections.abc import Callable

import numpy as np

from compare.oracle.force_law import (SEED_LAW, Law, arms, contact_state, friction_shape, normal_force,
                                      rolling_shape)
from compare.oracle.reference import Equations

from ..oracle.one_step import METHODS, one_step
from ..checks.row import CheckRow
from ..checks.step_check import COMPONENTS, UNIT_OF, check_step, first_failure, largest_residual, phase, step_residuals

# Steps of a failing trajectory a variant is screened on before the whole trajectory is
# stepped with it: the correct step's first failures (where a mistake shows) and a spread.
SCREEN_STEPS = 400
FIRST_SCREEN = 8      # the correct step's first failures: most variants are ruled out there


@dataclass(frozen=True)
class Mistake:
    """One known mistake: its name, the seed's line it concerns, what it does, and the variant.

    law        the force law with the mistake (default: the seed's)
    geometry   Equations -> Equations with wrong mass properties or contact points (or None)
    method     integrator named -> integrator actually run (a swap of update order), or {}
    applies    (scene, Equations, integrator) -> bool: the mistake changes this scene's step
    """

    name: str
    seed_line: str
    description: str
    law: Law = SEED_LAW
    geometry: Callable | None = None
    method: dict = field(default_factory=dict)
    applies: Callable = lambda scene, eq, integrator: True

    def equations(self, scene) -> Equations:
        eq = Equations.from_scene(scene)
        return self.geometry(scene, eq) if self.geometry else eq

    def integrator(self, named: str) -> str:
        return self.method.get(named, named)

    def step(self, scene, Z, dt: float, integrator: str, eq: Equations | None = None,
             input_rtol: float = 0.0):
        """The variant's one step from the states Z (N, 6): (Z1, bound, solved) as one_step."""
        eq = eq or self.equations(scene)
        return one_step(eq, Z, dt, self.integrator(integrator), self.law, input_rtol)

    def step_fn(self, scene, integrator: str):
        """The variant as a user's step function f(state, scene_dict, dt) -> state (a simulator
        with this mistake, for tests and examples)."""
        eq = self.equations(scene)

        def f(state, scene_dict=None, dt=scene.dt):
            return self.step(scene, np.asarray(state, float)[None, :], dt, integrator, eq)[0][0]
        return f


def _law(**changes) -> Law:
    return dataclasses.replace(SEED_LAW, **changes)


def _with_inertia(fn):
    def geometry(scene, eq):
        return dataclasses.replace(eq, inertia=fn(scene.body))
    return geometry


def _contact_at_com(scene, eq):
    return dataclasses.replace(eq, points=((0.0, 0.0),))


def _frame_origin_points(scene, eq):
    """Compound corners taken relative to the body frame's origin instead of the COM."""
    pts = []
    for p in scene.body.parts:
        (w, h), (ox, oy) = p.size, p.offset
        pts += [(ox - w / 2, oy - h / 2), (ox + w / 2, oy - h / 2),
                (ox + w / 2, oy + h / 2), (ox - w / 2, oy + h / 2)]
    return dataclasses.replace(eq, points=tuple(pts))


def _shape(*shapes):
    return lambda scene, eq, integrator: scene.body.shape in shapes


def _has(*effects, rotating=False):
    def applies(scene, eq, integrator):
        return all(scene.has(e) for e in effects) and (eq.rotates or not rotating)
    return applies


CATALOGUE: tuple[Mistake, ...] = (
    Mistake("friction_on_com_velocity",
            "Algorithm 2, line 8: v_i <- v + omega [-r_iy, r_ix]",
            "friction evaluated on the centre of mass velocity vx instead of the contact point's slip vx - omega r_y",
            law=_law(slip_velocity="com"), applies=_has("friction", rotating=True)),
    Mistake("box_inertia_about_corner",
            "Rigid body model: I = 1/12 m (w^2 + h^2)",
            "box inertia m (w^2 + h^2) / 3 (about a corner) instead of / 12 (about the centre)",
            geometry=_with_inertia(lambda b: b.mass * (b.size[0] ** 2 + b.size[1] ** 2) / 3.0),
            applies=_shape("box")),
    Mistake("box_inertia_width_only",
            "Rigid body model: I = 1/12 m (w^2 + h^2)",
            "box inertia m w^2 / 12: the height term left out",
            geometry=_with_inertia(lambda b: b.mass * b.size[0] ** 2 / 12.0),
            applies=_shape("box")),
    Mistake("compound_inertia_without_parallel_axis",
            "Algorithm 3, line 2: compute total mass, COM offset, inertia about COM",
            "compound inertia as the sum of the parts' own m (w^2 + h^2) / 12, without m_j |o_j - com|^2",
            geometry=_with_inertia(lambda b: sum(p.mass * (p.size[0] ** 2 + p.size[1] ** 2) / 12.0
                                                 for p in b.parts)),
            applies=_shape("compound")),
    Mistake("compound_points_not_about_com",
            "Algorithm 3, line 2: compute total mass, COM offset, inertia about COM",
            "compound contact points measured from the body frame's origin, not from the COM",
            geometry=_frame_origin_points,
            applies=lambda scene, eq, integrator: scene.body.shape == "compound"
            and any(abs(c) > 0 for c in _com(scene))),
    Mistake("disk_inertia_of_a_ring",
            "MuJoCo configuration / Algorithm 4: disk I = 0.5 m R^2",
            "disk inertia m R^2 (a thin ring) instead of m R^2 / 2",
            geometry=_with_inertia(lambda b: b.mass * b.radius ** 2), applies=_shape("circle")),
    Mistake("torque_sign_flipped",
            "Algorithm 2, line 11: tau <- tau + r_i x F_i",
            "the cross product taken backwards, r_y F_x - r_x F_y",
            law=_law(torque_sign=-1.0), applies=_has("contact", rotating=True)),
    Mistake("damping_in_the_air",
            "Algorithm 2, line 7: if c_iy < 0 then (forces only while touching)",
            "the damper c max(0, -vc_y) also acts at points above the ground (d <= 0)",
            law=_law(damping_in_air=True),
            applies=lambda scene, eq, integrator: scene.has("contact") and scene.contact.c > 0),
    Mistake("linear_damping_for_compression",
            "Algorithm 1, line 4: Fn <- k d + c max(0, -v_y)",
            "normal force max(0, k d - c vc_y) (damping both ways) where the compression law is asked",
            law=_law(damping_law="linear"),
            applies=lambda scene, eq, integrator: scene.has("contact") and scene.contact.c > 0
            and scene.contact.damping_law == "compression"),
    Mistake("compression_damping_for_linear",
            "Algorithm 1, line 4: Fn <- k d + c max(0, -v_y)",
            "normal force k d + c max(0, -vc_y) (damping only on approach) where the linear law is asked",
            law=_law(damping_law="compression"),
            applies=lambda scene, eq, integrator: scene.has("contact") and scene.contact.c > 0
            and scene.contact.damping_law == "linear"),
    Mistake("explicit_euler_in_disguise",
            "Algorithm 1, lines 7-8: v <- v + (F/m) dt, then p <- p + v dt",
            "positions advanced with the old velocity (explicit Euler) while semi-implicit Euler is named",
            method={"semi_implicit_euler": "explicit_euler"},
            applies=lambda scene, eq, integrator: integrator == "semi_implicit_euler"),
    Mistake("semi_implicit_for_explicit",
            "Numerical integration, explicit Euler: p_t+1 = p_t + v_t dt",
            "positions advanced with the new velocity (semi-implicit Euler) while explicit Euler is named",
            method={"explicit_euler": "semi_implicit_euler"},
            applies=lambda scene, eq, integrator: integrator == "explicit_euler"),
    Mistake("friction_sign_not_tanh",
            "Algorithm 1, line 5: Ff <- -mu Fn tanh(alpha v_x)",
            "friction -mu Fn sign(v) (Coulomb's law unregularised) instead of tanh(alpha v)",
            law=_law(friction_shape="sign"),
            applies=lambda scene, eq, integrator: scene.has("friction") and eq.friction_law == "tanh"),
    Mistake("friction_on_total_normal_force",
            "Algorithm 2, line 9: F_i <- ContactForce(c_i, v_i)",
            "each point's friction bounded by the whole body's normal force instead of its own Fn_i",
            law=_law(friction_load="body"),
            applies=lambda scene, eq, integrator: scene.has("friction") and len(eq.points) > 1),
    Mistake("gravity_without_mass",
            "Algorithm 2, line 3: F <- [0, -m g]",
            "a weight of g newtons, the mass left out (invisible on a 1 kg body)",
            law=_law(gravity_mass=False),
            applies=lambda scene, eq, integrator: scene.has("gravity") and eq.mass != 1.0),
    Mistake("rolling_resistance_bare_sign",
            "Algorithm 4, line 9: tau <- tau + r x Fc - mu_roll Fn sign(omega)",
            "rolling resistance with the bare sign(omega), where the reference regularises it",
            law=_law(rolling="sign"),
            applies=lambda scene, eq, integrator: scene.has("rolling_friction")
            and eq.roll_sharpness is not None),
    Mistake("rolling_resistance_missing",
            "Algorithm 4, line 9: tau <- tau + r x Fc - mu_roll Fn sign(omega)",
            "no rolling resistance torque",
            law=_law(rolling="none"), applies=_has("rolling_friction")),
    Mistake("contact_height_ignored",
            "Algorithm 1, line 3: d <- max(0, h - y)",
            "the point mass touches at its centre (d = -y), its contact height left out",
            geometry=_contact_at_com,
            applies=lambda scene, eq, integrator: scene.body.shape == "point"
            and scene.has("contact") and (scene.body.contact_height or 0.0) > 0.0),
    Mistake("corners_not_rotated",
            "Algorithm 2, line 5: r_i <- R(theta) c_i^local",
            "contact points taken in the body frame, never rotated by theta",
            law=_law(points_turn=False),
            applies=lambda scene, eq, integrator: scene.has("contact") and eq.turning),
)

BY_NAME = {m.name: m for m in CATALOGUE}


def _com(scene):
    masses = [p.mass for p in scene.body.parts]
    total = sum(masses)
    return tuple(sum(p.mass * p.offset[k] for p in scene.body.parts) / total for k in (0, 1))


def combine(a: Mistake, b: Mistake) -> Mistake:
    """Both mistakes at once (law fields, geometry and integrator swap of each)."""
    changes = {f.name: getattr(b.law, f.name) for f in dataclasses.fields(Law)
               if getattr(b.law, f.name) != getattr(SEED_LAW, f.name)}
    law = dataclasses.replace(a.law, **changes)
    ga, gb = a.geometry, b.geometry
    geometry = None
    if ga or gb:
        def geometry(scene, eq):
            return (gb(scene, ga(scene, eq) if ga else eq)) if gb else ga(scene, eq)
    return Mistake(f"{a.name} + {b.name}", f"{a.seed_line}; {b.seed_line}",
                   f"{a.description}; and {b.description}", law=law, geometry=geometry,
                   method={**a.method, **b.method},
                   applies=lambda s, e, i: a.applies(s, e, i) and b.applies(s, e, i))


def applicable(scene, integrator: str) -> list[Mistake]:
    eq = Equations.from_scene(scene)
    return [m for m in CATALOGUE if m.applies(scene, eq, integrator)]


def _candidates(scene, integrator):
    singles = applicable(scene, integrator)
    pairs = []
    for a, b in itertools.combinations(singles, 2):
        if a.method and b.method:
            continue
        if set(_changed(a.law)) & set(_changed(b.law)):
            continue  # two values for the same line
        pairs.append(combine(a, b))
    return singles, pairs


def _changed(law: Law):
    return [f.name for f in dataclasses.fields(Law) if getattr(law, f.name) != getattr(SEED_LAW, f.name)]


def _entry(m: Mistake) -> dict:
    return {"name": m.name, "seed_line": m.seed_line, "description": m.description}


def candidate(name: str) -> Mistake:
    """The catalogued mistake `name`, or the pair "a + b" (as _candidates names it)."""
    parts = [BY_NAME[n] for n in name.split(" + ")]
    return parts[0] if len(parts) == 1 else combine(*parts)


def contact_loads(eq: Equations, Z):
    """Per state and point, under the scene's law: depth d (N, n) m, normal velocity vc_y
    (N, n) m/s, slip vc_x (N, n) m/s and normal force Fn (N, n) N (0 where d <= 0)."""
    Z = np.atleast_2d(np.asarray(Z, dtype=float))
    rx, ry, _ = arms(eq, Z[:, 2])
    depth = -(Z[:, 1:2] + ry)
    vcy = Z[:, 4:5] + Z[:, 5:6] * rx
    slip = Z[:, 3:4] - Z[:, 5:6] * ry
    if not eq.contact:
        return depth, vcy, slip, np.zeros_like(depth)
    fn = normal_force(eq, depth, vcy)
    return depth, vcy, slip, np.where(depth > 0.0, fn, 0.0)


# A torque residual is read as one part of the contact torque (normal r_x Fn, friction -r_y Ft,
# rolling resistance) times -2 (that part's sign flipped), -1 (that part missing) or +1 (it
# counted twice) where it matches to TORQUE_PART_RTOL of itself: the parts are taken at the
# step's start state, and within one step of dt (5e-5 s) under the scenes' stiffnesses a
# contact force changes by a few parts in 1e4 at most.
TORQUE_PART_RTOL = 1e-3
TORQUE_READINGS = ((-2.0, "has the opposite sign"), (-1.0, "is missing"), (1.0, "is counted twice"))
PART_WORDS = {"normal": "the normal force's torque (r x Fn)", "friction": "the friction torque (r x Ft)",
              "rolling": "the rolling resistance torque", "contact": "the whole contact torque"}


def torque_parts(eq: Equations, z0) -> dict:
    """The contact torque about the COM at z0 (6,) under the scene's law, split into its parts
    (N m): normal (sum r_x Fn), friction (sum -r_y Ft), rolling (resistance), each summed
    over the points touching; and per point [{point, normal, friction}]."""
    z0 = np.asarray(z0, dtype=float)
    if not (eq.contact and eq.rotates):
        return {"normal": 0.0, "friction": 0.0, "rolling": 0.0, "points": []}
    rx, ry, _ = arms(eq, z0[None, 2])
    depth, vcy, slip, fn = contact_loads(eq, z0[None, :])
    touching = depth[0] > 0.0
    ft = np.zeros_like(fn)
    if eq.friction:
        shape = friction_shape(eq, slip)[0]
        ft = np.where(touching, -eq.mu * fn * shape, 0.0)
    tn, tt = (rx * fn)[0], (-ry * ft)[0]
    rolling = 0.0
    if eq.rolling:
        rolling = float(-(eq.mu_roll * fn * rolling_shape(eq, np.full_like(fn, z0[5]))[0]).sum())
    return {"normal": float(tn.sum()), "friction": float(tt.sum()), "rolling": rolling,
            "points": [{"point": int(j), "normal": float(tn[j]), "friction": float(tt[j])}
                       for j in np.flatnonzero(touching)]}


def read_torque(dtau: float, parts: dict) -> dict | None:
    """Which part of the contact torque a torque residual dtau (N m) is, and how: {part,
    factor, how} where dtau = factor x that part to TORQUE_PART_RTOL (the part not zero), or
    None where no single part reads it."""
    whole = parts["normal"] + parts["friction"] + parts["rolling"]
    for part, value in (("friction", parts["friction"]), ("normal", parts["normal"]),
                        ("rolling", parts["rolling"]), ("contact", whole)):
        if value == 0.0:
            continue
        for factor, how in TORQUE_READINGS:
            if abs(dtau - factor * value) <= TORQUE_PART_RTOL * abs(dtau):
                return {"part": part, "factor": factor, "how": how, "value": float(value)}
    return None


def _force_words(name: str, value: float, unit: str, over: bool) -> str | None:
    """'Fx +1.2 N' for a component beyond round-off; None for one within it (never a number
    below round-off)."""
    return f"{name} {value:+.3g} {unit}" if over else None


def force_difference(eq: Equations, z0, dz, dt: float, over=None) -> dict:
    """A step's difference dz (6,) (your step minus the reference step, both from z0) as the
    force that makes it: Fx, Fy = m dv / dt (N), torque = I domega / dt (N m), with the points
    touching at z0 it acts at (JSON-safe). over (6,) bool: the components beyond round-off
    (default: any non-zero); a force whose velocity component is within round-off (or a torque
    of a body that does not turn) is None, never a number below round-off. Where one point touches, also the
    torque that force has about the COM (r x dF) and the torque left over; where a torque is
    left with no force beside it, which part of the contact torque (normal, friction, rolling)
    it is (read_torque: "the friction torque has the opposite sign")."""
    z0, dz = np.asarray(z0, dtype=float), np.asarray(dz, dtype=float)
    over = np.asarray(dz != 0.0 if over is None else over, dtype=bool)
    fx = eq.mass * dz[3] / dt if over[3] else 0.0
    fy = eq.mass * dz[4] / dt if over[4] else 0.0
    torque = (eq.inertia * dz[5] / dt if over[5] else 0.0) if eq.rotates else None
    depth = contact_state(eq, z0[None, :])[0][0] if eq.contact else np.zeros(0)
    rx, ry, _ = arms(eq, z0[None, 2])
    touching = np.flatnonzero(depth > 0.0)
    out = {"dt": float(dt), "mass": float(eq.mass), "inertia": float(eq.inertia) if eq.rotates else None,
           "Fx": float(fx) if over[3] else None, "Fy": float(fy) if over[4] else None,
           "torque": float(torque) if torque is not None and over[5] else None,
           "points": [{"point": int(j), "arm": [float(rx[0, j]), float(ry[0, j])], "depth": float(depth[j])}
                      for j in touching], "torque_reading": None}
    said = [w for w in (_force_words("Fx", fx, "N", over[3]), _force_words("Fy", fy, "N", over[4]),
                        None if torque is None else _force_words("torque", torque, "N m", over[5])) if w]
    if not said:
        out["text"] = ("no force: your velocities agree with the reference's to round-off, only the positions "
                       "differ (the position update)")
        out["none"] = True
        return out
    text = ", ".join(said)
    if torque is not None and over[5] and not (over[3] or over[4]) and touching.size:
        parts = torque_parts(eq, z0)
        out["torque_parts"] = parts
        reading = read_torque(float(torque), parts)
        out["torque_reading"] = reading
        text += (f" with no force beside it: r x Fn {parts['normal']:+.3g} N m, r x Ft {parts['friction']:+.3g} N m"
                 + (f", rolling {parts['rolling']:+.3g} N m" if eq.rolling else "") + " there")
        if reading:
            text += f"; it is {reading['factor']:+g} x {PART_WORDS[reading['part']]}: that torque {reading['how']}"
        out["text"] = text + f" ({_acting_words(touching)})"
        return out
    if touching.size == 1:
        j = int(touching[0])
        text += f" at point {j} (the one point touching)"
        if torque is not None and (over[3] or over[4]):
            lever = float(rx[0, j] * fy - ry[0, j] * fx)
            out.update(torque_of_force=lever, torque_left=float(torque - lever))
            text += f"; r x F there is {lever:+.3g} N m, {torque - lever:+.3g} N m of torque left over"
    elif touching.size:
        text += (" shared by points " + ", ".join(map(str, touching))
                 + " (touching; one step does not split it between them)")
    else:
        text += " with no point touching"
    out["text"] = text
    return out


def force_clause(force: dict) -> str:
    """'a force of Fx +1 N at point 0 ...', or 'no force: ...' where the velocities agree."""
    return force["text"] if force.get("none") else f"a force of {force['text']}"


def _acting_words(touching) -> str:
    return (f"point {touching[0]} touching" if len(touching) == 1
            else "points " + ", ".join(map(str, touching)) + " touching")


def _split_nonfinite(states, bad: int | None):
    """(the finite states before state `bad`, the step into it as (z0, z1) or None)."""
    if bad is None:
        return states, None
    return states[:bad], (states[bad - 1], states[bad])


def _explains(m: Mistake, scene, states, integrator, dt, screen, input_rtol=0.0, tail=None) -> dict:
    """The variant's residual over each set of screened steps in turn, then (if it survives)
    over the whole trajectory: steps_off of steps leave round-off (tail: the step into a
    non-finite state, (z0, z1), off unless the variant's step is not finite either)."""
    eq = m.equations(scene)
    method = m.integrator(integrator)
    for rows in screen:
        z0, z1 = states[rows], states[rows + 1]
        mine, bound, solved = one_step(eq, z0, dt, method, m.law, input_rtol)
        # a screened step off by more than round-off rules the variant out (where implicit
        # Euler has no root the jump test decides, on the whole trajectory below)
        rooted = np.ones(len(rows), dtype=bool) if solved is None else solved
        if not np.all(np.abs(mine - z1)[rooted] <= bound[rooted]):
            return {**_entry(m), "explains": False, "screened_out": True}
    res = step_residuals(eq, states, method, dt, m.law, input_rtol)
    over = res.over.any(axis=1)
    steps_off, steps = int(over.sum()), int(over.size)
    if tail is not None:
        steps += 1
        if np.all(np.isfinite(one_step(eq, tail[0], dt, method, m.law, input_rtol)[0])):
            steps_off += 1          # the variant's step is finite: the blow-up is not its
    first = int(np.argmax(over)) if over.any() else (steps - 1 if steps_off else None)
    return {**_entry(m), "explains": steps_off == 0, "steps_off": steps_off, "steps": steps,
            "first_step": None if first is None else first + 1,
            "ratio_max": float(min(res.ratio().max(), 1e300)) if over.size else 0.0,
            "position_error_max": float(np.hypot(res.residual[:, 0], res.residual[:, 1]).max())
            if over.size else 0.0}


def explains_trajectory(name: str, scene, states, integrator: str, dt: float,
                        input_rtol: float = 0.0) -> dict:
    """Every step of the trajectory states (steps + 1, 6) against the variant `name` (a
    catalogued mistake or a pair "a + b"): its entry as diagnose's "mistakes" (explains,
    steps_off of steps, first_step, ratio_max), nothing screened."""
    states = np.asarray(states, dtype=float)
    bad = np.flatnonzero(~np.all(np.isfinite(states), axis=1))
    states, tail = _split_nonfinite(states, int(bad[0]) if bad.size and bad[0] > 0 else None)
    return _explains(candidate(name), scene, states, integrator, dt, (), input_rtol, tail)


def _near_misses(tried: list[dict]) -> list[dict]:
    """The variants stepped over the whole trajectory that explain all steps but some: fewest
    steps off first."""
    near = [t for t in tried if not t["explains"] and not t.get("screened_out") and t.get("steps_off")]
    return sorted(near, key=lambda t: t["steps_off"])


def not_named_text(near: list[dict], where: str = "", most: int = 3) -> str:
    """'a explains all but N of M steps; not named' for the first `most` near misses."""
    return "; ".join(f"{t['name']} explains all but {t['steps_off']} of {t['steps']} steps{where}; not named"
                     for t in near[:most])


def diagnose(scene, states, integrator: str, dt: float, input_rtol: float = 0.0, step_row=None) -> dict:
    """Which catalogued mistake (or pair) explains a trajectory that fails check `step`.

    Returns {"step": the step CheckRow, "explained_by": [names], "mistakes": [per
    variant tried: name, seed_line, description, explains, steps_off, steps, first_step,
    ratio_max], "not_named": [the variants that explain all steps but steps_off],
    "force": the first failing step's velocity residual as a force (force_difference), or
    None, "verdict": one line}. A variant explains the trajectory only when it explains every
    step, the step into a non-finite state included. Variants are tried one at a time; pairs
    only when no single one explains. step_row: the step check's row of these states, when the
    caller has it (a scenario's run), else computed here."""
    states = np.asarray(states, dtype=float)
    row = step_row if step_row is not None else check_step(scene, states, integrator, dt, input_rtol=input_rtol)
    out = {"step": row, "explained_by": [], "mistakes": [], "not_named": [], "force": None}
    if row.passed is None:
        out["verdict"] = f"not diagnosed: {row.reason}"
        return out
    if row.passed:
        out["verdict"] = "every step agrees with the reference step to round-off: no mistake to explain"
        return out
    states, tail = _split_nonfinite(states, row.details.get("nonfinite_step"))
    if states.shape[0] < 2:
        out["verdict"] = f"not diagnosed: {row.reason}"
        return out
    eq = Equations.from_scene(scene)
    res = step_residuals(eq, states, integrator, dt, input_rtol=input_rtol)
    failing = np.flatnonzero(res.over.any(axis=1))
    if failing.size:
        i = int(failing[0])
        ref = one_step(eq, states[i], dt, integrator, rtol=input_rtol)[0][0]
        dz = states[i + 1] - ref
        off = ", ".join(f"{c} {dz[k]:+.3g} {UNIT_OF[c]}" for k, c in enumerate(COMPONENTS) if res.over[i, k])
        out["force"] = {"where": f"step {i + 1}", "step": i + 1, "time": float((i + 1) * dt), "off": off,
                        **force_difference(eq, states[i], dz, dt, res.over[i])}
    spread = np.linspace(0, states.shape[0] - 2, SCREEN_STEPS // 2).astype(int)
    screen = (failing[:FIRST_SCREEN],
              np.unique(np.concatenate([failing[:SCREEN_STEPS // 2], spread])))
    singles, pairs = _candidates(scene, integrator)
    tried = [_explains(m, scene, states, integrator, dt, screen, input_rtol, tail) for m in singles]
    found = [t["name"] for t in tried if t["explains"]]
    near = _near_misses(tried)
    if not found:
        tried_pairs = [_explains(m, scene, states, integrator, dt, screen, input_rtol, tail) for m in pairs]
        found = [t["name"] for t in tried_pairs if t["explains"]]
        tried += [t for t in tried_pairs if t["explains"]]
        if not found and not near:
            near = _near_misses(tried_pairs)
            tried += near
    out["mistakes"] = tried
    out["explained_by"] = found
    out["not_named"] = [] if found else near
    out["verdict"] = _verdict(row, found, out["not_named"])
    return out


def _seed_lines(names):
    lines = []
    for name in names:
        for part in name.split(" + "):
            lines.append(f"{part} ({BY_NAME[part].seed_line})")
    return "; ".join(lines)


def _verdict(row: CheckRow, found, near=()) -> str:
    """near (the partial matches) is kept in the dict, never printed: it points the wrong way."""
    where = first_failure(row)
    if not found:
        return f"{where}; no catalogued mistake (nor pair) explains it to round-off: {largest_residual(row)}"
    if len(found) == 1:
        return f"{where}; explained by {_seed_lines(found)}"
    return f"{where}; explained equally by each of: {_seed_lines(found)}"


# ---------------------------------------------------------------------------------------
# A user's step function, called from chosen moments


# An effect is probed only where it changes one step by at least ACTIVE_ROUNDOFFS round-offs
# of the velocity, eps (|v| + g dt) (what one_step's STATE_ULPS bound scales with): a mistake
# that changes the effect by a millionth of itself still shows above round-off there.
ACTIVE_ROUNDOFFS = 1e6
EPS = np.finfo(float).eps
# A body at rest carries its weight on the ground: the contact force within this fraction of
# m g (the turning point of a bounce is as slow, but carries many times its weight).
RESTING_LOAD = 0.5


def least_acting_force(eq: Equations, states, dt: float):
    """(N,) N: the least force that changes one step from each state by ACTIVE_ROUNDOFFS
    round-offs of its velocity (a smaller one acts at round-off: it proves nothing)."""
    states = np.atleast_2d(states)
    speed = np.hypot(states[:, 3], states[:, 4])
    return ACTIVE_ROUNDOFFS * EPS * (speed + eq.g * dt) * eq.mass / dt


def carries_weight(eq: Equations, fn):
    """(N,) bool: the total normal force fn (N, n) N balances the weight m g to RESTING_LOAD."""
    weight = eq.mass * eq.g
    return (weight > 0.0) & (np.abs(fn.sum(axis=1) - weight) <= RESTING_LOAD * weight)


def damper_leaving(eq: Equations, depth, vcy):
    """The size (N) of the damper's pull-back at a point leaving the ground (vc_y > 0): c vc_y
    for the c-families, k d D vc_y for Hunt-Crossley (before any clamp at zero)."""
    if eq.law == "hunt_crossley":
        return eq.k * depth * eq.dissipation * vcy
    return eq.c * vcy


def rebound_score(eq: Equations, depth, vcy, loaded, least):
    """(N,) N: at each state, the largest difference the damping law makes at a touching point
    leaving the ground under load (vc_y > 0): min(damper, k d) (damper_leaving), which
    compression-only damping (k d), linear damping (max(0, k d - c vc_y)), an unclamped damper
    (k d - c vc_y) and Hunt-Crossley tell apart; -1 where no point leaves under load, the
    difference is below `least` (N,) N (see least_acting_force) or the scene has no damper."""
    damped = eq.dissipation > 0.0 if eq.law == "hunt_crossley" else eq.c > 0.0
    if not eq.contact or not damped:
        return np.full(depth.shape[0], -1.0)
    differ = np.minimum(damper_leaving(eq, depth, vcy), eq.k * depth)
    leaving = loaded & (vcy > 0.0) & (differ > np.asarray(least)[:, None])
    score = np.where(leaving, differ, -1.0)
    return score.max(axis=1) if score.shape[1] else np.full(depth.shape[0], -1.0)


def pick_moments(scene, states) -> list[tuple[str, np.ndarray]]:
    """Named states of a trajectory (T, 6) where mistakes show, each only where the effect it
    probes acts: in flight (moving or under gravity), at touchdown (the first state after a
    flight with a contact force above round-off), a rebound (a loaded point leaving the ground:
    the damping law), a sliding contact (slip beyond 1/alpha under a normal load), rolling (the
    circle, under load) and resting (the last state, if slow and loaded). Moments the motion
    never reaches are left out."""
    states = np.asarray(states, dtype=float)
    eq = Equations.from_scene(scene)
    depth, vcy, slip, fn = contact_loads(eq, states)
    touching = depth > 0.0
    least = least_acting_force(eq, states, scene.dt)
    loaded = touching & (fn > least[:, None])
    any_touch, any_load = touching.any(axis=1), loaded.any(axis=1)
    band = eq.slip_band if eq.friction else np.inf
    speed = np.hypot(states[:, 3], states[:, 4]) + np.abs(states[:, 5])
    moments = []

    def add(name, mask):
        idx = np.flatnonzero(mask)
        if idx.size:
            moments.append((name, states[idx[idx.size // 2]].copy()))
    add("in flight", ~any_touch & ((speed > 0) | (eq.g > 0)))
    if eq.contact:
        flight = np.flatnonzero(~any_touch)
        down = np.flatnonzero(any_load & (np.arange(len(states)) > flight[0])) if flight.size else flight
        if down.size:
            moments.append(("touchdown", states[down[0]].copy()))
        score = rebound_score(eq, depth, vcy, loaded, least)
        if score.max(initial=-1.0) > 0.0:
            moments.append(("rebound", states[int(np.argmax(score))].copy()))
        sliding = (loaded & (np.abs(slip) > band)).any(axis=1)
        circle = eq.rotates and not eq.turning
        if circle:
            rolling = any_load & (np.abs(slip[:, 0]) <= band) & (np.abs(states[:, 5]) * abs(eq.points[0][1]) > band)
            add("rolling", rolling)
        add("sliding contact", sliding)
        if any_load[-1] and speed[-1] < 10 * band and carries_weight(eq, fn[-1:])[0]:
            moments.append(("resting", states[-1].copy()))
    return moments


def _compare(z1_user, z1, bound):
    r = np.abs(z1_user - z1)
    agree = bool(np.all(r <= bound))
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(r == 0.0, 0.0, r / bound)
    return agree, r, ratio


def off_text(entry: dict) -> str:
    """A disagreeing moment's components off round-off, signed (your step minus the
    reference's): 'vx +0.00051 m/s, vy -0.00102 m/s'."""
    d, ratio = entry["difference"], entry["ratios"]
    return ", ".join(f"{c} {d[c]:+.3g} {UNIT_OF[c]}" for c in COMPONENTS if ratio[c] > 1.0)


def diagnose_step(step_fn, scene, moments, integrator: str | None = None, dt: float | None = None,
                  scene_dict: dict | None = None, also=()) -> dict:
    """Call a user's step f(state, scene_dict, dt) -> state from each named moment (a list of
    (name, state) or a dict) and compare with the reference step and each variant's.

    Returns {"moments": [{name, state, phase, agrees, component, residual |your step - the
    reference's| and difference (signed) per component, ratios (residual / round-off),
    ratio_max, explained_by, force (disagreeing moments: force_difference)}], "disagree":
    [moment names], "steps": how many moments were probed, "explained_by": [mistakes that
    reproduce the user's step at every moment], "mistakes": [{name, reproduces, of, not_at}:
    every single mistake reproducing at least one disagreeing moment, the explaining pairs and
    those named in `also`], "not_named": [the singles reproducing some but not all moments],
    "force": the first disagreeing moment's force, "verdict": one line}."""
    integrator = integrator or scene.integrator
    dt = float(dt or scene.dt)
    if scene_dict is None:
        scene_dict = dataclasses.asdict(scene)
    items = list(moments.items()) if isinstance(moments, dict) else list(moments)
    eq = Equations.from_scene(scene)
    out = {"moments": [], "disagree": [], "steps": len(items), "explained_by": [], "mistakes": [],
           "not_named": [], "force": None}
    if integrator not in METHODS:
        out["verdict"] = f"integrator {integrator!r} is not one the harness can step: not diagnosed"
        return out
    if not items:
        out["verdict"] = "no moment of the run probes an effect: not diagnosed"
        return out
    singles, pairs = _candidates(scene, integrator)
    Z = np.array([np.asarray(s, dtype=float) for _, s in items])
    user = np.array([np.asarray(step_fn(z.copy(), scene_dict, dt), dtype=float).reshape(6) for z in Z])
    ref, bound, _ = one_step(eq, Z, dt, integrator)
    variants = {}
    for m in singles + pairs:
        z1, b, _ = m.step(scene, Z, dt, integrator)
        variants[m.name] = (np.all(np.abs(user - z1) <= b, axis=1), m)
    for k, (name, _) in enumerate(items):
        agree, r, ratio = _compare(user[k], ref[k], bound[k])
        entry = {"name": name, "state": [float(v) for v in Z[k]], "phase": phase(eq, Z[k], ref[k]),
                 "agrees": agree, "residual": {c: float(v) for c, v in zip(COMPONENTS, r)},
                 "difference": {c: float(v) for c, v in zip(COMPONENTS, user[k] - ref[k])},
                 "ratios": {c: float(min(v, 1e300)) for c, v in zip(COMPONENTS, ratio)},
                 "ratio_max": float(min(ratio.max(), 1e300)), "component": None, "explained_by": []}
        if not agree:
            entry["component"] = COMPONENTS[int(np.argmax(ratio))]
            entry["explained_by"] = [n for n, (ok, m) in variants.items() if ok[k] and " + " not in n]
            entry["force"] = force_difference(eq, Z[k], user[k] - ref[k], dt, ratio > 1.0)
            out["disagree"].append(name)
        out["moments"].append(entry)
    names = [n for n, _ in items]
    off = np.array([not e["agrees"] for e in out["moments"]])
    everywhere = [n for n, (ok, m) in variants.items() if ok.all() and " + " not in n]
    if not everywhere:
        everywhere = [n for n, (ok, m) in variants.items() if ok.all()]
    out["mistakes"] = [{"name": n, "reproduces": int(ok.sum()), "of": len(items),
                        "not_at": [names[k] for k in np.flatnonzero(~ok)]}
                       for n, (ok, m) in variants.items()
                       if n in also or n in everywhere or (" + " not in n and (ok & off).any())]
    if not out["disagree"]:
        out["verdict"] = "the step agrees with the reference step at every moment, to round-off"
        return out
    first = next(e for e in out["moments"] if not e["agrees"])
    out["force"] = {"where": first["name"], "off": off_text(first), **first["force"]}
    out["explained_by"] = everywhere
    where = ", ".join(f"{e['name']} ({e['component']})" for e in out["moments"] if not e["agrees"])
    out["where"] = where
    if everywhere:
        out["verdict"] = f"disagrees at {where}; reproduced at every moment by {_seed_lines(everywhere)}"
        return out
    near = sorted((x for x in out["mistakes"] if " + " not in x["name"] and x["reproduces"] < x["of"]),
                  key=lambda x: x["of"] - x["reproduces"])
    out["not_named"] = [{"name": x["name"], "steps_off": x["of"] - x["reproduces"], "steps": x["of"],
                         "not_at": x["not_at"]} for x in near]
    out["verdict"] = (f"disagrees at {where}; no catalogued mistake (nor pair) explains every moment to "
                      f"round-off: at {first['name']} your step is off by {off_text(first)}: "
                      f"{force_clause(first['force'])}")
    return out
