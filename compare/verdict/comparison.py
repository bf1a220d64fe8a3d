"""One scenario, both simulators: run, measure, judge. The report is written from its result."""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from custom_sim import Scene, SimulationDiverged, Trajectory, simulate, stable_step
from custom_sim.scene import SOLREF_MAPPINGS

from . import events, metrics, tolerance


@dataclass
class Result:
    scene: Scene
    custom: Trajectory | None = None
    mujoco: Trajectory | None = None                  # with the scene's own mapping
    by_mapping: dict = field(default_factory=dict)    # mapping -> metrics (and drift, meta)
    metrics: dict = field(default_factory=dict)
    tolerance: tolerance.Tolerance | None = None
    passed: bool = False
    error: str | None = None                          # divergence: why no report was written
    ablation: dict | None = None                      # the same comparison with friction off

    @property
    def status(self) -> str:
        if self.error:
            return "diverged"
        return "pass" if self.passed else "FAIL"


def run_scenario(scene: Scene) -> Result:
    """Run the scene in custom_sim and in MuJoCo with every solref mapping; compare."""
    result = Result(scene)
    try:
        custom = simulate(scene)
    except SimulationDiverged as exc:
        result.error = str(exc)
        return result
    from mujoco_models import simulate_mujoco
    result.custom = custom
    own = scene.mujoco.solref
    for mapping in (own,) + tuple(m for m in SOLREF_MAPPINGS if m != own):
        try:
            twin = simulate_mujoco(scene, solref=mapping)
        except SimulationDiverged as exc:
            if mapping == own:
                result.error = f"MuJoCo ({mapping}): {exc}"
                return result
            result.by_mapping[mapping] = {"error": str(exc)}
            continue
        row = metrics.compare(custom, twin)
        row["energy_drift_mujoco"] = metrics.energy_drift(twin)
        row["wall_time_mujoco"] = twin.wall_time
        tol = tolerance.derive(scene, mapping)
        row["tolerance_position"] = tol.position if tol.checked else None
        row["pass"] = tolerance.judge(tol, row) if tol.checked else None
        result.by_mapping[mapping] = row
        if mapping == own:
            result.mujoco = twin
            result.metrics = row
            result.tolerance = tol
    result.passed = tolerance.judge(result.tolerance, result.metrics)
    if scene.has("friction") and result.tolerance.checked:
        result.ablation = without_friction(scene)
        result.passed = result.passed and result.ablation["pass"]
    return result


def without_friction(scene: Scene) -> dict:
    """Both simulators again with friction (and rolling resistance) off: what the two models
    share must then agree within the tolerance left when the friction terms are dropped."""
    from mujoco_models import simulate_mujoco

    bare = dataclasses.replace(scene, effects=tuple(e for e in scene.effects if "friction" not in e))
    row = metrics.compare(simulate(bare), simulate_mujoco(bare))
    tol = tolerance.derive(bare)
    row.update(tolerance_position=tol.position, tolerance_angle=tol.angle, reason=tol.reason,
               effects=list(bare.effects), **{"pass": tolerance.judge(tol, row)})
    return row


def metrics_json(result: Result) -> dict:
    """metrics.json: the keys docs/report-files.md promises, then ours."""
    scene, custom, twin, tol = result.scene, result.custom, result.mujoco, result.tolerance
    m = result.metrics
    limit = stable_step(scene)
    return {
        "name": scene.name,
        "integrator": scene.integrator,
        "dt": scene.dt,
        "steps": scene.steps,
        "position_error_max": m["position_error_max"],
        "position_error_rms": m["position_error_rms"],
        "angle_error_max": m["angle_error_max"],
        "energy_drift_custom": metrics.energy_drift(custom),
        "energy_drift_mujoco": metrics.energy_drift(twin),
        "tolerance": {"position": tol.position, "angle": tol.angle, "terms": tol.terms,
                      "reason": tol.reason, "mapping": scene.mujoco.solref, "checked": tol.checked},
        "pass": result.passed,
        "wall_time_custom": custom.wall_time,
        "wall_time_mujoco": twin.wall_time,
        # ours
        "description": scene.description,
        "shape": scene.body.shape,
        "effects": list(scene.effects),
        "velocity_error_max": m["velocity_error_max"],
        "angular_velocity_error_max": m["angular_velocity_error_max"],
        "position_error_final": m["position_error_final"],
        "time_of_position_error_max": m["time_of_position_error_max"],
        "energy_initial": float(custom.energy[0]),
        "force_evals_custom": custom.force_evals,
        "newton_iterations_custom": custom.newton_iterations,
        "stable_dt_theory": None if limit == float("inf") else limit,
        "dt_within_stability_limit": scene.dt < limit,
        "events_custom": events.events(scene, custom),
        "events_mujoco": events.events(scene, twin),
        "mujoco": {k: v for k, v in twin.meta.items()},
        "mujoco_integrator": twin.integrator,
        "mujoco_dt": twin.dt,
        "mappings": result.by_mapping,
        "without_friction": result.ablation,
    }
