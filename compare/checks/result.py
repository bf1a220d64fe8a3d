"""One scenario's result: what the checks found, and metrics.json written from it.

    Result          the scene, the runs, one CheckRow per check, the diagnosis, the status
    metrics_json    metrics.json of a scene that reached a verdict (docs/report-files.md)
    skipped_json    metrics.json of a scene the user's code does not do
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from custom_sim import Scene, Trajectory

from . import events, metrics
from .case import Case
from .row import CheckRow
from .status import Status, of_rows

CUSTOM = "custom_sim"
SHOWN = ("reference", "native")    # checks that are shown, not judged, by design


@dataclass
class Result:
    scene: Scene
    under_test: Trajectory | None = None              # the simulator under test
    custom: Trajectory | None = None                  # custom_sim with the scene's integrator
    runs: dict = field(default_factory=dict)          # custom_sim by integrator: Trajectory or the failure text
    mujoco: Trajectory | None = None                  # native twin, the scene's own mapping
    by_mapping: dict = field(default_factory=dict)    # mapping -> metrics (and drift)
    metrics: dict = field(default_factory=dict)       # under test against the native twin
    checks: list[CheckRow] = field(default_factory=list)   # one row per check
    attribution: list = field(default_factory=list)   # the measured ladder of causes
    residuals: dict = field(default_factory=dict)     # per-step residuals of the step checks (plots)
    reference: np.ndarray | None = None               # converged reference states (steps + 1, 6), for the plots
    warnings: list = field(default_factory=list)      # e.g. dt outside the theory's limit
    diagnosis: dict | None = None                     # a user's simulator: which mistake explains it
    simulator: str = CUSTOM                           # name of the simulator under test
    error: str | None = None                          # why no verdict could be reached
    unstable: bool = False                            # the error is a divergence or chatter
    error_details: str = ""                           # the user's own traceback, where their code raised
    skipped: str | None = None                        # why the user's code does not do this scene (never judged)
    keeps_state: str | None = None                    # a step function whose answer depends on earlier calls
    law_differences: list = field(default_factory=list)  # `run --law`: each effect that differs from the scene's
    balances: dict = field(default_factory=dict)      # simulator -> compare.energy.Balance (E, W, R)
    case: Case | None = None                          # the scene and the runs its checks shared
    stable_dt: float = float("inf")                   # s, the theory's stable step for the scene's integrator
    stable_dt_reason: str = ""                        # what sets it

    @property
    def judged(self) -> list[CheckRow]:
        return [c for c in self.checks if c.passed is not None]

    @property
    def failed(self) -> list[CheckRow]:
        return [c for c in self.checks if c.passed is False]

    @property
    def passed(self) -> bool:
        """Every judged check passed, and at least one was judged."""
        return self.error is None and not self.failed and bool(self.judged)

    @property
    def not_judged(self) -> list[CheckRow]:
        return [c for c in self.checks if c.passed is None and c.name not in SHOWN]

    @property
    def status(self) -> Status:
        if self.skipped:
            return Status.SKIPPED
        if self.error:
            return Status.UNSTABLE if self.unstable else Status.ERROR
        return of_rows(self.checks)


def metrics_json(result: Result) -> dict:
    """metrics.json: the keys docs/report-files.md promises, then ours."""
    from ..energy import metrics_block

    scene, tested, twin, custom = result.scene, result.under_test, result.mujoco, result.custom
    assert tested is not None and twin is not None and custom is not None, "a verdict has its runs"
    m = result.metrics
    limit = result.stable_dt
    contact = next((c for c in result.checks if c.name == "contact"), None)
    return {
        "name": scene.name,
        "integrator": scene.integrator,
        "dt": scene.dt,
        "steps": scene.steps,
        "position_error_max": m["position_error_max"],
        "position_error_rms": m["position_error_rms"],
        "angle_error_max": m["angle_error_max"],
        "energy_drift_custom": metrics.energy_drift(tested),
        "energy_drift_mujoco": metrics.energy_drift(twin),
        "tolerance": {c.label: {"position": c.tolerance_position, "angle": c.tolerance_angle, "reason": c.reason}
                      for c in result.checks},
        "pass": result.passed,
        "wall_time_custom": tested.wall_time,
        "wall_time_mujoco": twin.wall_time,
        "checks": [c.to_json() for c in result.checks],
        # ours
        "simulator": result.simulator,
        "integrator_under_test": tested.integrator,
        "status": result.status.value,
        "not_judged": [c.label for c in result.not_judged],
        "failed_checks": [c.label for c in result.failed],
        "warnings": result.warnings,
        "description": scene.description,
        "shape": scene.body.shape,
        "effects": list(scene.effects),
        "velocity_error_max": m["velocity_error_max"],
        "angular_velocity_error_max": m["angular_velocity_error_max"],
        "position_error_final": m["position_error_final"],
        "time_of_position_error_max": m["time_of_position_error_max"],
        "energy_initial": float(tested.energy[0]),
        "force_evals_custom": custom.force_evals,
        "newton_iterations_custom": custom.newton_iterations,
        "stable_dt_theory": None if limit == float("inf") else float(limit),
        "stable_dt_reason": result.stable_dt_reason,
        "dt_within_stability_limit": not result.warnings,
        "events_custom": events.events(scene, tested),
        "events_mujoco": events.events(scene, twin),
        "mujoco": dict(twin.meta),
        "mujoco_integrator": twin.integrator,
        "mujoco_dt": twin.dt,
        "mappings": result.by_mapping,
        "attribution": result.attribution,
        "contact_check": None if contact is None else contact.to_json(),
        "diagnosis": result.diagnosis,
        "law": law_json(result),
        "energy_balance": {name: {**metrics_block(b), "rule": b.rule} for name, b in result.balances.items()},
    }


def skipped_json(result: Result) -> dict:
    """metrics.json of a scene the user's code skipped: what the scene is, the status and the
    reason; no check (none was judged, nothing ran)."""
    scene = result.scene
    return {"name": scene.name, "integrator": scene.integrator, "dt": scene.dt, "steps": scene.steps,
            "status": Status.SKIPPED.value, "skipped": result.skipped, "pass": None, "checks": [],
            "simulator": result.simulator, "description": scene.description, "shape": scene.body.shape,
            "effects": list(scene.effects), "law": {"from": scene.law_from or "scene",
                                                    "judged": dataclasses.asdict(scene.contact)}}


def law_json(result: Result) -> dict:
    """The contact law the checks used, where it came from, and (under `run --law`) the scene
    file's own law and each effect that differs."""
    scene = result.scene
    out = {"from": scene.law_from or "scene", "judged": dataclasses.asdict(scene.contact)}
    if scene.scene_contact is not None:
        out["scene"] = dataclasses.asdict(scene.scene_contact)
        out["differences"] = result.law_differences
    return out
