"""The user's simulator in `sweep` and `bench` (--sim): the order its error falls at, its stable
step by custom_sim's own search, the sentence where its order is not the one it declares.

The scene for the orders: box_slide cut to 0.2 s under the linear (Kelvin-Voigt) damping law.
The box slides on its two lower corners, which never leave the ground, and the law's force
k d - c v stays positive, so nothing switches (the reference finds no event) and friction is
saturated (tanh of alpha v ~ tanh(200)): the motion is smooth and every method shows its own
order. Under the scene's compression law, c max(0, -v) kinks each time a corner's vertical
velocity crosses zero as the box rocks; RK4's error then falls at about order 2 (custom_sim's
own sweep of box_slide: 1.1e-7 m at 2 ms, 5.8e-12 m at 20 us).
"""
from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from compare.cli import main
from compare.scenarios import load
from compare.tools.accuracy import workprecision as wp
from compare.tools.accuracy.orders import mismatch, orders
from compare.tools.accuracy.stability_search import (
    BISECTION_RATIO,
    custom_limit,
    energy_scale,
)
from compare.tools.accuracy.yours import (
    YOURS,
    integrators_of,
    run_verdict,
    trial,
    variant,
    yours_ladder,
    yours_limit,
)
from compare.tools.sweep.results_json import write_json
from compare.tools.sweep.yours import yours_lines
from compare.usersim import StepFunction, WholeFunction
from custom_sim import SimulationChattered, simulate

ROOT = Path(__file__).resolve().parents[3]
SEED = str(ROOT / "examples" / "seed_sim.py") + ":step"
OUTSIDER = str(ROOT / "tests" / "outsiders" / "heun_box.py") + ":step"
BESIDE_SEED = f"import sys\nsys.path.insert(0, {str(ROOT / 'examples')!r})\n"   # a module that imports the example
LADDER = (1, 2, 4)        # dt = 2, 1, 0.5 ms: all above the reference's floor for RK4 too
# Away from contact events the fitted slope lands within 0.05 of the method's order
# (test_workprecision.py); Heun (explicit trapezoid) is second order.
ORDER_TOLERANCE = 0.1


@pytest.fixture(autouse=True)
def quick_timing(monkeypatch):
    """Two timings per rung: the error, not the time, is under test here."""
    monkeypatch.setattr(wp, "TIMING_BUDGET", 0.0)


def smooth_slide(duration=0.2):
    scene = dataclasses.replace(load("box_slide"), duration=duration)
    return dataclasses.replace(scene, contact=dataclasses.replace(scene.contact, damping_law="linear"))


@pytest.fixture(scope="module")
def reference():
    scene = smooth_slide()
    ref = wp.reference_task(scene, None)
    assert sum(ref["switches"].values()) == 0   # the premise: nothing switches
    return scene, ref


def sweep_of(scene, ref, simulator, integrators, custom=("rk4",)):
    runs, skipped = [], {}
    for integ in custom:
        runs += wp.custom_ladder(scene, integ, ref["states"], ref["energy_scale"], LADDER)
    for integ in integrators:
        ladder, why = yours_ladder(simulator, scene, integ, ref["states"], ref["energy_scale"], LADDER)
        runs += ladder
        if why:
            skipped[integ] = why
    yours = {"label": simulator.label, "declared": integrators != ["explicit_euler", "semi_implicit_euler",
                                                                   "implicit_euler", "rk4"],
             "integrators": [i for i in integrators if i not in skipped], "skipped": skipped}
    return wp.SceneSweep(scene, ref, runs, {}, [], yours)


def test_seed_sim_orders_are_its_integrators(reference):
    scene, ref = reference
    sim = StepFunction(SEED)
    assert integrators_of(sim, scene) == ["explicit_euler", "semi_implicit_euler", "implicit_euler", "rk4"]
    sweep = sweep_of(scene, ref, sim, ["semi_implicit_euler", "rk4", "implicit_euler"])
    fitted = {(e["simulator"], e["integrator"]): e for e in orders(sweep)}
    assert abs(fitted[(YOURS, "semi_implicit_euler")]["order"] - 1) < ORDER_TOLERANCE
    assert abs(fitted[(YOURS, "rk4")]["order"] - 4) < ORDER_TOLERANCE
    assert fitted[(YOURS, "rk4")]["dts"] == [0.002, 0.001, 0.0005]
    # the seed's algorithm is custom_sim's: the same errors, to round-off
    for mine, ours in zip(sweep.of(YOURS, "rk4"), sweep.of("custom", "rk4")):
        assert mine.error_max == pytest.approx(ours.error_max, rel=1e-6, abs=1e-14)
        assert mine.force_evals is None and mine.wall_time > 0 and mine.repeats >= 2
    # implicit Euler is not written in the example: said, not run
    assert "is not written in this example" in sweep.yours["skipped"]["implicit_euler"]
    assert not sweep.of(YOURS, "implicit_euler")
    assert mismatch(sweep, "rk4") == "" and mismatch(sweep, "semi_implicit_euler") == ""


def test_outsider_declaring_rk4_is_told_its_order(reference):
    scene, ref = reference
    sim = StepFunction(OUTSIDER)
    assert integrators_of(sim, scene) == ["rk4"]
    sweep = sweep_of(scene, ref, sim, ["rk4"])
    order = next(e["order"] for e in orders(sweep) if e["simulator"] == YOURS)
    assert abs(order - 2) < ORDER_TOLERANCE          # Heun's step, whatever the label says
    sentence = mismatch(sweep, "rk4")
    assert sentence.startswith(f"you declare rk4; your error falls at order {order:.1f}")
    assert sentence in yours_lines(sweep)


def test_outsider_refuses_a_circle():
    scene = dataclasses.replace(load("rolling_circle"), duration=0.01)
    ladder, why = yours_ladder(StepFunction(OUTSIDER), scene, "rk4", np.zeros((6, 6)), 1.0, LADDER)
    assert ladder == [] and why == "a circle body, not in the module's SHAPES = ('box',)"   # never called


def test_whole_run_is_given_each_rungs_dt(tmp_path, reference):
    """--whole: simulate(scene) steps with scene["dt"]; the errors are the step function's."""
    scene, ref = reference
    (tmp_path / "whole_seed.py").write_text(
        BESIDE_SEED + "import numpy as np\nfrom seed_sim import step\n\n"
        "def simulate(scene):\n    out = [np.array(scene['state0'])]\n"
        "    for _ in range(scene['steps']):\n        out.append(step(out[-1], scene, scene['dt']))\n"
        "    return np.array(out)\n")
    whole, _ = yours_ladder(WholeFunction(f"{tmp_path / 'whole_seed.py'}:simulate"), scene, "semi_implicit_euler",
                            ref["states"], ref["energy_scale"], LADDER)
    steps, _ = yours_ladder(StepFunction(SEED), scene, "semi_implicit_euler", ref["states"], ref["energy_scale"],
                            LADDER)
    assert [r.steps for r in whole] == [100, 200, 400]
    assert [r.error_max for r in whole] == [r.error_max for r in steps]


def test_stability_search_agrees_with_custom_sims():
    """The same bisection and the same stops on the same algorithm: the same largest step,
    failing for the same reason just above it: the slip chattering as the box stops (0.41 s)."""
    scene = dataclasses.replace(load("box_slide"), duration=0.6)
    scale = energy_scale(simulate(scene).states(), scene)
    ours = custom_limit(scene, "semi_implicit_euler", scale)
    mine = yours_limit(StepFunction(SEED), scene, "semi_implicit_euler", scale)
    assert abs(math.log(mine.h_max / ours.h_max)) <= math.log(BISECTION_RATIO)
    assert mine.reason == ours.reason and mine.simulator == YOURS
    assert ours.reason.startswith("chatter: point")


def test_chatter_is_found_in_the_states_where_custom_sim_stops():
    """custom_sim stops a chattering run; the same run's states, read after the fact, chatter
    at the same step."""
    scene = dataclasses.replace(load("box_slide"), duration=0.6, dt=3e-3)
    with pytest.raises(SimulationChattered) as stop:
        simulate(scene)
    t = trial(StepFunction(SEED), variant(scene, scene.integrator, scene.dt))
    ok, why = run_verdict(scene, t.states, 1.0)
    assert not ok and why == f"chatter: point {stop.value.point} {stop.value.quantity} at step {stop.value.step}"


def test_stateful_step_starts_each_trial_afresh(tmp_path):
    """A step keeping the time in its module (the seed's step, then a kick after 0.05 s of its
    own clock): every trial is a fresh import, so every trial gives the same run."""
    (tmp_path / "clocked.py").write_text(
        BESIDE_SEED + "from seed_sim import step as seed\nT = [0.0]\n\n"
        "def step(state, scene, dt):\n    T[0] += dt\n    z = seed(state, scene, dt)\n"
        "    if abs(T[0] - 0.05) < dt / 2:\n        z[3] += 0.1\n    return z\n")
    sim = StepFunction(f"{tmp_path / 'clocked.py'}:step")
    scene = variant(dataclasses.replace(load("box_slide"), duration=0.1), "semi_implicit_euler", 1e-3)
    first, second = trial(sim, scene), trial(sim, scene)
    assert np.array_equal(first.states, second.states)


def test_results_json_has_yours_beside_custom(tmp_path, reference):
    scene, ref = reference
    sweep = sweep_of(scene, ref, StepFunction(SEED), ["rk4"])
    sweep.stability.append(yours_limit(StepFunction(SEED), scene, "implicit_euler", 1.0))
    write_json([sweep], tmp_path / "results.json", 1.0, 1)
    doc = json.loads((tmp_path / "results.json").read_text())["scenes"][0]
    mine = [r for r in doc["runs"] if r["simulator"] == "yours"]
    ours = [r for r in doc["runs"] if r["simulator"] == "custom"]
    assert mine and set(mine[0]) == set(ours[0])
    assert all(r["force_evals"] is None for r in mine)
    entry = next(e for e in doc["orders"] if e["simulator"] == "yours")
    assert entry["integrator"] == "rk4" and abs(entry["order"] - 4) < ORDER_TOLERANCE and entry["dts"]
    assert {"simulator", "integrator", "order", "dts"} == set(entry)
    assert doc["stability"][0]["simulator"] == "yours" and "is not written in this example" in doc["stability"][0]["reason"]


def test_sweep_sim_bad_module_is_bad_input(tmp_path, capsys):
    status = main(["sweep", "box_slide", "--sim", str(tmp_path / "missing.py") + ":step", "--out", str(tmp_path)])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1 and "no such file" in err[0]
    assert not (tmp_path / "sweep").exists()


def test_bench_sim_prints_a_line_for_the_users_step(capsys):
    from compare.tools.accuracy import benchmark
    pytest.importorskip("mujoco_models")
    scene = dataclasses.replace(load("box_slide"), duration=0.05)
    r = benchmark.bench_scene(scene, rounds=1, yours=StepFunction(SEED), repeats=2)
    assert r.ns_per_step_yours > r.ns_per_step_custom > 0 and r.ns_per_call_harness is not None
    from compare.commands.bench import yours_line
    line = yours_line(r)
    assert line.startswith("box_slide: yours (") and "x custom_sim's" in line and "harness's own share" in line


@pytest.mark.slow
def test_sweep_sim_command(tmp_path, capsys):
    from short_scene import short_scene
    path = short_scene(tmp_path, "box_slide", 0.2)
    status = main(["sweep", str(path), "--sim", SEED, "--no-mujoco", "--jobs", "1", "--out", str(tmp_path)])
    out = capsys.readouterr().out
    assert status == 0 and "yours, RK4: error falls at order" in out
    doc = json.loads((tmp_path / "sweep" / "results.json").read_text())["scenes"][0]
    assert {e["simulator"] for e in doc["orders"]} == {"custom", "yours"}
    assert {lim["simulator"] for lim in doc["stability"]} == {"custom", "yours"}
    assert "yours: RK4" in (tmp_path / "sweep" / "index.md").read_text()


def test_law_file_lays_its_contact_over_every_scene(tmp_path):
    """--law FILE on sweep and bench: every simulator runs the scene under the file's law."""
    import argparse

    from compare.commands.sweep import user_simulator
    (tmp_path / "law.toml").write_text('[contact]\ndamping_law = "linear"\nk = 2e4\n')
    args = argparse.Namespace(sim=SEED, whole=False, law=str(tmp_path / "law.toml"))
    sim, (scene,) = user_simulator(args, [load("box_slide")])
    assert sim.label == SEED
    assert (scene.contact.damping_law, scene.contact.k, scene.contact.mu) == ("linear", 2e4, load("box_slide").contact.mu)


def test_sweep_sim_wrong_return_is_bad_input_before_the_sweep(tmp_path, capsys):
    (tmp_path / "short.py").write_text("def step(state, scene, dt):\n    return state[:5]\n")
    status = main(["sweep", "box_slide", "--sim", f"{tmp_path / 'short.py'}:step", "--out", str(tmp_path)])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and "returned an array of shape (5,)" in err[-1]
    assert not (tmp_path / "sweep").exists()


def test_figure_draws_the_users_curve(tmp_path, reference, monkeypatch):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from compare.tools.sweep.figure import plot_scene
    scene, ref = reference
    sweep = sweep_of(scene, ref, StepFunction(OUTSIDER), ["rk4"])
    monkeypatch.setattr(plt, "close", lambda fig: None)   # keep the figure to read its curves
    plot_scene(sweep, tmp_path / "figure.png")
    lines = {line.get_label(): line for line in plt.gcf().axes[0].get_lines()}
    mine = lines["yours: RK4"]
    assert mine.get_linestyle() == ":" and list(mine.get_ydata()) == [r.error_max for r in sweep.of(YOURS, "rk4")]
    assert "ours: RK4" in lines and (tmp_path / "figure.png").stat().st_size > 0
    plt.close("all")
