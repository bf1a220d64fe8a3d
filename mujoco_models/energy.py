"""A twin's energy from MuJoCo's own state (J), by the formula of docs/report-files.md:

    kinetic        MuJoCo's qvel^T M qvel / 2 (sensor e_kinetic)
    gravitational  MuJoCo's potential - sum m g . x_com = m g y (sensor e_potential; 0 without
                   gravity, MuJoCo's gravity being 0 then)
    contact        sum over touching contact points of k d^2 / 2, d from MuJoCo: the depth
                   -dist of each active contact (native pairs), or, without pairs, the depth of
                   each contact site below the ground (the circle's point R below its site)

sensors.py says where each value sits; rollout's sensor row i belongs to state row i (sensors
are computed at the start of a step), so the final state gets one more step of rollout, whose
sensor row is that state's. (mj_setState then mj_forward on a data that has run can leave
e_kinetic at the previous call's value in mujoco 4.0.0; a test checks the sensor rows against
mj_energyPos / mj_energyVel on a fresh MjData.)
"""
from __future__ import annotations

import mujoco
import numpy as np
from mujoco import rollout

from .sensors import SensorLayout


def final_sensors(model: mujoco.MjModel, data: mujoco.MjData, full_state: np.ndarray) -> np.ndarray:
    """sensordata (nsensordata,) at the given full physics state: the sensor row of one
    rollout step from it."""
    _, sensors = rollout.rollout(model, data, full_state, nstep=1)
    return sensors[0, 0].copy()


def energy_parts(layout: SensorLayout, sensordata: np.ndarray, k: float, below: float = 0.0):
    """(kinetic, gravitational, contact) arrays (T,) from sensor rows (T, nsensordata); k the
    contact stiffness (N/m), below: how far under its site a contact point lies (m)."""
    s = np.atleast_2d(sensordata)
    kinetic = s[:, layout.kinetic].copy()
    gravity = s[:, layout.potential].copy()
    contact = np.zeros(s.shape[0])
    if layout.contacts:
        a, w, n = layout.contact_start, layout.contact_width, layout.contacts
        block = s[:, a:a + w * n].reshape(s.shape[0], n, w)
        if layout.kind == "dist":
            found, dist = block[:, :, 0], block[:, :, 1]
            depth = np.where(found > 0.0, np.maximum(0.0, -dist), 0.0)
        else:
            depth = np.maximum(0.0, below - block[:, :, 2])
        contact = 0.5 * k * np.sum(depth * depth, axis=1)
    return kinetic, gravity, contact
