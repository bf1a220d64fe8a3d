"""The balance of MuJoCo's runs: the dynamics twin under the scene's law, the native twin from its constraint forces."""
from __future__ import annotations

import dataclasses

import mujoco
import numpy as np

from mujoco_models.dynamics import simulate_dynamics
from scene_types.integrators import MUJOCO_TWIN, SAME_UPDATE
from mujoco_models.frames import joint_count, states_from_q
from mujoco_models.spec import compiled_twin
from scene_types import Scene

from .balance import Balance, balance
from .law import arms, body_of
from .terms import energy_terms

NATIVE_RULES = {
    "Euler": "MuJoCo's native contact, Euler: each constraint row's force (computed at the step's start, "
             "as the step applied it) on the row's displacement h J v1",
    "RK4": "MuJoCo's native contact, RK4: h/6 (P1 + 2 P2 + 2 P3 + P4), P_s = -f_s . J_s v_s of each stage "
           "recomputed by mj_forward",
}
SPRING_RULES = {
    True: "; the normal rows' spring k d (the penalty mapping's, d MuJoCo's depth) is stored in "
          "sum k d^2 / 2 and left out of damping",
    False: "; this mapping's spring is not the scene's k, so the normal rows' whole work is counted, "
           "less the change of sum k d^2 / 2: R is the step's kinetic-energy defect",
}
# MuJoCo's implicit integrators differ from its Euler only in the passive damping they treat
# implicitly; a twin has none (no joint damping, springs or fluid), so they take Euler's step
RK4_A = (0.5, 0.5, 1.0)             # each stage's offset from the step's start, in h
RK4_B = (1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0)


def dynamics_balance(scene: Scene, integrator: str = "Euler", dt: float | None = None) -> Balance:
    """The balance of the dynamics twin (the scene's law through MuJoCo's passive callback),
    W by the rule of the custom_sim integrator that takes MuJoCo's update (Euler:
    semi-implicit Euler; RK4: rk4), the law evaluated on MuJoCo's states."""
    integrator = MUJOCO_TWIN.get(integrator, integrator)
    traj = simulate_dynamics(scene, integrator, dt)
    return balance(dataclasses.replace(scene, dt=traj.dt), traj.t, traj.states(), SAME_UPDATE[integrator])


CONTACT_ROWS = (mujoco.mjtConstraint.mjCNSTR_CONTACT_FRICTIONLESS, mujoco.mjtConstraint.mjCNSTR_CONTACT_PYRAMIDAL,
                mujoco.mjtConstraint.mjCNSTR_CONTACT_ELLIPTIC)


def _depths(data) -> np.ndarray:
    """MuJoCo's depth (m, > 0) of each current contact."""
    return np.maximum(0.0, -data.contact.dist[:data.ncon])


def _row_power(model, data, qvel: np.ndarray, spring: float) -> np.ndarray:
    """Power (3,) W that MuJoCo's current constraint forces take from the body moving at qvel,
    split by row: [normal rows less a spring spring * depth per contact (N/m; 0: none),
    sliding friction, torsional and rolling]. An elliptic contact's rows are normal, two
    sliding, then torsional and rolling; a pyramidal contact's are pairs of edges
    J_n +- mu_k J_k, whose mean is the normal's row J_n. A row of no contact (none in a twin)
    counts as normal."""
    nefc = data.nefc
    if nefc == 0:
        return np.zeros(3)
    if mujoco.mj_isSparse(model):
        J = np.zeros((nefc, model.nv))
        mujoco.mju_sparse2dense(J, data.efc_J, data.efc_J_rownnz, data.efc_J_rowadr, data.efc_J_colind)
    else:
        J = data.efc_J[:nefc * model.nv].reshape(nefc, model.nv)
    rate, force = J @ qvel, data.efc_force[:nefc]
    contact = np.isin(data.efc_type[:nefc], CONTACT_ROWS)
    first = np.where(contact, data.contact.efc_address[np.where(contact, data.efc_id[:nefc], 0)], np.arange(nefc))
    offset = np.arange(nefc) - first
    normal = rate[first]
    if model.opt.cone == mujoco.mjtCone.mjCONE_PYRAMIDAL:
        edges = contact & (data.efc_type[:nefc] == mujoco.mjtConstraint.mjCNSTR_CONTACT_PYRAMIDAL)
        normal = np.where(edges, 0.5 * (rate[first] + rate[np.minimum(first + 1, nefc - 1)]), normal)
        offset = np.where(edges, offset // 2, offset)
        kind = np.where(edges, np.where(offset < 2, 1, 2), 0)
    else:
        kind = np.where(offset == 0, 0, np.where(offset < 3, 1, 2))
        normal = np.where(offset == 0, rate, 0.0)
    kind = np.where(contact, kind, 0)
    normal = np.where(contact, normal, rate)
    out = np.bincount(kind, weights=-force * (rate - normal), minlength=3)
    out[0] -= float(force @ normal)
    if spring and data.ncon:
        first_rows = data.contact.efc_address[:data.ncon]
        live = first_rows >= 0
        out[0] += spring * float(_depths(data)[live] @ normal[first_rows[live]])
    return out


def _native_steps(model, data, n: int, integrator: str, spring: float):
    """(qpos (n + 1, nq), qvel (n + 1, nv), work (n, 3) J, stored (n + 1,) J: sum k d^2 / 2 of
    MuJoCo's contacts at each state, largest step mismatch) of n mj_steps."""
    h = model.opt.timestep
    qpos, qvel = [data.qpos.copy()], [data.qvel.copy()]
    work, stored = np.zeros((n, 3)), np.zeros(n + 1)
    stage = mujoco.MjData(model) if integrator == "RK4" else None
    k = spring or 0.0
    mismatch = 0.0
    for i in range(n):
        if stage is not None:
            work[i], stored[i], end = _rk4_stage_work(model, data, stage, h, spring)
        mujoco.mj_step(model, data)
        if stage is None:
            # Euler's step: forces at the start, v1 = v0 + h qacc, q1 = q0 + h v1
            work[i] = h * (_row_power(model, data, data.qvel, spring) - _passive(data, data.qvel))
            stored[i] = 0.5 * k * float(np.sum(_depths(data) ** 2))
            end = np.concatenate([qpos[-1] + h * data.qvel, qvel[-1] + h * data.qacc])
        qpos.append(data.qpos.copy())
        qvel.append(data.qvel.copy())
        mismatch = max(mismatch, float(np.max(np.abs(end - np.concatenate([qpos[-1], qvel[-1]])))))
    mujoco.mj_forward(model, data)
    stored[n] = 0.5 * k * float(np.sum(_depths(data) ** 2))
    return np.array(qpos), np.array(qvel), work, stored, mismatch


def _passive(data, qvel) -> np.ndarray:
    """Power (3,) W of MuJoCo's passive forces (none in a twin), counted as damping."""
    return np.array([float(data.qfrc_passive @ qvel), 0.0, 0.0])


def _rk4_stage_work(model, data, stage, h: float, spring: float):
    """(work (3,) J, sum k d^2 / 2 at the start, the step's end state (qpos, qvel)) of MuJoCo's
    RK4 step from data's state, its four stages recomputed in `stage` (slide and hinge joints:
    positions add linearly)."""
    q0, v0 = data.qpos.copy(), data.qvel.copy()
    stage.qacc_warmstart[:] = data.qacc_warmstart
    stage.time = data.time
    q, v = q0, v0
    power, dq, dv = np.zeros(3), np.zeros_like(q0), np.zeros_like(v0)
    stored = 0.0
    for s in range(4):
        stage.qpos[:], stage.qvel[:] = q, v
        mujoco.mj_forward(model, stage)
        if s == 0:
            stored = 0.5 * (spring or 0.0) * float(np.sum(_depths(stage) ** 2))
        power += RK4_B[s] * (_row_power(model, stage, v, spring) - _passive(stage, v))
        dq += RK4_B[s] * v
        dv += RK4_B[s] * stage.qacc
        if s < 3:
            q, v = q0 + RK4_A[s] * h * v, v0 + RK4_A[s] * h * stage.qacc
    return h * power, stored, np.concatenate([q0 + h * dq, v0 + h * dv])


def native_balance(scene: Scene, solref: str | None = None, integrator: str | None = None,
                   dt: float | None = None) -> Balance:
    """The balance of MuJoCo's native twin (its own contact; solref mapping, integrator and dt
    default to the scene's [mujoco] table), stepped here with mj_step. E = kinetic + m g y +
    sum k d^2 / 2 over MuJoCo's contacts (the native rows of the trajectory files); W sums the
    power of each constraint row (normal rows as damping, friction rows, torsional and rolling
    rows) and of MuJoCo's passive forces (none in a twin). Under the penalty mapping MuJoCo's
    normal row is the spring k d plus the damper (to its force error d (A/A_hat - 1)), so the
    spring's work is left to E and R is the integrator's energy error, as custom_sim's; under
    the other mappings the spring is not k, the rows' whole work is counted and R is the Euler
    step's kinetic-energy defect (docs/energy-balance.md)."""
    twin, model = compiled_twin(scene, solref, integrator=integrator, dt=dt)
    name = MUJOCO_TWIN[SAME_UPDATE[twin.integrator]]
    penalty = twin.contact.mapping == "penalty"
    k = scene.contact.k if scene.has("contact") else 0.0
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    n = max(1, int(round(scene.duration / twin.dt)))
    qpos, qvel, work, stored, mismatch = _native_steps(model, data, n, name, k if penalty else 0.0)
    nq = joint_count(twin.props)
    Z = states_from_q(twin.props, qpos[:, :nq], qvel[:, :nq])
    terms = energy_terms(scene, body_of(scene), Z)
    if not penalty:
        stored = terms["contact"]      # not MuJoCo's spring: only shown, and taken out of W again
    E = terms["translation"] + terms["rotation"] + terms["gravity"] + stored
    W = np.vstack([np.zeros((1, 3)), np.cumsum(work, axis=0)])
    if not penalty:
        W[:, 0] -= stored - stored[0]
    t = np.arange(n + 1) * twin.dt
    return Balance(t, E, W, E - E[0] + W.sum(axis=1), NATIVE_RULES[name] + SPRING_RULES[penalty],
                   f"mujoco {twin.integrator}", np.full(6, mismatch))


FROM_STATES_RULES = {
    "Euler": "MuJoCo's native contact, Euler, from its states: the constraint's generalized force "
             "M (v1 - v0) / h + m g (exact for Euler with the hinge at the centre of mass) on the step's "
             "displacement h v1",
    "RK4": "not measured for MuJoCo's RK4 from its states: its four stages' constraint forces are not in "
           "them, and a quadrature in their place would put its own error into R (W shown is the step's mean "
           "constraint force M (v1 - v0) / h + m g on h (v0 + v1) / 2; native_balance steps the stages row by "
           "row, 8 s a scene)",
}
SPLIT_RULE = ("; split by effect at the touching points' mean arm (friction: the horizontal force on the "
              "slip there; rolling: the torque the point forces leave, circle only; damping: the rest)")


def native_from_run(scene: Scene, t: np.ndarray, states: np.ndarray, mujoco_integrator: str,
                    mapping: str) -> Balance:
    """The balance of MuJoCo's native run from its states alone (no stepping again): the twin's
    mass matrix is diag(m, m, I) in our coordinates (its hinge sits at the centre of mass, frames.py)
    and its only smooth force is gravity, so each step's constraint force is what the velocity
    change leaves of them. Under the penalty mapping the spring k d (depths from the states) is
    stored in E and left out of W, as native_balance does row by row."""
    Z = np.atleast_2d(np.asarray(states, dtype=float))
    rb = body_of(scene)
    h = float(t[1] - t[0]) if len(t) > 1 else scene.dt
    terms = energy_terms(scene, rb, Z)
    E = terms["translation"] + terms["rotation"] + terms["gravity"] + terms["contact"]
    n = len(Z) - 1
    W = np.zeros((n + 1, 3))
    name = MUJOCO_TWIN[SAME_UPDATE[mujoco_integrator]]
    if n == 0 or not scene.has("contact"):
        return Balance(np.asarray(t, float), E, W, E - E[0], FROM_STATES_RULES[name], f"mujoco {mujoco_integrator}",
                       np.zeros(6))
    mass = np.array([rb.mass, rb.mass, rb.inertia if rb.rotates else 0.0])
    v0, v1 = Z[:-1, 3:], Z[1:, 3:]
    force = mass * (v1 - v0) / h
    if scene.has("gravity"):
        force[:, 1] += rb.mass * scene.g
    moving = v1 if name == "Euler" else 0.5 * (v0 + v1)
    rx, ry = arms(rb, Z[:-1, 2])
    d = np.maximum(0.0, -(Z[:-1, 1:2] + ry))
    touching = d > 0.0
    count = np.maximum(1, touching.sum(axis=1))
    spring = np.zeros_like(force)
    if mapping == "penalty":
        kd = scene.contact.k * d
        spring[:, 1] = kd.sum(axis=1)
        spring[:, 2] = (rx * kd).sum(axis=1) if rb.rotates else 0.0
    else:   # the spring is not the scene's k: all of the constraint's work, less what E stores
        E = E - terms["contact"]
    rest = force - spring                     # the constraint's dissipative part
    total = -h * np.sum(rest * moving, axis=1)
    x_bar = np.where(touching, rx, 0.0).sum(axis=1) / count
    y_bar = np.where(touching, ry, 0.0).sum(axis=1) / count
    friction = -h * rest[:, 0] * (moving[:, 0] - moving[:, 2] * y_bar)
    rolling = np.zeros(n)
    if scene.has("rolling_friction"):
        torque = rest[:, 2] - (x_bar * rest[:, 1] - y_bar * rest[:, 0])
        rolling = -h * torque * moving[:, 2]
    W[1:] = np.cumsum(np.column_stack([total - friction - rolling, friction, rolling]), axis=0)
    rule = FROM_STATES_RULES[name] + SPLIT_RULE + SPRING_RULES[mapping == "penalty"]
    R = E - E[0] + W.sum(axis=1) if name == "Euler" else np.full(len(E), np.nan)   # RK4: not measured
    return Balance(np.asarray(t, float), E, W, R, rule, f"mujoco {mujoco_integrator}", np.zeros(6))
