"""Batched runs equal single runs bit for bit: custom_sim.batch against simulate, mujoco_models.batch
against simulate_mujoco, with bodies of different contact-point counts and a diverging run in one batch."""
from __future__ import annotations

import dataclasses

import numpy as np

from compare.scenarios import load
from custom_sim import INTEGRATORS, SimulationDiverged, simulate
from custom_sim.batch import simulate_batch


def _short(name: str, **changes):
    return dataclasses.replace(load(name), duration=0.4, **changes)


def test_custom_batch_equals_simulate_bit_for_bit():
    box = _short("box_drop")
    scenes = [dataclasses.replace(box, integrator=name) for name in INTEGRATORS]
    scenes += [_short("point_drop"), _short("rolling_circle", integrator="rk4"), _short("t_shape_drop")]
    # explicit Euler far past its limit on a stiff contact: stops at a step, like simulate
    stiff = dataclasses.replace(box.contact, k=1e7)
    scenes.append(dataclasses.replace(box, integrator="explicit_euler", dt=2e-3, contact=stiff))
    runs = simulate_batch(scenes, threads=2)
    diverged = 0
    for scene, run in zip(scenes, runs):
        try:
            traj = simulate(scene)
        except SimulationDiverged as exc:
            diverged += 1
            assert run.failed_step == exc.step and np.array_equal(run.failed_state, exc.state), scene.name
            assert np.all(np.isnan(run.states[exc.step + 1:]))
            continue
        assert not run.diverged
        assert np.array_equal(run.states, traj.states()), (scene.name, scene.integrator)
        assert (run.force_evals, run.newton_iterations) == (traj.force_evals, traj.newton_iterations)
    assert diverged == 1


def test_samples_pick_rows_of_the_trajectory():
    scene = _short("box_drop", integrator="rk4")
    rows = np.array([0, 1, 7, scene.steps])
    (run,) = simulate_batch([scene], [rows])
    assert np.array_equal(run.states, simulate(scene).states()[rows])


def test_mujoco_batch_equals_simulate_mujoco_bit_for_bit():
    from mujoco_models import simulate_mujoco
    from mujoco_models.batch import simulate_mujoco_batch

    box = _short("box_drop")
    scenes = [box, dataclasses.replace(box, contact=dataclasses.replace(box.contact, k=3e4)),
              dataclasses.replace(box, dt=2e-4), _short("point_drop")]
    for scene, twin in zip(scenes, simulate_mujoco_batch(scenes, threads=2)):
        assert not twin.diverged, twin.note
        assert np.array_equal(twin.states, simulate_mujoco(scene).states()), scene.name
