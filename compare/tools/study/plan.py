"""A study's runs: the cartesian product of the varied values, for every integrator, in batches.

    point   one combination of the varied values: one scene, one MuJoCo twin, one reference
    run     a point with one integrator of one simulator (custom_sim, or with --sim yours):
            one row of study.csv
    batch   points whose runs one task simulates in one compiled call (custom_sim.batch) and
            whose twins it rolls out together (mujoco_models.batch)

Every run has a key, a hash of everything its result depends on (the varied scene, the
integrator, the sampling, STUDY_VERSION and, for yours, the text of the code shipped), so a
study started again finds what it already has.
"""
from __future__ import annotations

import dataclasses
import hashlib
import itertools
from dataclasses import dataclass

import numpy as np

from custom_sim import INTEGRATORS, Scene
from scene_types.schema import MujocoSettings, Tolerance

from ...oracle.reference import REFERENCE_VERSION
from .fields import SceneSource, Vary

# Bump when what a run measures changes: results kept from an older version are not reused.
STUDY_VERSION = 1
# s: errors are read every SAMPLE seconds (or every step when the step is longer), as in the
# work-precision sweep: a 2 s run has 1000 samples.
SAMPLE = 2e-3
# Estimated cost of a batch (s): far above Dask's per-task overhead (about 1 ms) and short
# enough that a dead worker loses little and the progress bar moves.
BATCH_SECONDS = 0.25
# Rough costs for packing batches (s per force evaluation; s per MuJoCo stage).
CUSTOM_EVAL_COST = 80e-9
IMPLICIT_EVALS_PER_STEP = 12
MUJOCO_STAGE_COST = 2e-6
YOUR_STEP_COST = 30e-6   # a step written in Python and numpy, as the examples are


@dataclass(frozen=True)
class Run:
    """simulator: "custom_sim", or "yours" (the user's --sim, run from its shipped copy)."""

    values: tuple
    integrator: str
    scene: Scene
    key: str
    simulator: str = "custom_sim"


@dataclass(frozen=True)
class Yours:
    """The user's simulator in a study: its shipped code (compare.usersim.bundle.Bundle) and the
    integrators it runs: the one it declares (INTEGRATOR), else each of the study's, told to it
    by the scene dict's `integrator`."""

    bundle: object
    integrators: tuple[str, ...]


@dataclass(frozen=True)
class Point:
    """values: one per varied field; scene: the varied scene (its own integrator); runs: one per
    integrator; physics: the key of its reference (the scene without dt, integrator, twin)."""

    values: tuple
    scene: Scene
    runs: tuple[Run, ...]
    physics: str

    @property
    def key(self) -> str:
        return _hash(tuple(r.key for r in self.runs))


def _hash(obj) -> str:
    return hashlib.sha1(repr(obj).encode()).hexdigest()[:16]


def sample_rows(scene: Scene) -> np.ndarray:
    """Step indices read for the errors: the step nearest each multiple of SAMPLE (every step
    when dt > SAMPLE), 0 and the last step included."""
    n = scene.steps
    k = np.arange(int(round(scene.duration / SAMPLE)) + 1)
    rows = np.unique(np.clip(np.rint(k * SAMPLE / scene.dt).astype(np.int64), 0, n))
    if scene.dt > SAMPLE:
        rows = np.arange(n + 1)
    return np.union1d(rows, [0, n])


def sample_times(scene: Scene) -> np.ndarray:
    return sample_rows(scene) * scene.dt


def physics_scene(scene: Scene) -> Scene:
    """What the reference depends on: the scene without its step, integrator and twin settings."""
    return dataclasses.replace(scene, dt=min(scene.duration, SAMPLE), integrator="semi_implicit_euler",
                               mujoco=MujocoSettings(), tolerance=Tolerance(), description="",
                               source="")


def _yours_scene(scene: Scene, integrator: str) -> Scene:
    """The scene the user's code is given: the integrator it runs, where the harness knows it."""
    return dataclasses.replace(scene, integrator=integrator) if integrator in INTEGRATORS else scene


def plan(source: SceneSource, varies: list[Vary], integrators: list[str], yours: Yours | None = None) -> list[Point]:
    """Every point of the product, in the order of the command line (last field fastest); with
    `yours`, each point's runs of the user's code after custom_sim's."""
    points = []
    for values in itertools.product(*(v.values for v in varies)):
        scene = source.varied(varies, values)
        runs = []
        for name in integrators:
            sc = dataclasses.replace(scene, integrator=name)
            key = _hash((STUDY_VERSION, REFERENCE_VERSION, SAMPLE, name,
                         repr(dataclasses.replace(sc, source=""))))
            runs.append(Run(values, name, sc, key))
        for name in (yours.integrators if yours else ()):
            sc = _yours_scene(scene, name)
            key = _hash((STUDY_VERSION, REFERENCE_VERSION, SAMPLE, "yours", name, yours.bundle.digest,
                         yours.bundle.whole, yours.bundle.function, repr(dataclasses.replace(sc, source=""))))
            runs.append(Run(values, name, sc, key, "yours"))
        points.append(Point(values, scene, tuple(runs), _hash(repr(physics_scene(scene)))))
    return points


def estimated_cost(point: Point, twin: bool) -> float:
    """Seconds one point's runs take, roughly (for packing batches only)."""
    steps = point.scene.steps
    cost = 0.0
    for run in point.runs:
        if run.simulator == "yours":
            cost += steps * YOUR_STEP_COST
            continue
        per = INTEGRATORS[run.integrator].evals_per_step or IMPLICIT_EVALS_PER_STEP
        cost += steps * per * CUSTOM_EVAL_COST
    if twin:
        mj = point.scene.mujoco
        mj_steps = int(round(point.scene.duration / (mj.dt or point.scene.dt)))
        cost += mj_steps * (4 if mj.integrator == "RK4" else 1) * MUJOCO_STAGE_COST
    return cost


# Batches per worker at least, when the study is small: the last batches to finish keep one
# worker busy while the others wait, so each is a small share of a worker's work.
BATCHES_PER_WORKER = 6


def batches(points: list[Point], twin: bool, target: float = BATCH_SECONDS, workers: int = 1) -> list[list[Point]]:
    """Points packed in order into batches of about `target` seconds, or smaller, so that each
    of `workers` gets BATCHES_PER_WORKER of them (at least one point each); the costliest batch
    first, so that the cheap ones fill the end. Points of one physics key stay near each
    other, so a batch needs few references."""
    priced = sorted(((p, estimated_cost(p, twin)) for p in points), key=lambda pc: pc[0].physics)
    target = min(target, sum(c for _, c in priced) / (BATCHES_PER_WORKER * max(1, workers)))
    out, current, spent = [], [], 0.0   # out: (batch, its cost)
    for point, cost in priced:
        if current and spent + cost > target:
            out.append((current, spent))
            current, spent = [], 0.0
        current.append(point)
        spent += cost
    if current:
        out.append((current, spent))
    return [batch for batch, cost in sorted(out, key=lambda bc: -bc[1])]
