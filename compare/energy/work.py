"""The dissipated work of each step, by the rule of the integrator that took it (docs/energy-balance.md)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from compare.oracle.rigid_body import RigidBody
from scene_types import Scene

from .law import accelerations, dissipated_power, loads

# What each rule integrates: the dissipative load the step applied, on the displacement it applied.
RULES = {
    "explicit_euler": "explicit Euler's rule: the load at (q0, v0) on the displacement h v0",
    "semi_implicit_euler": "semi-implicit Euler's rule: the load at (q0, v0) on the displacement h v1",
    "implicit_euler": "implicit Euler's rule: the load at (q1, v1) on the displacement h v1 "
                      "(a touchdown jump's point at its Filippov share, a bare sign law at the value "
                      "the step applied)",
    "rk4": "RK4's rule: h/6 (P1 + 2 P2 + 2 P3 + P4), each stage's load on that stage's velocity",
    "trapezoid": "the trapezoid rule on the dissipated power at the recorded states "
                 "(integrator unknown; its error bound is quadrature_bound)",
}
# m: a point this close to the ground at the end of an implicit Euler step sits on a touchdown
# jump (custom_sim's jump step lands within h times its Newton tolerance, 1e-10 m/s, so below
# 1e-13 m at any dt <= 1e-3 s, plus the round-off eps (|y| + |r|) ~ 1e-16 m of the depth): ten
# times that, and far below the depth h |v_n| of any resolved step into the ground
FILIPPOV_DEPTH = 1e-12
# m/s, rad/s: above this, v1 - v0 - h a(q1, v1) says the step did not apply the plain law:
# ten times custom_sim's Newton residual tolerance (1e-10), far below the jump h c |v_n| / m
IMPLICIT_RESIDUAL = 1e-9


@dataclass(frozen=True)
class StepWork:
    """Work (steps, 3) J of each step against damping, friction, rolling; the rule's name;
    step_mismatch (6,): the largest difference per state component between the recorded
    step and the named integrator's step under the scene's law (nan for the trapezoid; above
    round-off the states were not taken by that rule); jump_steps: implicit Euler steps
    counted at a Filippov share; selected_steps: implicit Euler steps where a bare sign law
    applied a value of its set (left out of step_mismatch); quadrature_bound J: the
    trapezoid's error bound (0 else)."""

    work: np.ndarray
    rule: str
    step_mismatch: np.ndarray
    jump_steps: int = 0
    quadrature_bound: float = 0.0
    selected_steps: int = 0


def _velocity_power(scene, rb, Z, U=None, share=None):
    """(dissipated power (N, 3) W, accelerations (N, 3)) of the loads at Z moving at U."""
    ld = loads(scene, rb, Z, share)
    return dissipated_power(ld, Z[:, 3:] if U is None else U), accelerations(scene, rb, Z, ld)


def step_work(scene: Scene, rb: RigidBody, h: np.ndarray, Z: np.ndarray, integrator: str | None) -> StepWork:
    """The work of each step of the trajectory Z (T, 6) with steps h (T - 1,) s, taken by
    `integrator` (explicit_euler, semi_implicit_euler, implicit_euler, rk4; None or any other
    name: the trapezoid rule)."""
    h = np.asarray(h, dtype=float).reshape(-1, 1)
    Z0, Z1 = Z[:-1], Z[1:]
    if integrator in ("explicit_euler", "semi_implicit_euler"):
        semi = integrator == "semi_implicit_euler"
        power, a = _velocity_power(scene, rb, Z0, Z1[:, 3:] if semi else None)
        v1 = Z0[:, 3:] + h * a
        q1 = Z0[:, :3] + h * (v1 if semi else Z0[:, 3:])
        return StepWork(h * power, RULES[integrator], _mismatch(np.hstack([q1, v1]), Z1))
    if integrator == "implicit_euler":
        return _implicit(scene, rb, h, Z0, Z1)
    if integrator == "rk4":
        return _rk4(scene, rb, h, Z0, Z1)
    p = _velocity_power(scene, rb, Z)[0]
    bound = float((0.5 * h * np.abs(np.diff(p, axis=0)).sum(axis=1, keepdims=True)).sum())
    return StepWork(0.5 * h * (p[:-1] + p[1:]), RULES["trapezoid"], np.full(6, np.nan),
                    quadrature_bound=bound)


def _mismatch(computed: np.ndarray, recorded: np.ndarray) -> np.ndarray:
    return np.abs(computed - recorded).max(axis=0) if len(recorded) else np.zeros(6)


def _rk4(scene, rb, h, Z0, Z1) -> StepWork:
    """Stages recomputed under the law: z_s = z0 + c_s h k_{s-1}, c = (1/2, 1/2, 1)."""
    total_power = np.zeros((len(Z0), 3))
    slope = np.zeros_like(Z0)
    zs = Z0
    for weight, c_next in ((1.0, 0.5), (2.0, 0.5), (2.0, 1.0), (1.0, None)):
        power, a = _velocity_power(scene, rb, zs)
        k = np.hstack([zs[:, 3:], a])
        total_power += weight * power
        slope += weight * k
        if c_next is not None:
            zs = Z0 + c_next * h * k
    z1 = Z0 + h / 6.0 * slope
    return StepWork(h / 6.0 * total_power, RULES["rk4"], _mismatch(z1, Z1))


def _implicit(scene, rb, h, Z0, Z1) -> StepWork:
    """The load at the end of each step. Where the step stopped a point on the ground with a
    residual the plain law leaves (a touchdown jump), that point's share lam in [0, 1] is the
    one that makes v1 - v0 = h (a_others + lam a_point), fitted in the mass metric. Where a
    bare sign law (friction or rolling) leaves a residual still, the step applied a value of
    its set (custom_sim: Newton's end point at the kink): that force, M (v1 - v0) / h less the
    law's, is the sign law's too, and its work on h v1 goes to that column."""
    ld = loads(scene, rb, Z1)
    share = (ld.d > 0.0).astype(float)
    residual = Z1[:, 3:] - Z0[:, 3:] - h * accelerations(scene, rb, Z1, ld)
    jumps = np.flatnonzero((np.abs(residual).max(axis=1) > IMPLICIT_RESIDUAL)
                           & (np.abs(ld.d).min(axis=1) <= FILIPPOV_DEPTH))
    metric = np.array([rb.mass, rb.mass, rb.inertia if rb.rotates else 0.0])
    for i in jumps:
        j = int(np.argmin(np.abs(ld.d[i])))
        z = Z1[i:i + 1]
        whole = np.zeros((1, share.shape[1]))
        whole[0, j] = 1.0
        a_point = accelerations(scene, rb, z, loads(scene, rb, z, whole))
        a_point -= accelerations(scene, rb, z, loads(scene, rb, z, np.zeros_like(whole)))  # gravity out
        target = residual[i] / h[i, 0] + share[i, j] * a_point[0]   # what the point must supply
        norm = float((metric * a_point[0] ** 2).sum())
        if norm > 0.0:
            share[i, j] = float(np.clip((metric * target * a_point[0]).sum() / norm, 0.0, 1.0))
    ld = loads(scene, rb, Z1, share)
    work = h * dissipated_power(ld, Z1[:, 3:])
    v_mismatch = Z1[:, 3:] - Z0[:, 3:] - h * accelerations(scene, rb, Z1, ld)
    q_mismatch = Z1[:, :3] - Z0[:, :3] - h * Z1[:, 3:]
    column = set_valued_column(scene, rb)
    selected = np.abs(v_mismatch).max(axis=1) > IMPLICIT_RESIDUAL if column is not None else np.zeros(len(Z0), bool)
    if np.any(selected):
        work[selected, column] -= (metric * v_mismatch[selected] * Z1[selected, 3:]).sum(axis=1)
        v_mismatch[selected] = 0.0
    mismatch = np.abs(np.hstack([q_mismatch, v_mismatch])).max(axis=0) if len(Z0) else np.zeros(6)
    return StepWork(work, RULES["implicit_euler"], mismatch, jump_steps=len(jumps),
                    selected_steps=int(selected.sum()))


def set_valued_column(scene: Scene, rb: RigidBody) -> int | None:
    """The work column (1 friction, 2 rolling) of the scene's bare sign law, None without one."""
    if scene.has("contact") and scene.has("friction") and scene.contact.friction_law == "sign":
        return 1
    if scene.has("contact") and scene.has("rolling_friction") and rb.rotates and scene.contact.roll_law == "sign":
        return 2
    return None
