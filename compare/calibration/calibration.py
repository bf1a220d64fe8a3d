"""A whole calibration: fit on some scenes, measure every mapping and the fit on all of them.

    calibrate(fitted, held_out, params) -> Calibration
    calibrated_spec(scene, base, params, values) -> (MjSpec, ContactSettings)

The calibrated MJCF is the base mapping's twin (mujoco_models.build_twin) with the fitted
settings written on its <pair>s. `readback` compiles that spec and also reloads the MJCF text
it writes, and reads every fitted setting back from the two MjModels: a value that never
reached the model shows there, not as a good-looking fit of the wrong model.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import mujoco
import numpy as np

from custom_sim import Scene, simulate
from mujoco_models import MAPPINGS, build_twin

from ..cli import BadInput
from .fit import FitResult, fit, jacobian_cost
from .settings import ContactSettings, calibrated, read_model, write_spec
from .targets import Batch, Target, errors, prepare

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
    cost = jacobian_cost(fit_targets, params, nthread)
    mapping_settings = {}

    reports = []
    with Batch(nthread) as batch:
        for scene, held in scenes:
            target = targets[scene.name]
            errs, paths = {}, {}
            for mapping in MAPPINGS:
                t = target if mapping == base else prepare(scene, mapping, references[scene.name])
                paths[mapping] = batch.paths(t, [t.base.settings])[0]
                mapping_settings.setdefault(scene.name, {})[mapping] = t.base.settings
                errs[mapping] = errors(target, paths[mapping])
            spec, settings = calibrated_spec(scene, base, target, params, result.values)
            compiled = spec.compile()
            xml = spec.to_xml()
            reloaded = mujoco.MjModel.from_xml_string(xml)
            # the calibrated path is the compiled spec's own rollout (what a user gets)
            model_target = dataclasses.replace(target, model=compiled)
            paths["calibrated"] = batch.paths(model_target, [read_model(compiled)])[0]
            errs["calibrated"] = errors(target, paths["calibrated"])
            reports.append(SceneReport(scene, held, errs, paths, target.reference,
                                       np.arange(target.steps + 1) * target.dt, settings, xml,
                                       readback(params, settings, compiled, reloaded)))
    return Calibration(tuple(params), base, result, reports, cost, mapping_settings)
