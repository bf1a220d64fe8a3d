"""Parameter study: stability, accuracy and cost of every integrator over a grid of scene fields, on Dask.

    python -m compare study SCENE --vary NAME=SPEC [--vary NAME=SPEC ...]
        [--integrators NAME ...] [--sim MODULE:FUNCTION [--whole]] [--law FILE.toml]
        [--scheduler tcp://HOST:PORT | tls://HOST:PORT] [--workers N] [--dashboard [HOST:PORT]]
        [--no-twin] [--out DIR]

NAME is a scene field as in the TOML file: dt, contact.k, contact.c, contact.mu, body.mass,
initial.velocity[1], ... SPEC is a list (1e3,1e4,1e5) or a range START:STOP:COUNT:log|lin
(1e3:1e6:7:log: seven values from 1e3 to 1e6, evenly spaced in log). Every combination of the
values runs with every integrator asked (default: all four). Per run: stable, the error against
the converged reference, the largest difference to the MuJoCo twin, the wall time and the
force evaluations. With --sim the user's simulator runs every point too (rows with simulator
`yours`): the integrator its module declares (INTEGRATOR), else each of --integrators, told by
the scene dict; each run from a fresh import of its module, as `run` does. --law lays a law
file's [contact] over the scene's before the fields are varied.

Runs on a local Dask cluster of --workers processes of one thread each (default: every core),
everything on 127.0.0.1 (--dashboard opens its dashboard there and prints its address), or on
an existing cluster with --scheduler (tls:// with Dask's own TLS settings); needs Dask (pip
install -e '.[study]'). The user's module and the .py files beside it that it imports travel
with the tasks: the workers need no copy of them.
Writes DIR/study.csv (one row per run), DIR/*.png (maps, with the theory's stability limit
drawn over them) and DIR/index.md; finished batches are kept in DIR/batches/ and reused when
the same study runs again.
Exit status: 0 done (unstable runs are results, not errors), 2 bad input.
"""
from __future__ import annotations

import sys

from scene_types import BadInput

from ..files import output_folder

DEFAULT_OUT = "reports/study"


def add_arguments(parser) -> None:
    from custom_sim import INTEGRATORS

    parser.add_argument("scene", metavar="SCENE", help="built-in name or path to a .toml")
    parser.add_argument("--vary", action="append", required=True, metavar="NAME=SPEC",
                        help="a scene field and its values; repeat for a grid")
    parser.add_argument("--integrators", nargs="+", default=list(INTEGRATORS), metavar="NAME",
                        help=f"custom_sim integrators (default: all: {' '.join(INTEGRATORS)})")
    parser.add_argument("--sim", metavar="MODULE:FUNCTION", default=None,
                        help="your simulator beside custom_sim: a step function step(state, scene, dt) -> state "
                             "(MODULE a path to a .py file or a dotted module); it and the .py files beside it "
                             "that it imports are sent to the workers")
    parser.add_argument("--whole", action="store_true",
                        help="with --sim: FUNCTION is simulate(scene) -> array (steps + 1, 6)")
    parser.add_argument("--sim-process", metavar="COMMAND", default=None,
                        help="your simulator in any language on stdin/stdout (docs/process-protocol.md), in place "
                             "of --sim; the command is started where each task runs")
    parser.add_argument("--law", metavar="FILE.toml", default=None,
                        help="a law file's [contact] table laid over the scene's, then the fields varied")
    parser.add_argument("--scheduler", metavar="ADDRESS", default=None,
                        help="run on this Dask cluster, e.g. tcp://127.0.0.1:8786, or tls://HOST:PORT with Dask's "
                             "TLS settings (distributed.comm.tls.*) (default: a local cluster on 127.0.0.1)")
    parser.add_argument("--workers", type=int, default=None,
                        help="local cluster: worker processes of one thread (default: every core)")
    parser.add_argument("--dashboard", nargs="?", const="127.0.0.1:0", default=None, metavar="HOST:PORT",
                        help="local cluster: open Dask's dashboard (default 127.0.0.1, a free port) and print "
                             "its address; without it nothing of the study listens beyond 127.0.0.1")
    parser.add_argument("--no-twin", action="store_true", help="skip the MuJoCo twin (its column stays empty)")
    parser.add_argument("--out", default=DEFAULT_OUT, metavar="DIR", help=f"output folder (default: {DEFAULT_OUT})")


def yours_of(args, scene, integrators):
    """plan.Yours for --sim (None without): the module imported and shipped once here, so a
    fault of it is bad input before anything runs."""
    from ..tools.study.plan import Yours
    from ..usersim import load_simulator

    if args.sim_process is not None:
        from ..tools.accuracy.yours import integrators_of
        from ..usersim.process import Command
        if args.sim is not None or args.whole:
            raise BadInput("--sim-process: expected it in place of --sim (and without --whole)")
        process = load_simulator(process=args.sim_process)
        chosen = integrators_of(process, scene)
        process.close()
        return Yours(Command(args.sim_process), tuple(i for i in chosen if i in integrators) or tuple(chosen))
    if args.sim is None:
        if args.whole:
            raise BadInput("--whole: expected it with --sim MODULE:FUNCTION")
        return None
    from ..usersim.bundle import Bundle

    simulator = load_simulator(args.sim, args.whole)
    declared = getattr(simulator.module, "INTEGRATOR", None)
    chosen = (simulator.integrator_for(scene),) if declared is not None else tuple(integrators)
    return Yours(Bundle.of(args.sim, args.whole), chosen)


def parse(args):
    """(source, varies, integrators, out, yours): every input checked before anything runs."""
    from custom_sim import INTEGRATORS

    from ..scenarios import resolve
    from ..tools.study.fields import SceneSource, parse_vary

    source = SceneSource.read(resolve(args.scene))
    if args.law == "identified":
        raise BadInput("--law identified: not in a study (expected a law file; `python -m compare identify "
                       "MODULE:FUNCTION SCENE` names the law, which a [contact] table in a .toml file can hold)")
    if args.law:
        source = source.under_law(args.law)
    varies = [parse_vary(text) for text in args.vary]
    names = [v.name for v in varies]
    for name in names:
        if names.count(name) > 1:
            raise BadInput(f"--vary {name}: given twice (expected each field once)")
    for name in args.integrators:
        if name not in INTEGRATORS:
            raise BadInput(f"--integrators {name}: unknown integrator (expected some of: {', '.join(INTEGRATORS)})")
    if len(set(args.integrators)) != len(args.integrators):
        raise BadInput("--integrators: an integrator is given twice")
    if args.workers is not None and args.workers < 1:
        raise BadInput(f"--workers {args.workers}: expected a whole number >= 1")
    if args.scheduler and args.workers:
        raise BadInput("--workers: the cluster given by --scheduler has its own workers")
    if args.scheduler and args.dashboard:
        raise BadInput("--dashboard: the cluster given by --scheduler has its own "
                       "(its scheduler's --dashboard-address)")
    out = output_folder(args.out)
    yours = yours_of(args, source.scene, args.integrators)
    from ..tools.study.plan import plan
    plan(source, varies, args.integrators, yours)   # every combination through the loader, before any output
    return source, varies, list(args.integrators), out, yours


def command_line(args) -> str:
    """The command that reproduces this study (for the report)."""
    parts = ["python -m compare study", args.scene, *(f"--vary {v}" for v in args.vary)]
    from custom_sim import INTEGRATORS
    if list(args.integrators) != list(INTEGRATORS):
        parts += ["--integrators", *args.integrators]
    if args.sim:
        parts += ["--sim", args.sim] + (["--whole"] if args.whole else [])
    if args.sim_process:
        parts += ["--sim-process", args.sim_process]
    if args.law:
        parts += ["--law", args.law]
    if args.no_twin:
        parts.append("--no-twin")
    if args.out != DEFAULT_OUT:
        parts += ["--out", args.out]
    return " ".join(parts)


def main(args) -> int:
    from ..executor import require_dask
    require_dask("study")   # the study extra: one line and exit 2, before anything runs
    source, varies, integrators, out, yours = parse(args)
    from ..tools.study.report import write_report
    from ..tools.study.runner import run_study

    engine = None
    if args.scheduler:   # a wrong address is bad input: found before anything is written
        from ..executor import make_executor
        engine = make_executor("dask", scheduler=args.scheduler)
    try:
        out.mkdir(parents=True, exist_ok=True)
        study = run_study(source, varies, integrators, out, scheduler=args.scheduler,
                          workers=args.workers, twin=not args.no_twin, engine=engine, yours=yours,
                          dashboard=args.dashboard)
    finally:
        if engine is not None:
            engine.close()
    index = write_report(study, out, command=command_line(args))
    counts = {s: sum(r["status"] == s for r in study.rows) for s in ("ok", "unstable", "failed", "skipped")}
    skipped = f", {counts['skipped']} skipped" if counts["skipped"] else ""
    for status in ("failed", "skipped"):
        mine = [r for r in study.rows if r.get("simulator") == "yours" and r["status"] == status]
        if mine:   # the user's code: one line, its first reason (each row's is in study.csv)
            print(f"yours: {len(mine)} run(s) {status}, the first: {mine[0]['note']}", file=sys.stderr)
    print(f"study of {len(study.rows)} runs ({counts['ok']} ok, {counts['unstable']} unstable, "
          f"{counts['failed']} failed{skipped}; {study.reused} reused) in {study.wall_time:.1f} s; report: {index}")
    return 0
