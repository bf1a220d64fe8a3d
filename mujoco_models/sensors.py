"""Sensors MuJoCo fills on every step, so that a run's energy comes from MuJoCo's own state.

    e_kinetic      (1)  qvel^T M qvel / 2, MuJoCo's mass matrix (J)
    e_potential    (1)  - sum m g . x_com, MuJoCo's gravity and COM: m g y here (J)
    contact i      (2)  [found, dist] of the pair ground / contact geom i (dist < 0: depth)
    framepos i     (3)  world position of contact site i, for a twin without pairs (m)

MuJoCo computes sensors in mj_forward at the start of mj_step, so the sensor row rollout
returns for step i holds the values of the state *before* it (row i of our trajectory); the
final state's values come from one more mj_forward (energy.py).
"""
from __future__ import annotations

from dataclasses import dataclass

import mujoco

CONTACT_FOUND_DIST = 1 | 8   # mjtConDataField bits: found (1), dist (8)


@dataclass(frozen=True)
class SensorLayout:
    """Offsets into sensordata: kinetic, potential, the first contact sensor and its width
    (2 for [found, dist], 3 for a site's framepos), and the number of contact sensors."""

    kinetic: int
    potential: int
    contact_start: int
    contact_width: int
    contacts: int
    kind: str          # "dist" (MuJoCo's contact distances) | "site" (site positions) | "none"


def add_sensors(spec: mujoco.MjSpec, ground: str, paired_geoms: list[str], sites: list[str]) -> SensorLayout:
    """Energy sensors, then contact sensors for the paired geoms, or framepos of the sites."""
    spec.add_sensor(name="kinetic", type=mujoco.mjtSensor.mjSENS_E_KINETIC)
    spec.add_sensor(name="potential", type=mujoco.mjtSensor.mjSENS_E_POTENTIAL)
    for geom in paired_geoms:
        spec.add_sensor(name=f"dist_{geom}", type=mujoco.mjtSensor.mjSENS_CONTACT,
                        objtype=mujoco.mjtObj.mjOBJ_GEOM, objname=ground,
                        reftype=mujoco.mjtObj.mjOBJ_GEOM, refname=geom,
                        intprm=[CONTACT_FOUND_DIST, 0, 1])
    if paired_geoms:
        return SensorLayout(0, 1, 2, 2, len(paired_geoms), "dist")
    for site in sites:
        spec.add_sensor(name=f"pos_{site}", type=mujoco.mjtSensor.mjSENS_FRAMEPOS,
                        objtype=mujoco.mjtObj.mjOBJ_SITE, objname=site)
    return SensorLayout(0, 1, 2, 3, len(sites), "site" if sites else "none")
