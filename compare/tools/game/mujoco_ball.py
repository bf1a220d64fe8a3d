"""The ball's MuJoCo twin (mujoco_models) behind custom_sim.Stepper's interface, for `--engine mujoco`.

The twin is generated from the same ball scene (penalty solref mapping, MuJoCo's Euler). The
player's force and the goal frame's force act at the centre: they enter as generalised forces
on the twin's joints, slide x = Fx, slide y (MuJoCo's z) = Fy, hinge theta = tau (its axis
0 -1 0 makes it the counter-clockwise torque). MuJoCo keeps them in qfrc_applied for every
step of `advance`, as the Stepper holds its force.
"""
from __future__ import annotations

import mujoco
import numpy as np

from custom_sim import Scene
from mujoco_models import build_twin
from mujoco_models.frames import joint_count, qpos_qvel, states_from_q


class MujocoBall:
    """state [x, y, theta, vx, vy, omega] (a fresh array), advance(n, force), reset(state)."""

    def __init__(self, scene: Scene):
        twin = build_twin(scene)
        self.scene, self.props = scene, twin.props
        self.model = twin.spec.compile()
        self.data = mujoco.MjData(self.model)
        self.nq = joint_count(self.props)
        self.steps = 0
        mujoco.mj_resetDataKeyframe(self.model, self.data, 0)
        mujoco.mj_forward(self.model, self.data)

    @property
    def state(self) -> np.ndarray:
        return states_from_q(self.props, self.data.qpos, self.data.qvel)[0]

    def advance(self, n: int, force=(0.0, 0.0, 0.0)) -> np.ndarray:
        self.data.qfrc_applied[:] = np.asarray(force, dtype=np.float64)[:self.nq]
        mujoco.mj_step(self.model, self.data, nstep=n)
        self.steps += n
        return self.state

    def reset(self, state) -> None:
        """Start over from `state` (warm start and time cleared, so a round never depends on the last)."""
        mujoco.mj_resetData(self.model, self.data)
        qpos, qvel = qpos_qvel(self.props, state)
        self.data.qpos[:] = qpos
        self.data.qvel[:] = qvel
        mujoco.mj_forward(self.model, self.data)
        self.steps = 0
