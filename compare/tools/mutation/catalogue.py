"""Typical mistakes of a hand-written contact simulator, each an edit of custom_sim's source.

Each mistake is one exact text replacement in one file of custom_sim (every occurrence, so a
line the force law and its Jacobian share changes in both). `python -m compare tools mutation` puts
each into a copy of custom_sim and runs the default `run` on it: the harness earns trust only
if every one of them makes `run` exit 1, named by the check that caught it. A mistake the
diagnosis also knows (compare/diagnosis/mistakes.py) has the same name and seed line there.
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Mistake:
    name: str
    what: str          # the mistake, as a student would make it
    seed_line: str     # where in the seed's algorithms it belongs
    file: str          # in custom_sim/
    old: str           # exact text (must occur)
    new: str


MISTAKES = (
    Mistake("box_inertia_about_corner", "box inertia m (w^2 + h^2) / 3, the formula about a corner instead of the centre",
            "Rigid body model: I = 1/12 m (w^2 + h^2)", "bodies.py",
            "mass * (w * w + h * h) / 12.0", "mass * (w * w + h * h) / 3.0"),
    Mistake("box_inertia_width_only", "box inertia m w^2 / 12, the height left out",
            "Rigid body model: I = 1/12 m (w^2 + h^2)", "bodies.py",
            "mass * (w * w + h * h) / 12.0", "mass * (w * w) / 12.0"),
    Mistake("disk_inertia_of_a_ring", "disk inertia m R^2 (a ring's) instead of m R^2 / 2",
            "MuJoCo configuration / Algorithm 4: disk I = 0.5 m R^2", "bodies.py",
            "0.5 * mass * radius * radius", "mass * radius * radius"),
    Mistake("unit_mass", "the mass left out of F / m: every body moves as if it weighed 1 kg",
            "Algorithm 1, line 7: v <- v + (F / m) dt", "model.py",
            "inv_mass=1.0 / props.mass,", "inv_mass=1.0,"),
    Mistake("gravity_without_mass", "gravity added as a force g instead of m g",
            "Algorithm 2, line 3: F <- [0, -m g]", "forces.py",
            "fy -= model.g / model.inv_mass", "fy -= model.g"),
    Mistake("friction_on_com_velocity", "friction from the centre of mass's velocity, not the contact point's",
            "Algorithm 2, line 8: v_i <- v + omega [-r_iy, r_ix]", "forces.py",
            "slip_sign(model, vx - om * ry)", "slip_sign(model, vx)"),
    Mistake("normal_velocity_of_com", "the normal damping from the centre of mass's vertical velocity",
            "Algorithm 2, line 8: v_i <- v + omega [-r_iy, r_ix]", "forces.py",
            "fn = normal_force(model, d, vy + om * rx)", "fn = normal_force(model, d, vy)"),
    Mistake("torque_sign", "the friction torque with the wrong sign: r x F taken as r_x F_y + r_y F_x",
            "Algorithm 2, line 11: tau <- tau + r_i x F_i", "forces.py",
            "tau += rx * fn - ry * ft", "tau += rx * fn + ry * ft"),
    Mistake("corners_not_rotated", "contact points left in the body frame: never turned by R(theta)",
            "Algorithm 2, line 5: r_i <- R(theta) c_i^local", "forces.py",
            "rx, ry = cs * lx - sn * ly, sn * lx + cs * ly", "rx, ry = lx, ly"),
    Mistake("rotation_transposed", "R(theta) transposed: the corners turn clockwise",
            "Algorithm 2, line 5: r_i <- R(theta) c_i^local", "forces.py",
            "rx, ry = cs * lx - sn * ly, sn * lx + cs * ly", "rx, ry = cs * lx + sn * ly, -sn * lx + cs * ly"),
    Mistake("contact_one_millimetre_early", "contact tested against y < 1 mm instead of y < 0",
            "Algorithm 2, line 7: if c_i,y < 0", "forces.py",
            "d = -(z[1] + ry)\n            if d <= 0.0:", "d = -(z[1] + ry) + 1e-3\n            if d <= 0.0:"),
    Mistake("damping_both_ways_unclamped", "the compression law's damping applied both ways (k d - c v_y, pulling the body down)",
            "Algorithm 1, line 4: Fn <- k d + c max(0, -v_y)", "forces.py",
            "return model.k * d + model.c * max(0.0, -vcy)", "return model.k * d - model.c * vcy"),
    Mistake("explicit_euler_in_disguise", "semi-implicit Euler that moves the position with the old velocity",
            "Algorithm 1, lines 7-8: v <- v + (F/m) dt, then p <- p + v dt", "integrators.py",
            "        vx += h * ax\n        vy += h * ay\n        om += h * aw\n"
            "        x += h * vx\n        y += h * vy\n        theta += h * om\n    else:",
            "        x += h * vx\n        y += h * vy\n        theta += h * om\n"
            "        vx += h * ax\n        vy += h * ay\n        om += h * aw\n    else:"),
    Mistake("rk4_wrong_node", "RK4 whose third stage is taken at the half step from k3 instead of the full step",
            "Numerical integration: RK4", "integrators.py",
            "ch = (1.0 if s == 2 else 0.5) * h", "ch = 0.5 * h"),
    Mistake("implicit_euler_old_positions", "implicit Euler that evaluates the force at the old positions q0",
            "Numerical integration: implicit Euler, v1 = v0 + a(q1, v1) dt", "implicit_residual.py",
            "zi[j] = z0[j] + h * zi[3 + j]", "zi[j] = z0[j]"),
    Mistake("compound_inertia_without_parallel_axis", "compound inertia without the parallel-axis term m |o - com|^2",
            "Algorithm 3, line 2: compute total mass, COM offset, inertia about COM", "bodies.py",
            "inertia += box_inertia(p.mass, w, h) + p.mass * float(rel @ rel)",
            "inertia += box_inertia(p.mass, w, h)"),
    Mistake("compound_geometric_centre", "the compound's centre of mass taken as the parts' geometric mean",
            "Algorithm 3, line 2: compute total mass, COM offset", "bodies.py",
            "com = masses @ offsets / masses.sum()", "com = offsets.mean(axis=0)"),
    Mistake("contact_height_ignored", "the point mass touches the ground at its centre, not at y < h",
            "Algorithm 1, line 3: d <- max(0, h - y)", "bodies.py",
            'pts = np.array([[0.0, -body.of_shape("contact_height")]])', "pts = np.array([[0.0, 0.0]])"),
    Mistake("disk_contact_point_turns", "the disk's contact point turns with the disk instead of staying below the centre",
            "Algorithm 4, line 3: r <- [0, -R]", "bodies.py",
            "np.array([[0.0, -R]]),\n                              rotates=True, points_rotate=False)",
            "np.array([[0.0, -R]]),\n                              rotates=True, points_rotate=True)"),
    Mistake("rolling_resistance_pushes", "rolling resistance with the wrong sign: it speeds the disk up",
            "Algorithm 4, line 9: tau <- tau + r x F - mu_roll Fn sign(omega)", "forces.py",
            "            if model.rolling:\n                tau -= roll",
            "            if model.rolling:\n                tau += roll"),
)
