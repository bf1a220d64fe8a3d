"""Only the effects a scene lists reach the MJCF: read back with an XML parser, and run."""
import xml.etree.ElementTree as ET

import mujoco
import numpy as np
import pytest

from custom_sim import parse_scene
from mujoco_models import build_model, simulate_mujoco, to_mjcf


def box_scene(effects, **mujoco_table):
    return parse_scene({
        "duration": 0.3, "dt": 1e-4, "effects": list(effects),
        "body": {"shape": "box", "mass": 1.0, "size": [0.2, 0.1]},
        "contact": {"k": 1e4, "c": 20.0, "mu": 0.5},
        "initial": {"position": [0.0, 0.06], "velocity": [0.5, -1.0], "angle": 0.2},
        "mujoco": mujoco_table}, file="<test>")


def parse(scene):
    return ET.fromstring(to_mjcf(scene))


def gravity_of(root):
    opt = root.find("option")
    text = opt.get("gravity") if opt is not None else None
    return [0.0, 0.0, -9.81] if text is None else [float(v) for v in text.split()]  # MJCF default


def test_nothing_listed_means_no_gravity_no_pair_and_nothing_collides():
    scene = box_scene([])
    root = parse(scene)
    assert gravity_of(root) == [0.0, 0.0, 0.0]
    assert root.find("contact") is None or len(root.find("contact")) == 0, "no contact pair"
    for geom in root.iter("geom"):
        assert geom.get("contype") == "0" and geom.get("conaffinity") == "0", geom.get("name")
    # and in a run: the box falls through the ground level at constant velocity, no contact ever
    model = build_model(scene)
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    for _ in range(2000):
        mujoco.mj_step(model, data)
        assert data.ncon == 0
    assert data.qvel == pytest.approx([0.5, -1.0, 0.0])


@pytest.mark.parametrize("effects,condim", [
    (["gravity", "contact"], "1"),
    (["contact"], "1"),
    (["gravity", "contact", "friction"], "3"),
])
def test_condim_follows_the_effects(effects, condim):
    root = parse(box_scene(effects))
    pairs = root.find("contact").findall("pair")
    assert len(pairs) == 4, "one pair per corner"
    for pair in pairs:
        assert pair.get("condim", "3") == condim    # MJCF's default condim is 3
    assert gravity_of(root)[2] == (-9.81 if "gravity" in effects else 0.0)


def test_rolling_circle_gets_condim_6_and_mu_roll():
    scene = parse_scene({
        "duration": 0.1, "dt": 1e-4, "effects": ["gravity", "contact", "friction", "rolling_friction"],
        "body": {"shape": "circle", "mass": 1.0, "radius": 0.1},
        "contact": {"k": 1e4, "c": 20.0, "mu": 0.3, "mu_roll": 0.002},
        "initial": {"position": [0.0, 0.099]}}, file="<test>")
    (pair,) = parse(scene).find("contact").findall("pair")
    assert pair.get("condim") == "6"
    assert [float(v) for v in pair.get("friction").split()] == [0.3, 0.3, 0.0, 0.002, 0.002]


@pytest.mark.parametrize("cone", ["elliptic", "pyramidal"])
def test_cone_comes_from_the_scene(cone):
    root = parse(box_scene(["gravity", "contact", "friction"], cone=cone))
    assert root.find("option").get("cone", "pyramidal") == cone


def test_no_contact_scene_runs_as_ballistic_flight():
    scene = box_scene(["gravity"])
    twin = simulate_mujoco(scene)
    t = twin.t
    # semi-implicit Euler under gravity: y_n = y0 + v0 t - g t (t + h) / 2, exact in floating point to 1e-12
    assert twin.y == pytest.approx(0.06 - 1.0 * t - 9.81 * t * (t + scene.dt) / 2, abs=1e-12)
    assert np.all(twin.energy_contact == 0.0)
