"""The calibration fit is real: it recovers settings it was given, reaches the compiled model,
repeats itself, says when it stops short or sits on a bound; the reverse fit inverts the
penalty mapping. Tiny fits (short scenes, few iterations)."""
from __future__ import annotations

import copy
import dataclasses

import mujoco
import numpy as np
import pytest

from compare.tools.calibration.calibration import calibrated_spec, readback
from compare.tools.calibration.conversion import drop_scene
from compare.tools.calibration.fit import fit
from compare.tools.calibration.parameters import PARAMETERS, parse_fit
from compare.tools.calibration.reverse import prepare_reverse, reverse_fit
from compare.tools.calibration.settings import calibrated, read_model, write_model
from compare.tools.calibration.targets import Batch, prepare
from compare.cli import main
from scene_types import BadInput
from compare.scenarios import load

# Gains recovered from a noise-free target made by the twin itself: limited by the finite
# difference step (1e-3 in ln p) and the optimiser's stopping rule, not by any physics.
RECOVERY_TOLERANCE = 1e-3
PARAMS = (PARAMETERS["solref.stiffness"], PARAMETERS["solref.damping"])


@pytest.fixture(scope="module")
def short_drop():
    """point_drop cut to its first bounce (0.45 s): fast, and both gains act on it."""
    return dataclasses.replace(load("point_drop"), duration=0.45)


POSITIVE = (PARAMETERS["solref.timeconst"], PARAMETERS["solref.dampratio"])


def _synthetic(scene, gains, params=PARAMS, base="penalty"):
    """A target whose reference is the base twin itself with the given gains."""
    target = prepare(scene, base)
    with Batch(1) as b:
        target.reference = b.paths(target, [calibrated(target.base, params, gains)])[0]
    return target


@pytest.mark.parametrize("params,base", [(PARAMS, "penalty"), (POSITIVE, "physical")],
                         ids=["direct form", "positive form"])
def test_fit_recovers_the_gains_that_made_the_target(short_drop, params, base):
    target = _synthetic(short_drop, [1.5, 0.7], params, base)
    result = fit([target], params, max_iter=15)
    assert result.converged, result.status
    assert result.values == pytest.approx([1.5, 0.7], rel=RECOVERY_TOLERANCE)
    assert result.objective[-1] < 1e-6 * result.objective[0]
    assert result.mujoco_steps == result.residual_evaluations * target.steps


def test_same_fit_twice_gives_the_same_numbers(short_drop):
    target = _synthetic(short_drop, [1.2, 0.9])
    a, b = (fit([target], PARAMS, max_iter=4) for _ in range(2))
    assert np.array_equal(a.values, b.values) and a.objective == b.objective


def test_a_fit_stopped_early_says_so(short_drop):
    result = fit([_synthetic(short_drop, [1.5, 0.7])], PARAMS, max_iter=1)
    assert not result.converged and result.status == "maximum iterations reached."


def test_a_gain_beyond_its_bound_is_flagged(short_drop):
    result = fit([_synthetic(short_drop, [20.0, 1.0])], PARAMS, max_iter=15)
    assert result.values[0] == pytest.approx(PARAMS[0].upper)
    assert result.at_bound == ["solref.stiffness (upper bound 10)"]


def test_fitted_settings_reach_the_model():
    """The spec written for the user holds every fitted value, and its rollout is the fit's
    (a model copy with the pair arrays set) to the bit; leaving one field out shows."""
    scene = dataclasses.replace(load("box_slide"), duration=0.2)
    params = parse_fit("solref.stiffness,solref.damping,solreffriction.damping,friction.slide,impratio,solimp.width")
    values = [1.3, 0.8, 1.7, 0.9, 500.0, 0.002]
    target = prepare(scene, "penalty")
    spec, settings = calibrated_spec(scene, "penalty", target, params, values)
    compiled = spec.compile()
    reloaded = mujoco.MjModel.from_xml_string(spec.to_xml())
    rows = readback(params, settings, compiled, reloaded)
    assert len(rows) == 7 and all(r["compiled_equal"] and r["mjcf_equal"] for r in rows), rows
    assert read_model(compiled) == settings
    # mutation: a model that kept the base solref fails the read-back on exactly those rows
    stale = copy.copy(compiled)
    stale.pair_solref[:] = target.base.settings.solref
    bad = [r["parameter"] for r in readback(params, settings, stale, reloaded) if not r["compiled_equal"]]
    assert bad == ["solref.stiffness", "solref.damping"]
    with Batch(1) as b:
        fit_path = b.paths(target, [settings])[0]
        spec_path = b.paths(dataclasses.replace(target, model=compiled), [read_model(compiled)])[0]
        assert np.array_equal(fit_path, spec_path)
        # mutation: a copy that misses the friction coefficient is a different model
        wrong = dataclasses.replace(settings, friction=target.base.settings.friction)
        assert not np.array_equal(b.paths(target, [wrong])[0], fit_path)


def test_write_model_sets_every_pair():
    target = prepare(dataclasses.replace(load("box_drop"), duration=0.01), "penalty")
    s = calibrated(target.base, PARAMS, [2.0, 3.0])
    m = copy.copy(target.model)
    write_model(m, s)
    assert m.npair == 4 and np.all(m.pair_solref == np.array(s.solref))
    assert np.all(target.model.pair_solref != m.pair_solref)   # the base model is untouched


def test_reverse_fit_inverts_the_penalty_mapping():
    """custom_sim's k and c that follow the penalty twin of a point drop are the k and c the
    twin was made from (same linear law; the penalty force is off by only d m g)."""
    scene = drop_scene(0.5, 1e4, 20.0, duration=0.5)
    result = reverse_fit([prepare_reverse(scene, "penalty")], max_iter=10)
    k, c = result.values[:2]
    assert k == pytest.approx(1.0, abs=1e-2) and c == pytest.approx(1.0, abs=5e-2), result.parameters


def test_reverse_fit_finds_what_the_seed_mapping_means():
    """The seed mapping's spring is k / zeta^2 (zeta = 0.14 here): the reverse fit finds a much
    stiffer k than the scene's."""
    scene = drop_scene(0.5, 1e4, 20.0, duration=0.5)
    result = reverse_fit([prepare_reverse(scene, "seed")], max_iter=10)
    assert result.values[0] > 5.0, result.parameters


@pytest.mark.parametrize("argv,field", [
    (["calibrate", "--fit", "solref.bogus"], "--fit"),
    (["calibrate", "--fit", "solref.stiffness,solref.timeconst"], "--fit"),
    (["calibrate", "no_such_scene"], "no_such_scene"),
    (["calibrate", "box_slide", "--test", "box_slide"], "--test"),
])
def test_calibrate_bad_input_writes_nothing(argv, field, capsys, tmp_path):
    out = tmp_path / "cal"
    assert main(argv + ["--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and field in err[0]
    assert not out.exists()


def test_parse_fit_default_and_errors():
    assert [p.name for p in parse_fit(None)] == ["solref.stiffness", "solref.damping",
                                                 "solreffriction.damping", "friction.slide"]
    with pytest.raises(BadInput, match="twice"):
        parse_fit("impratio,impratio")


def test_calibration_files(tmp_path):
    """calibration.json has the contract's keys; the calibrated MJCF loads and is what was fitted."""
    import json

    from compare.tools.calibration.calibration import calibrate
    from compare.tools.calibration.report import write_calibration

    fitted = [dataclasses.replace(load("box_slide"), duration=0.1)]
    held = [dataclasses.replace(load("box_drop"), duration=0.1)]
    cal = calibrate(fitted, held, PARAMS, "penalty", max_iter=2, nthread=1)
    index = write_calibration(cal, tmp_path)
    data = json.loads((tmp_path / "calibration.json").read_text())
    assert set(data) >= {"parameters", "status", "converged", "scenes"}
    assert set(data["parameters"]) == {"solref.stiffness", "solref.damping"}
    assert [(s["name"], s["held_out"]) for s in data["scenes"]] == [("box_slide", False), ("box_drop", True)]
    for s in data["scenes"]:
        assert set(s["position_error_max"]) == {"seed", "physical", "penalty", "calibrated"}
        model = mujoco.MjModel.from_xml_path(str(tmp_path / f"model_{s['name']}.xml"))
        assert model.pair_solref[0] == pytest.approx(s["settings"]["solref"], rel=5e-6)
    assert data["fit"]["readback_ok"] and (tmp_path / "objective.png").is_file()
    assert "Objective against iterations" in index.read_text()


# A fit must not lose to the mapping it starts from on a scene it was fitted to.

def _fitted_pair():
    """box_slide (the penalty mapping follows it to 1e-5 m) and point_drop's first bounce
    (0.08 m off: the compression law MuJoCo cannot do), cut short."""
    return [dataclasses.replace(load("box_slide"), duration=0.3), dataclasses.replace(load("point_drop"), duration=0.45)]


def test_each_scene_is_measured_against_its_start_mappings_largest_error():
    """The ratios' units are each scene's largest position and angle difference under the
    penalty mapping, as targets.errors measures them on the same run (point_drop does not turn:
    no angle); point_drop's 0.08 m and box_slide's 1e-5 m both start at a largest ratio of 1."""
    from compare.tools.calibration.targets import errors

    targets = [prepare(s, "penalty") for s in _fitted_pair()]
    result = fit(targets, parse_fit(None), max_iter=1)
    with Batch(1) as b:
        for t in targets:
            e = errors(t, b.paths(t, [t.base.settings])[0])
            assert result.scales[t.name]["position"] == e["position_error_max"]
            assert result.scales[t.name]["angle"] == (e["angle_error_max"] if t.rotates else None)
    assert result.scales["box_slide"]["position"] < 1e-4 < result.scales["point_drop"]["position"]


# A two-scene problem in one parameter z where least squares trades a peak for the mean. Scene
# A: one step at 1 - z + 2 z^2 (its peak) and nine at 0.5 (1 - z); scene B: ten steps at 1 - z.
# Both start (z = 0) at a largest ratio of 1. The minimax is analytic: for 0 <= z <= 0.5, A's
# peak is above B, so max(A, B) = 1 - z + 2 z^2, smallest at z = 1/4 (A 0.875, B 0.75).
TOY_STEPS = 10
TOY_MINIMAX = (0.25, 0.875)


def _toy_rows(z):
    z = np.atleast_2d(z)[0]
    a = np.vstack([1 - z + 2 * z ** 2] + [0.5 * (1 - z)] * (TOY_STEPS - 1))
    return np.vstack([a] + [1 - z] * TOY_STEPS)


def _toy_worst(z):
    r = np.abs(_toy_rows(z))
    return np.column_stack([r[:TOY_STEPS].max(axis=0), r[TOY_STEPS:].max(axis=0)])


def test_the_fit_minimises_the_largest_ratio_where_least_squares_trades_the_peak():
    from mujoco import minimize

    from compare.tools.calibration.fit import PNorm, minimax

    bounds = (np.array([-2.0]), np.array([2.0]))
    # the old objective: each scene over its RMS at the start, least squares
    rms = np.sqrt(np.mean(_toy_rows(np.zeros((1, 1)))[:TOY_STEPS] ** 2))
    z_ls, _ = minimize.least_squares(
        np.zeros(1), lambda z: np.vstack([_toy_rows(z)[:TOY_STEPS] / rms, _toy_rows(z)[TOY_STEPS:]]),
        bounds=bounds, verbose=0)
    a_ls, b_ls = _toy_worst(z_ls[:, None])[0]
    assert a_ls > 1.1 and b_ls < 0.5          # A's peak rose for its mean and B's

    norm = PNorm(np.arange(2 * TOY_STEPS), np.full(2 * TOY_STEPS, 1.0 / TOY_STEPS))
    z, _, _, _, ratios = minimax(_toy_rows, _toy_worst, norm, np.zeros(1), *bounds, 12, 2)
    assert np.array_equal(ratios, _toy_worst(z[:, None])[0])
    assert z[0] == pytest.approx(TOY_MINIMAX[0], abs=0.05)
    # on the step_back grid, within 0.1 % of the analytic minimax; both scenes better than at the start
    assert TOY_MINIMAX[1] <= max(ratios) <= TOY_MINIMAX[1] * 1.001 and max(ratios) < 1.0


def test_step_back_never_returns_a_point_worse_than_the_start():
    """Where every point of the optimiser's step is worse on one scene, the fit keeps the start;
    where part of it is better, the best part (largest ratio first, then the next)."""
    from compare.tools.calibration.fit import step_back

    z0, z = np.zeros(1), np.ones(1)
    kept, ratios = step_back(lambda zz: np.column_stack([1 + zz[0], 1 - zz[0]]), z0, z, 2)
    assert kept == 0.0 and list(ratios) == [1.0, 1.0]
    kept, ratios = step_back(_toy_worst, z0, 0.5 * z, 2)   # toy: smallest largest ratio at z = 1/4
    assert kept == 0.5 and list(ratios) == [0.875, 0.75]


def test_calibrate_is_never_worse_than_the_penalty_mapping_on_a_fitted_scene():
    """Unweighted least squares made box_slide thirteen times worse (1.2e-5 m to 1.5e-4 m) to
    fit point_drop; the minimax improves both, point_drop more than twofold, and the fit is kept."""
    from compare.tools.calibration.calibration import calibrate

    cal = calibrate(_fitted_pair(), [], parse_fit(None), "penalty", max_iter=5, nthread=2)
    for s in cal.scenes:
        e = s.errors
        for key in ("position_error_max", "angle_error_max"):
            assert e["calibrated"][key] <= e["penalty"][key], (s.scene.name, key, e["calibrated"][key], e["penalty"][key])
    assert cal.accepted, cal.gave_up
    drop = next(s for s in cal.scenes if s.scene.name == "point_drop").errors
    assert drop["calibrated"]["position_error_max"] < 0.5 * drop["penalty"]["position_error_max"]


def test_a_fit_worse_on_a_fitted_scene_is_rejected_and_says_so(monkeypatch, tmp_path):
    """A fit that lands on a stiffness ten times the mapping's makes box_slide worse: the
    calibrated twin keeps the penalty mapping's values (the same run to the bit), and the status,
    calibration.json and index.md name the scene the fit gave up."""
    import json

    import compare.tools.calibration.calibration as calibration
    from compare.tools.calibration.report import write_calibration

    real = calibration.fit

    def stiff(*args, **kw):
        result = real(*args, **kw)
        return dataclasses.replace(result, values=np.array([10.0, 1.0, 1.0, 1.0]))

    monkeypatch.setattr(calibration, "fit", stiff)
    scene = dataclasses.replace(load("box_slide"), duration=0.3)
    cal = calibration.calibrate([scene], [], parse_fit(None), "penalty", max_iter=1, nthread=1)
    assert not cal.accepted and [g["scene"] for g in cal.gave_up] == ["box_slide"]
    (s,) = cal.scenes
    assert s.errors["calibrated"] == s.errors["penalty"]
    assert np.array_equal(s.paths["calibrated"], s.paths["penalty"])
    assert s.settings == cal.mapping_settings["box_slide"]["penalty"]
    assert cal.fitted_errors["box_slide"]["position_error_max"] > s.errors["penalty"]["position_error_max"]
    index = write_calibration(cal, tmp_path).read_text()
    data = json.loads((tmp_path / "calibration.json").read_text())
    assert "fit rejected" in data["status"] and data["accepted"] is False
    assert data["parameters"]["solref.stiffness"] == 1.0 and data["fitted_parameters"]["solref.stiffness"] == 10.0
    assert "The fit gave up box_slide" in index and "fit rejected" in index


# Exit status: 0 whenever a calibrated twin is written, 1 only when the fit could not run.

@pytest.fixture
def short_scenes(monkeypatch):
    """`calibrate` on its scenes cut to 0.2 s (a fast run of the real command)."""
    import compare.commands.calibrate as command

    real = command.load_all
    monkeypatch.setattr(command, "load_all",
                        lambda names: [dataclasses.replace(s, duration=0.2) for s in real(names)])


def test_a_rejected_fit_stopped_short_still_writes_the_twin_and_exits_0(short_scenes, monkeypatch, tmp_path,
                                                                        capsys):
    import compare.tools.calibration.calibration as calibration

    real = calibration.fit
    monkeypatch.setattr(calibration, "fit", lambda *a, **kw: dataclasses.replace(
        real(*a, **kw), values=np.array([10.0, 1.0, 1.0, 1.0])))
    out = tmp_path / "cal"
    assert main(["calibrate", "box_slide", "--max-iter", "1", "--threads", "1", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "NOT converged" in text and "fit rejected" in text
    assert "calibrated twin written (the penalty mapping's values): model_box_slide.xml" in text
    model = mujoco.MjModel.from_xml_path(str(out / "model_box_slide.xml"))
    target = prepare(dataclasses.replace(load("box_slide"), duration=0.2), "penalty")
    assert model.pair_solref[0] == pytest.approx(target.base.settings.solref, rel=5e-6)


def test_a_fit_that_cannot_run_exits_1_and_writes_nothing(short_scenes, monkeypatch, tmp_path, capsys):
    import compare.tools.calibration.calibration as calibration
    from custom_sim import SimulationDiverged

    def diverges(scene):
        raise SimulationDiverged(scene, "semi_implicit_euler", scene.dt, 3, np.full(6, np.nan))

    monkeypatch.setattr(calibration, "simulate", diverges)
    out = tmp_path / "cal"
    assert main(["calibrate", "box_slide", "--max-iter", "1", "--threads", "1", "--out", str(out)]) == 1
    assert "nothing written" in capsys.readouterr().out
    assert not out.exists() or not any(out.iterdir())


def test_a_fit_that_steps_back_to_the_start_says_the_twin_is_the_mapping(monkeypatch):
    """When no point of the optimiser's step is better on every fitted scene, the values are the
    start's, and the verdict and the command's output say the twin carries the mapping's values."""
    import compare.tools.calibration.calibration as calibration

    real = calibration.fit
    monkeypatch.setattr(calibration, "fit", lambda *a, **kw: dataclasses.replace(
        real(*a, **kw), values=np.ones(2), step_back=0.0))
    scene = dataclasses.replace(load("box_slide"), duration=0.1)
    cal = calibration.calibrate([scene], [], PARAMS, "penalty", max_iter=1, nthread=1)
    assert cal.accepted and cal.carries_mapping and "keeps the penalty mapping's values" in cal.verdict
    (s,) = cal.scenes
    assert np.array_equal(s.paths["calibrated"], s.paths["penalty"])
