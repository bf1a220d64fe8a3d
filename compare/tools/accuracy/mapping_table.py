"""How far each solref mapping's twin lands from the hand-written simulator, per scene.

    python -m compare tools mapping-table [SCENE ...]     (default: every built-in scene)

prints, for each scene, the maximum distance (m) between the COM of simulate(scene) and of
simulate_mujoco(scene, solref=mapping) for the three mappings; the same for the penalty twin
against our run with damping_law = "linear" (MuJoCo's own law: what is left is the friction
law and the mapping); and MuJoCo's time per mj_step (ns, the fastest of REPEATS rollouts).
"""
from __future__ import annotations

import dataclasses

import numpy as np

from custom_sim import Scene, simulate

from mujoco_models.run import rollout_ns_per_step, setup_rollout, simulate_mujoco
from mujoco_models.solref import MAPPINGS

REPEATS = 3


def max_position_difference(a, b) -> float:
    """max over the run of |COM_a - COM_b| (m); both trajectories on the same time grid."""
    if a.steps != b.steps:
        raise ValueError(f"different step counts {a.steps} and {b.steps}: compare on the same dt")
    return float(np.max(np.hypot(a.x - b.x, a.y - b.y)))


def mapping_errors(scene: Scene) -> dict:
    """{mapping: m, "penalty_vs_linear_law": m, "ns_per_step": ns} for one scene."""
    ours = simulate(scene)
    out = {}
    for mapping in MAPPINGS:
        out[mapping] = max_position_difference(ours, simulate_mujoco(scene, solref=mapping))
    linear = dataclasses.replace(scene, contact=dataclasses.replace(scene.contact, damping_law="linear"))
    twin = simulate_mujoco(scene, solref="penalty")
    out["penalty_vs_linear_law"] = max_position_difference(simulate(linear), twin)
    out["ns_per_step"] = ns_per_step(scene)
    return out


def ns_per_step(scene: Scene, repeats: int = REPEATS) -> float:
    """CPU ns per mj_step of the scene's twin, the fastest of `repeats` whole-run rollouts."""
    _, model, data, start, n = setup_rollout(scene)
    return rollout_ns_per_step(model, data, start, n, repeats)


def print_table(names: list[str]) -> int:
    """The table of the named scenes (default: every built-in scene), in Markdown; 0."""
    from compare.scenarios import builtin_names, load
    from compare.table import stream

    names = names or builtin_names()
    def rows():
        for name in names:
            e = mapping_errors(load(name))
            yield [name, *(f"{e[k]:.3g}" for k in ("penalty", "physical", "seed", "penalty_vs_linear_law")),
                   f"{e['ns_per_step']:.0f}"]
    stream(["scene", "penalty (m)", "physical (m)", "seed (m)", "penalty vs our linear law (m)", "CPU ns per mj_step"],
           rows())
    return 0
