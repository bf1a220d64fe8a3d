"""What the dynamics twin's contact law costs: ns per mj_step, measured in one run.

    python -m compare tools twin-speed [SCENE ...]     (default: every built-in scene)

For each scene and MuJoCo integrator (Euler, RK4), the CPU time per step of whole-run rollouts
(the fastest of REPEATS, after a warm-up) of

    native     the native twin: MuJoCo's own contact pairs and solver
    dynamics   the dynamics twin: no pairs, the seed's law in the compiled passive callback
    bare       the dynamics twin's model with no callback installed (MuJoCo's step alone: the
               difference to `dynamics` is what the callback costs)
"""
from __future__ import annotations

from mujoco_models.passive import installed, law_parameters
from mujoco_models.run import rollout_ns_per_step, setup_rollout
from mujoco_models.sites import contact_below_site

REPEATS = 3
INTEGRATORS = ("Euler", "RK4")


def speeds(scene, integrator: str, repeats: int = REPEATS) -> dict[str, float]:
    """{"native", "dynamics", "bare"}: CPU ns per mj_step (module docstring)."""
    _, model, data, start, n = setup_rollout(scene, integrator=integrator, dt=scene.dt)
    out = {"native": rollout_ns_per_step(model, data, start, n, repeats)}
    twin, model, data, start, n = setup_rollout(scene, integrator=integrator, dt=scene.dt, pairs="none")
    out["bare"] = rollout_ns_per_step(model, data, start, n, repeats)
    params = law_parameters(scene, twin.props, contact_below_site(scene.body),
                            native_normal=False, friction_at="corner")
    with installed(model, data, params):
        out["dynamics"] = rollout_ns_per_step(model, data, start, n, repeats)
    return out


def print_table(names: list[str]) -> int:
    """The speeds of the named scenes (default: every built-in scene), in Markdown; 0."""
    from compare.scenarios import builtin_names, load
    from compare.table import stream

    names = names or builtin_names()
    def rows():
        for name in names:
            scene = load(name)
            for integrator in INTEGRATORS:
                s = speeds(scene, integrator)
                yield [scene.name, integrator, *(f"{s[k]:.0f}" for k in ("native", "dynamics", "bare"))]
    stream(["scene", "integrator", "native twin (ns/step)", "dynamics twin, cfunc (ns/step)",
            "its model without callback (ns/step)"], rows())
    return 0
