"""Hold a simulator to the checks that need no MuJoCo, and print its diagnosis (writes nothing).

    python -m compare.usersim.validate examples/seed_sim.py:step [SCENE ...]
    python -m compare.usersim.validate examples/buggy_sim.py:step box_drop --markdown
    python -m compare.usersim.validate --trajectories DIR [SCENE ...]

Per scene: `identical` (against custom_sim, same integrator and dt, to round-off), `step` (every
step against one independent step) and the diagnosis. Exit status 0 when every judged check
passes and at least one was judged, 1 otherwise, 2 for bad input. `python -m compare run --sim ...` adds the MuJoCo checks
and the report pages.
"""
from __future__ import annotations

import argparse
import sys


def _cell(row) -> str:
    """A CheckRow in a few words."""
    if row.passed is None:
        return "not judged"
    word = "pass" if row.passed else "FAIL"
    return f"{word} {row.position_error_max:.2e} m / {row.tolerance_position:.2e} m"


def main(argv=None) -> int:
    from scene_types import BadInput
    from custom_sim import SceneError

    p = argparse.ArgumentParser(prog="python -m compare.usersim.validate", description=__doc__.splitlines()[0])
    p.add_argument("sim", nargs="?", metavar="MODULE:FUNCTION")
    p.add_argument("scenes", nargs="*", metavar="SCENE")
    p.add_argument("--whole", action="store_true")
    p.add_argument("--trajectories", metavar="DIR")
    p.add_argument("--markdown", action="store_true", help="print each scene's diagnosis section in full")
    args = p.parse_args(argv)
    if args.trajectories and args.sim:  # with --trajectories the first positional is a scene
        args.scenes, args.sim = [args.sim, *args.scenes], None
    try:
        return _validate(args)
    except (SceneError, BadInput) as exc:
        details = getattr(exc, "details", "")
        if details:
            print(details, file=sys.stderr)
        print(f"error: {exc}", file=sys.stderr)
        return 2


def _validate(args) -> int:
    from ..scenarios import load_all
    from ..checks.identical_check import check_identical
    from ..checks.step_check import check_step
    from . import diagnosis, load_simulator, render_markdown, run_user

    from . import UserFault, preflight

    sim = load_simulator(args.sim, args.whole, args.trajectories)
    if sim is None:
        raise SystemExit("expected MODULE:FUNCTION or --trajectories DIR")
    scenes = load_all(args.scenes)
    preflight(sim, scenes)
    ok, judged = True, 0
    print(f"{'scene':<16} {'identical':<34} {'step':<34} diagnosis")
    for scene in scenes:
        try:
            traj = run_user(sim, scene)
        except UserFault as exc:   # this scene's fault: its line, the others still judged
            ok = False
            print(f"{scene.name:<16} error: {exc}")
            if exc.details:
                print(exc.details, file=sys.stderr)
            continue
        states = traj.states()
        same = check_identical(scene, states, traj.integrator, scene.dt, traj.meta["rounding"])
        step = check_step(scene, states, traj.integrator, scene.dt, rounding=traj.meta["rounding"])
        diag = diagnosis(sim, scene, states)
        ok &= same.passed is not False and step.passed is not False
        judged += (same.passed is not None) + (step.passed is not None)
        print(f"{scene.name:<16} {_cell(same):<34} {_cell(step):<34} {diag['verdict']}")
        if args.markdown:
            print("\n" + render_markdown(diag) + "\n")
    if not judged:
        print("nothing judged: no scene had a check this command can judge (see each line)")
    return 0 if ok and judged else 1


if __name__ == "__main__":
    sys.exit(main())
