"""The solref conversion against MuJoCo's own quantities: the penalty mapping's constraint force
on a point mass, the physical mapping's natural frequency and damping ratio."""
from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from compare.tools.calibration.conversion import conversion_table, drop_scene
from compare.cli import main
from custom_sim import parse_scene
from mujoco_models import build_twin, simulate_mujoco, solref_for

M, K, C, G = 0.5, 1e4, 20.0, 9.81
PENALTY_IMPEDANCE = solref_for(drop_scene(M, K, C), "penalty").solimp[0]   # MuJoCo's smallest, 1e-4
# The penalty row's force is (k d + c v - d_imp a0 / A_hat) / (1 + d_imp (A / A_hat - 1)); on a
# point mass A = A_hat = 1/m, so it is off only by d_imp m g (a0 = -g), plus rounding.
PENALTY_FORCE_TOLERANCE = PENALTY_IMPEDANCE * M * G + 1e-9
# Frequency and damping ratio measured from the twin's extrema: located on the 1e-4 s grid of a
# 0.31 s period, and MuJoCo's Euler step is first order, h wn = 2e-3.
OSCILLATION_TOLERANCE = 2e-3


def _normal_force(mapping: str, depth: float, speed: float) -> tuple[float, float]:
    """MuJoCo's normal constraint force (N) and contact distance (m) on the point mass at
    `depth` below contact and moving down at `speed`."""
    scene = drop_scene(M, K, C)
    model = build_twin(scene, mapping).spec.compile()
    data = mujoco.MjData(model)
    data.qpos[:] = [0.0, scene.body.contact_height - depth]
    data.qvel[:] = [0.0, -speed]
    mujoco.mj_forward(model, data)
    assert data.ncon == 1 and data.nefc == 1
    return float(data.efc_force[0]), float(data.contact.dist[0])


@pytest.mark.parametrize("depth,speed", [(0.001, 0.0), (0.003, 0.2), (0.005, -0.1)])
def test_penalty_mapping_is_mujocos_constraint_force(depth, speed):
    force, dist = _normal_force("penalty", depth, speed)
    assert dist == pytest.approx(-depth, abs=1e-12), "MuJoCo's depth is not ours"
    want = K * depth + C * speed
    assert abs(force - want) <= PENALTY_FORCE_TOLERANCE, f"efc_force {force} N against k d + c v = {want} N"


def test_the_force_check_fails_on_the_seed_mapping():
    force, _ = _normal_force("seed", 0.003, 0.2)
    assert abs(force - (K * 0.003 + C * 0.2)) > 100 * PENALTY_FORCE_TOLERANCE


def _oscillation(mapping: str):
    """(wn rad/s, zeta) measured from the twin of a point mass resting in the ground: under
    g = 50 its equilibrium depth (1 - dmax) g / wn^2 = 6 mm keeps it deeper than solimp's
    width (1 mm), where MuJoCo's impedance is dmax and the contact is linear."""
    m, k, c, h = 0.5, 200.0, 2.0, 0.05          # wn = 20 rad/s, zeta = 0.1
    scene = parse_scene({"name": "osc", "duration": 1.5, "dt": 1e-4, "g": 50.0,
                         "effects": ["gravity", "contact"],
                         "body": {"shape": "point", "mass": m, "contact_height": h},
                         "contact": {"k": k, "c": c, "damping_law": "linear"},
                         "initial": {"position": [0.0, h - 0.004]}})
    y = simulate_mujoco(scene, mapping).y
    ext = np.flatnonzero(np.diff(np.sign(np.diff(y))) != 0) + 1
    swing = np.abs(np.diff(y[ext]))                 # peak to trough: ratio exp(-pi zeta / sqrt(1 - zeta^2))
    delta = -np.mean(np.log(swing[1:] / swing[:-1]))
    zeta = delta / math.hypot(math.pi, delta)
    period = 2.0 * np.mean(np.diff(ext)) * scene.dt
    return 2.0 * math.pi / period / math.sqrt(1.0 - zeta * zeta), zeta, (k, c, m)


def test_physical_mapping_has_the_spring_dampers_frequency_and_damping_ratio():
    wn, zeta, (k, c, m) = _oscillation("physical")
    assert wn == pytest.approx(math.sqrt(k / m), rel=OSCILLATION_TOLERANCE), f"wn {wn} rad/s"
    assert zeta == pytest.approx(c / (2 * math.sqrt(k * m)), rel=OSCILLATION_TOLERANCE), f"zeta {zeta}"


def test_the_oscillation_check_fails_on_the_seed_mapping():
    wn, zeta, (k, c, m) = _oscillation("seed")
    assert abs(wn / math.sqrt(k / m) - 1.0) > 10 * OSCILLATION_TOLERANCE


def test_conversion_table_errors():
    rows = {r.mapping: r for r in conversion_table(M, K, C)}
    assert set(rows) == {"seed", "physical", "penalty"}
    assert rows["penalty"].solref == pytest.approx((-K / M, -C / M))   # A_hat = 1/m on a point
    # the penalty mapping is the only one exact on a point mass (same law, force off by d m g)
    assert rows["penalty"].position_error_max < 1e-4 < rows["physical"].position_error_max


@pytest.mark.parametrize("argv,field", [
    (["solref", "--mass", "0", "--k", "1e4", "--c", "20"], "--mass"),
    (["solref", "--mass", "1", "--k", "-5", "--c", "20"], "--k"),
    (["solref", "--mass", "1", "--k", "1e4", "--c", "20", "--shape", "blob"], "--shape"),
])
def test_solref_bad_input(argv, field, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and field in err[0]
