"""Fit the MuJoCo twin's contact settings to custom_sim's trajectories (or, with --reverse,
custom_sim's k, c, mu, alpha to MuJoCo's).

The fit minimises, over the fitted scenes at once, each scene's largest position and angle
difference relative to the starting mapping's (a minimax through a high p-norm, solved by
mujoco.minimize.least_squares with box bounds); finite differences run as batches of twins in mujoco.rollout.
Default: fit box_slide and point_drop, hold out box_drop and t_shape_drop. --fit takes a
comma-separated list of: solref.stiffness, solref.damping (direct form, on the penalty
mapping) or solref.timeconst, solref.dampratio (positive form, on the physical mapping),
solreffriction.damping, friction.slide, friction.roll, solimp.d0, solimp.dwidth, solimp.width,
solimp.midpoint, solimp.power, impratio (default: solref.stiffness, solref.damping,
solreffriction.damping, friction.slide). Writes DIR/index.md, DIR/calibration.json,
DIR/model_<scene>.xml (the calibrated MJCF) and plots. A fit that leaves a fitted scene worse
than the starting mapping (its largest position or angle difference) is rejected: the
calibrated twin keeps the mapping's values, and the output names the scene and why. Exit
status: 0 when a calibrated twin is written (whether the optimiser converged, stopped at
--max-iter, or its fit was rejected: the output says which), 1 when the fit could not run (a
reference run diverged; nothing written), 2 bad input (nothing written).
"""
from __future__ import annotations

import os
import sys

from scene_types import BadInput

from ..files import output_folder
from ..scenarios import load_all

DEFAULT_FITTED = ("box_slide", "point_drop")
DEFAULT_HELD_OUT = ("box_drop", "t_shape_drop")


def add_arguments(parser) -> None:
    parser.add_argument("scenes", nargs="*", metavar="SCENE",
                        help=f"scenes to fit (default: {' '.join(DEFAULT_FITTED)})")
    parser.add_argument("--test", metavar="SCENES", default=None,
                        help="comma-separated held-out scenes, measured but never fitted (default: "
                             f"{','.join(DEFAULT_HELD_OUT)} with the default scenes, else none)")
    parser.add_argument("--fit", metavar="PARAMS", default=None, help="comma-separated parameters to fit")
    parser.add_argument("--reverse", action="store_true",
                        help="fit custom_sim's k, c, mu, alpha to the twin's trajectory instead")
    parser.add_argument("--solref", choices=("penalty", "physical", "seed"), default=None,
                        help="--reverse: the twin's mapping to match (default: the scene's [mujoco] solref)")
    parser.add_argument("--max-iter", type=int, default=None,
                        help="optimiser iterations (default 12, --reverse 30)")
    parser.add_argument("--threads", type=int, default=os.cpu_count() or 1,
                        help="mujoco.rollout threads (default: every core)")
    parser.add_argument("--out", default=None, metavar="DIR",
                        help="output folder (default: reports/calibration, reverse: reports/calibration/reverse)")


def _m(x) -> str:
    return "diverged" if x is None else f"{x:.3g}"


def main(args) -> int:
    from ..tools.calibration.fit import MAX_ITERATIONS
    from ..tools.calibration.reverse import MAX_ITERATIONS as REVERSE_MAX_ITERATIONS
    from ..tools.calibration.parameters import base_mapping, parse_fit

    if args.max_iter is None:
        args.max_iter = REVERSE_MAX_ITERATIONS if args.reverse else MAX_ITERATIONS
    if args.max_iter < 1:
        raise BadInput(f"--max-iter: {args.max_iter} (expected a whole number >= 1)")
    if args.reverse and args.fit:
        raise BadInput("--fit: not used with --reverse (the reverse fit always fits k, c, mu, alpha)")
    if args.reverse and args.test:
        raise BadInput("--test: not used with --reverse (the reverse fit reports every scene it fits)")
    if not args.reverse and args.solref:
        raise BadInput("--solref: only used with --reverse (the forward fit starts from the penalty or physical "
                       "mapping, by --fit)")
    params = None if args.reverse else parse_fit(args.fit)
    fitted = load_all(list(args.scenes or DEFAULT_FITTED))
    test = args.test if args.test is not None else ("" if args.scenes else ",".join(DEFAULT_HELD_OUT))
    held = load_all([s for s in test.split(",") if s.strip()]) if test else []
    names = [s.name for s in fitted]
    for s in held:
        if s.name in names:
            raise BadInput(f"--test: {s.name} is also a fitted scene (expected scenes the fit never sees)")
    for s in fitted + held:
        if not s.has("contact"):
            raise BadInput(f"{s.source}: effects: no 'contact' (expected scenes with contact to calibrate)")
    out = output_folder(args.out or ("reports/calibration/reverse" if args.reverse else "reports/calibration"))

    from custom_sim import SimulationDiverged
    from mujoco_models import MujocoDiverged

    try:
        return _run(args, fitted, held, params, base_mapping, out)
    except (SimulationDiverged, MujocoDiverged) as exc:
        print(f"error: {exc}", file=sys.stderr)
        print("calibration stopped: a reference run diverged; nothing written")
        return 1


def _run(args, fitted, held, params, base_mapping, out) -> int:
    from ..tools.calibration.report import write_calibration, write_reverse

    if args.reverse:
        from ..tools.calibration.reverse import prepare_reverse, reverse_fit

        targets = [prepare_reverse(s, args.solref) for s in fitted]
        result = reverse_fit(targets, max_iter=args.max_iter)
        index = write_reverse(result, targets, out)
        for t in targets:
            ct = t.scene.contact
            g = result.values
            print(f"{t.scene.name:<16} MuJoCo ({t.mapping}) ~ k = {ct.k * g[0]:.5g} N/m, c = {ct.c * g[1]:.5g} N s/m, "
                  f"mu = {ct.mu * g[2]:.4g}, alpha = {ct.alpha * g[3]:.4g} s/m")
    else:
        from ..tools.calibration.calibration import calibrate

        cal = calibrate(fitted, held, params, base_mapping(params), args.max_iter, args.threads)
        result = cal.result
        index = write_calibration(cal, out)
        for name, value in result.parameters.items():
            print(f"{name:<24} {value:.6g}" + ("" if cal.accepted else " (rejected)"))
        for s in cal.scenes:
            e = s.errors
            print(f"{s.scene.name:<16} {'held out' if s.held_out else 'fitted':<9} position error max (m): " +
                  ", ".join(f"{k} {_m(e[k]['position_error_max'])}" for k in ("seed", "physical", "penalty", "calibrated"))
                  + ("" if cal.accepted else f", fitted (rejected) {_m(cal.fitted_errors[s.scene.name]['position_error_max'])}"))
        for g in cal.gave_up:
            print(f"gave up {g['scene']}: {g['why']}")
        print(cal.verdict)
        print(f"calibrated twin written ({f'the {cal.base} mapping' if cal.carries_mapping else 'the fit'}'s values): "
              f"{', '.join(f'model_{s.scene.name}.xml' for s in cal.scenes)}")
    print(f"status: {result.status} ({'converged' if result.converged else 'NOT converged'}), "
          f"{result.iterations} iterations, {result.wall_time:.1f} s")
    if result.at_bound:
        print(f"on a bound: {', '.join(result.at_bound)}")
    print(f"report: {index}")
    if args.reverse:
        return 0 if result.converged else 1
    return 0   # a calibrated twin is written: the fit's values, or the mapping's when rejected
