"""A whole calibration: fit on some scenes, measure every mapping and the fit on all of them.

    calibrate(fitted, held_out, params) -> Calibration
    calibrated_spec(scene, base, params, values) -> (MjSpec, ContactSettings)

The calibrated MJCF is the base mapping's twin (mujoco_models.build_twin) with the fitted
settings written on its <pair>s. `readback` compiles that spec and also reloads the MJCF text
it writes, and reads every fitted setting back from the two MjModels: a value that never
reached the model shows there, not as a good-looking fit of the wrong model.

A fit must not lose to the mapping it starts from on a scene it was fitted to. The fit
minimises each scene's largest error relative to the start's (fit.py), and `calibrate` then
measures the fitted values on every fitted scene: where either largest difference (position, angle) is above the
base mapping's, the fit is rejected and the calibrated twin keeps the base mapping's values;
the Calibration names each scene the fit gave up, with both figures and why (`gave_up`).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import mujoco
import numpy as np

from custom_sim import Scene, simulate
from mujoco_models import MAPPINGS, build_twin

from scene_types import BadInput
from .fit import FitResult, fit
from .settings import ContactSettings, calibrated, read_model, write_spec
from .targets import Batch, Target, errors, prepare, residual_of

# MjSpec.to_xml writes 6 significant digits: a setting read back from the reloaded MJCF
# differs from the fitted one by at most half a unit in the 6th digit.
MJCF_RELATIVE_DIGITS = 5e-6


@dataclass
class SceneReport:
    scene: Scene
    held_out: bool
    errors: dict[str, dict]              # mapping or "calibrated" -> errors (targets.errors)
    paths: dict[str, np.ndarray]         # (steps + 1, 3) per mapping and calibrated
    reference: np.ndarray
    t: np.ndarray
    settings: ContactSettings            # the calibrated settings of this scene
    mjcf: str                            # the calibrated MJCF text
    readback: list[dict] = field(default_factory=list)


@dataclass
class Calibration:
    params: tuple
    base: str
    result: FitResult
    scenes: list[SceneReport]
    jacobian: dict = field(default_factory=dict)   # fit.jacobian_cost
    mapping_settings: dict = field(default_factory=dict)   # scene -> mapping -> ContactSettings
    # the values the calibrated twin carries: the fit's, or the base mapping's when rejected
    values: np.ndarray | None = None
    gave_up: list[dict] = field(default_factory=list)      # fitted scenes the fit made worse
    fitted_errors: dict = field(default_factory=dict)      # scene -> errors of the fit's values

    @property
    def accepted(self) -> bool:
        return not self.gave_up

    @property
    def carries_mapping(self) -> bool:
        """The calibrated twin carries the base mapping's values: the fit was rejected, or no point
        of the optimiser's step was better on every fitted scene (fit.step_back kept none of it)."""
        return not self.accepted or self.result.step_back == 0.0

    @property
    def verdict(self) -> str:
        """One sentence: the fit kept, or rejected with the scenes it gave up and why."""
        if self.accepted and self.carries_mapping:
            return (f"no point of the optimiser's step lowers the largest difference of every fitted scene: "
                    f"the calibrated twin keeps the {self.base} mapping's values")
        if self.accepted:
            return f"fit kept: no fitted scene is worse than with the {self.base} mapping"
        names = ", ".join(g["scene"] for g in self.gave_up)
        which = "a scene" if len(self.gave_up) == 1 else "scenes"
        return (f"fit rejected: worse than the {self.base} mapping on {names} ({which} it was fitted to); "
                f"the calibrated twin keeps the {self.base} mapping's values")


def calibrated_spec(scene: Scene, base: str, target: Target, params, values):
    """The base twin's spec with the calibrated settings on its pairs."""
    settings = calibrated(target.base, params, values)
    spec = build_twin(scene, base, integrator=None).spec
    write_spec(spec, settings)
    return spec, settings


def readback(params, settings: ContactSettings, compiled, reloaded) -> list[dict]:
    """One row per fitted parameter and entry: the value fitted, and what the compiled spec's
    and the reloaded MJCF's MjModel hold (pair 0, checked equal across pairs)."""
    rows = []
    got_c, got_x = read_model(compiled), read_model(reloaded)
    for p in params:
        for i in p.index:
            want = settings.field(p.field)[i]
            a, b = got_c.field(p.field)[i], got_x.field(p.field)[i]
            rows.append({"parameter": p.name, "field": f"{'pair_' if p.field != 'impratio' else 'opt.'}"
                         f"{p.field}[{i}]" if p.field != "impratio" else "opt.impratio",
                         "fitted": want, "compiled": a, "mjcf": b, "compiled_equal": a == want,
                         "mjcf_equal": abs(b - want) <= MJCF_RELATIVE_DIGITS * abs(want)})
    return rows


def calibrate(fitted: list[Scene], held_out: list[Scene], params, base: str,
              max_iter: int, nthread: int = 2) -> Calibration:
    scenes = [(s, False) for s in fitted] + [(s, True) for s in held_out]
    references = {s.name: simulate(s) for s, _ in scenes}
    targets = {s.name: prepare(s, base, references[s.name]) for s, _ in scenes}
    if any(p.form == "positive" for p in params):
        for s, _ in scenes:
            ref = targets[s.name].base.settings.solref
            if not (ref[0] > 0.0 and ref[1] > 0.0):
                raise BadInput(f"{s.source}: contact.c: the physical mapping of c = 0 is in the direct form "
                               f"{ref} (expected c > 0 to fit solref.timeconst/solref.dampratio)")
    fit_targets = [targets[s.name] for s in fitted]
    result = fit(fit_targets, params, max_iter=max_iter, nthread=nthread)
    cost = {}   # fit.jacobian_cost times one Jacobian two ways: a measurement, not run here
    mapping_settings = {}

    def calibrated_run(scene, values, batch):
        target = targets[scene.name]
        spec, settings = calibrated_spec(scene, base, target, params, values)
        compiled = spec.compile()
        xml = spec.to_xml()
        reloaded = mujoco.MjModel.from_xml_string(xml)
        # the calibrated path is the compiled spec's own rollout (what a user gets)
        model_target = dataclasses.replace(target, model=compiled)
        path = batch.paths(model_target, [read_model(compiled)])[0]
        return path, settings, xml, readback(params, settings, compiled, reloaded)

    reports = []
    with Batch(nthread) as batch:
        for scene, held in scenes:
            target = targets[scene.name]
            errs, paths = {}, {}
            for mapping in MAPPINGS:
                t = target if mapping == base else prepare(scene, mapping, references[scene.name])
                if mapping == base and scene.name in result.start_paths:
                    paths[mapping] = result.start_paths[scene.name]   # the fit's start: the same run
                else:
                    paths[mapping] = batch.paths(t, [t.base.settings])[0]
                mapping_settings.setdefault(scene.name, {})[mapping] = t.base.settings
                errs[mapping] = errors(target, paths[mapping])
            paths["calibrated"], settings, xml, rows = calibrated_run(scene, result.values, batch)
            errs["calibrated"] = errors(target, paths["calibrated"])
            reports.append(SceneReport(scene, held, errs, paths, target.reference,
                                       np.arange(target.steps + 1) * target.dt, settings, xml, rows))
        fitted_errors = {r.scene.name: dict(r.errors["calibrated"]) for r in reports}
        gave_up = [given_up(r, base, targets[r.scene.name], [s.name for s in fitted if s.name != r.scene.name])
                   for r in reports if not r.held_out and worse(r.errors["calibrated"], r.errors[base])]
        values = result.values
        if gave_up:
            # rejected: every scene's calibrated twin is the base mapping's (the fit's start)
            values = result.start
            for r in reports:
                r.paths["fitted"] = r.paths["calibrated"]
                r.paths["calibrated"], r.settings, r.mjcf, r.readback = calibrated_run(r.scene, values, batch)
                r.errors["calibrated"] = errors(targets[r.scene.name], r.paths["calibrated"])
    return Calibration(tuple(params), base, result, reports, cost, mapping_settings, values, gave_up,
                       fitted_errors)


def worse(fitted: dict, start: dict) -> bool:
    """The fitted twin's errors (targets.errors) above the start mapping's: a larger largest
    difference in position or angle, or a run that diverged where the start's did not."""
    if fitted["diverged"] or start["diverged"]:
        return fitted["diverged"] and not start["diverged"]
    return (fitted["position_error_max"] > start["position_error_max"]
            or fitted["angle_error_max"] > start["angle_error_max"])


def given_up(report: SceneReport, base: str, target: Target, others: list[str]) -> dict:
    """What the fit did to a fitted scene it made worse: the largest differences and the RMS
    difference (targets.residual_of: position, and angle times the radius of gyration), with the
    base mapping's and the fitted values (the runs already in the report), and why in a sentence."""
    rms = {key: float(np.linalg.norm(residual_of(target, report.paths[run][None])))
           for key, run in ((base, base), ("fitted", "calibrated"))}
    e0, e1 = report.errors[base], report.errors["calibrated"]
    out = {"scene": report.scene.name,
           "position_error_max": {base: e0["position_error_max"], "fitted": e1["position_error_max"]},
           "angle_error_max": {base: e0["angle_error_max"], "fitted": e1["angle_error_max"]},
           "residual_rms": {base: rms[base], "fitted": rms["fitted"]}}
    if e1["diverged"]:
        why = "the fitted values make its run diverge"
    elif rms["fitted"] <= rms[base]:
        why = (f"the fit lowered its RMS difference ({rms[base]:.3g} m to {rms['fitted']:.3g} m) but not "
               f"its largest ({_pair(e0, e1)}): the peak rose while the mean fell")
    elif not others:
        why = (f"the optimiser ended above its start ({_pair(e0, e1)}; RMS {rms[base]:.3g} m to "
               f"{rms['fitted']:.3g} m)")
    else:
        why = (f"the fitted values raise its difference ({_pair(e0, e1)}; RMS {rms[base]:.3g} m to "
               f"{rms['fitted']:.3g} m) to lower that of {', '.join(others)}: one set of contact settings "
               f"cannot follow them all (what no setting removes is listed below)")
    out["why"] = why
    return out


def _pair(e0: dict, e1: dict) -> str:
    text = f"{e0['position_error_max']:.3g} m to {e1['position_error_max']:.3g} m"
    if e1["angle_error_max"] > e0["angle_error_max"]:
        text += f", angle {e0['angle_error_max']:.3g} rad to {e1['angle_error_max']:.3g} rad"
    return text
