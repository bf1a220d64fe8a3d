"""A scenario's Case does each thing once: the counts of one scenario walked through every check."""
import collections
import dataclasses
import sys

import pytest

import compare.oracle.rigid_body  # noqa: F401 - the modules, not the functions of the same name
import custom_sim.bodies
import mujoco_models.rigid_body  # noqa: F401
from compare.scenarios import load
from compare.checks import case as case_module
from compare.checks.case import Case
from compare.run.scenario import run_scenario

ORACLE = sys.modules["compare.oracle.rigid_body"]
TWIN_BODY = sys.modules["mujoco_models.rigid_body"]


def counted(monkeypatch, module, name, counts, label):
    real = getattr(module, name)

    def wrapper(*args, **kwargs):
        counts[label] += 1
        return real(*args, **kwargs)
    monkeypatch.setattr(module, name, wrapper)


@pytest.fixture
def counts(monkeypatch):
    """Calls per scenario of each derivation, from empty caches."""
    found = collections.Counter()
    for cached in (custom_sim.bodies.mass_properties, ORACLE.rigid_body, TWIN_BODY.rigid_body):
        cached.cache_clear()
    counted(monkeypatch, custom_sim.bodies, "_derive", found, "custom_sim mass properties")
    counted(monkeypatch, ORACLE, "polygons_body", found, "oracle mass properties")
    counted(monkeypatch, TWIN_BODY, "_derive", found, "MuJoCo mass properties")
    real_simulate = case_module.simulate

    def simulate(scene, *args, **kwargs):
        found[("simulate", scene)] += 1
        return real_simulate(scene, *args, **kwargs)
    monkeypatch.setattr(case_module, "simulate", simulate)
    import compare.checks.sensitivity as sensitivity
    real_states = sensitivity.run_states

    def run_states(scene, integrator, dt, *args, **kwargs):
        found[("run_states", scene, integrator, dt, args, tuple(kwargs.items()))] += 1
        return real_states(scene, integrator, dt, *args, **kwargs)
    monkeypatch.setattr(sensitivity, "run_states", run_states)
    import mujoco
    real_compile = mujoco.MjSpec.compile

    def compile_spec(spec, *args, **kwargs):
        model = real_compile(spec, *args, **kwargs)
        found[("compile", spec.to_xml())] += 1   # the model's own text: one key per distinct model
        return model
    monkeypatch.setattr(mujoco.MjSpec, "compile", compile_spec)
    import mujoco_models.spec as spec_module
    spec_module._A_HAT.clear()
    spec_module._COMPILED.clear()
    yield found
    for cached in (custom_sim.bodies.mass_properties, ORACLE.rigid_body, TWIN_BODY.rigid_body):
        cached.cache_clear()


@pytest.mark.parametrize("name", ["box_drop", "t_shape_drop"])
def test_one_scenario_derives_each_side_once_and_runs_the_scene_once(counts, name):
    scene = dataclasses.replace(load(name), duration=0.4)
    result = run_scenario(scene)
    assert result.error is None, result.error
    from mujoco_models import to_mjcf
    to_mjcf(scene)   # the report's model.xml: the native twin, compiled already
    for side in ("custom_sim mass properties", "oracle mass properties", "MuJoCo mass properties"):
        assert counts[side] == 1, (side, counts[side])
    runs = {key[1].integrator: n for key, n in counts.items() if isinstance(key, tuple) and key[0] == "simulate"}
    assert runs == {"explicit_euler": 1, "semi_implicit_euler": 1, "implicit_euler": 1, "rk4": 1}, runs
    # no other route runs the scene's own run again (the attribution's reference, its last rung)
    again = [key for key in counts if isinstance(key, tuple) and key[0] == "run_states"
             and key[1:4] == (scene, scene.integrator, scene.dt) and not key[4] and not key[5]]
    assert not again, again
    # nor any variant twice, nor any MuJoCo model compiled twice
    assert all(n == 1 for key, n in counts.items() if isinstance(key, tuple)), \
        [(key[0], n) for key, n in counts.items() if isinstance(key, tuple) and n > 1]


def test_a_failure_is_kept_and_raised_again_without_running_twice(monkeypatch):
    from custom_sim import SimulationDiverged

    base = load("point_drop")   # a spring 100 times stiffer at 40 times the step: explicit Euler blows up
    scene = dataclasses.replace(base, dt=2e-3, duration=0.6, contact=dataclasses.replace(base.contact, k=1e6))
    calls = collections.Counter()
    real = case_module.simulate

    def simulate(s, *args, **kwargs):
        calls[s.integrator] += 1
        return real(s, *args, **kwargs)
    monkeypatch.setattr(case_module, "simulate", simulate)
    case = Case(scene)
    for _ in range(2):
        with pytest.raises(SimulationDiverged):
            case.trajectory("explicit_euler")
    assert calls["explicit_euler"] == 1


def test_the_case_gives_the_same_states_as_a_run_of_its_own():
    """A run shared through the case is the run a check would make itself, to the bit."""
    from compare.checks.sensitivity import run_states
    from custom_sim import simulate

    scene = dataclasses.replace(load("box_drop"), duration=0.3)
    case = Case(scene)
    assert (case.trajectory().states() == simulate(scene).states()).all()
    case.trajectory()   # the own run is known: states() of the own scene takes it
    assert (case.states(scene, scene.integrator, scene.dt) == run_states(scene, scene.integrator, scene.dt)).all()
