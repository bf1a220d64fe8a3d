"""Parameter study: stability, accuracy and cost of every integrator over a grid of scene fields, on Dask.

    python -m compare study SCENE --vary NAME=SPEC [--vary NAME=SPEC ...]
        [--integrators NAME ...] [--scheduler tcp://HOST:PORT] [--workers N] [--no-twin] [--out DIR]

NAME is a scene field as in the TOML file: dt, contact.k, contact.c, contact.mu, body.mass,
initial.velocity[1], ... SPEC is a list (1e3,1e4,1e5) or a range START:STOP:COUNT:log|lin
(1e3:1e6:7:log: seven values from 1e3 to 1e6, evenly spaced in log). Every combination of the
values runs with every integrator asked (default: all four). Per run: stable, the error against
the converged reference, the largest difference to the MuJoCo twin, the wall time and the
force evaluations.

Runs on a local Dask cluster of --workers processes of one thread each (default: every core),
or on an existing cluster with --scheduler; needs Dask (pip install -e '.[study]').
Writes DIR/study.csv (one row per run), DIR/*.png (maps, with the theory's stability limit
drawn over them) and DIR/index.md; finished batches are kept in DIR/batches/ and reused when
the same study runs again.
Exit status: 0 done (unstable runs are results, not errors), 2 bad input.
"""
from __future__ import annotations

from scene_types import BadInput

from ..cli import output_folder

DEFAULT_OUT = "reports/study"


def add_arguments(parser) -> None:
    from custom_sim import INTEGRATORS

    parser.add_argument("scene", metavar="SCENE", help="built-in name or path to a .toml")
    parser.add_argument("--vary", action="append", required=True, metavar="NAME=SPEC",
                        help="a scene field and its values; repeat for a grid")
    parser.add_argument("--integrators", nargs="+", default=list(INTEGRATORS), metavar="NAME",
                        help=f"custom_sim integrators (default: all: {' '.join(INTEGRATORS)})")
    parser.add_argument("--scheduler", metavar="ADDRESS", default=None,
                        help="run on this Dask cluster, e.g. tcp://127.0.0.1:8786 (default: a local cluster)")
    parser.add_argument("--workers", type=int, default=None,
                        help="local cluster: worker processes of one thread (default: every core)")
    parser.add_argument("--no-twin", action="store_true", help="skip the MuJoCo twin (its column stays empty)")
    parser.add_argument("--out", default=DEFAULT_OUT, metavar="DIR", help=f"output folder (default: {DEFAULT_OUT})")


def parse(args):
    """(source, varies, integrators, out): every input checked before anything runs."""
    from custom_sim import INTEGRATORS

    from ..scenarios import resolve
    from ..tools.study.fields import SceneSource, parse_vary

    source = SceneSource.read(resolve(args.scene))
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
    out = output_folder(args.out)
    from ..tools.study.plan import plan
    plan(source, varies, args.integrators)   # every combination through the loader, before any output
    return source, varies, list(args.integrators), out


def command_line(args) -> str:
    """The command that reproduces this study (for the report)."""
    parts = ["python -m compare study", args.scene, *(f"--vary {v}" for v in args.vary)]
    from custom_sim import INTEGRATORS
    if list(args.integrators) != list(INTEGRATORS):
        parts += ["--integrators", *args.integrators]
    if args.no_twin:
        parts.append("--no-twin")
    if args.out != DEFAULT_OUT:
        parts += ["--out", args.out]
    return " ".join(parts)


def main(args) -> int:
    from ..executor import require_dask
    require_dask("study")   # the study extra: one line and exit 2, before anything runs
    source, varies, integrators, out = parse(args)
    from ..tools.study.report import write_report
    from ..tools.study.runner import run_study

    engine = None
    if args.scheduler:   # a wrong address is bad input: found before anything is written
        from ..executor import make_executor
        engine = make_executor("dask", scheduler=args.scheduler)
    try:
        out.mkdir(parents=True, exist_ok=True)
        study = run_study(source, varies, integrators, out, scheduler=args.scheduler,
                          workers=args.workers, twin=not args.no_twin, engine=engine)
    finally:
        if engine is not None:
            engine.close()
    index = write_report(study, out, command=command_line(args))
    counts = {s: sum(r["status"] == s for r in study.rows) for s in ("ok", "unstable", "failed")}
    print(f"study of {len(study.rows)} runs ({counts['ok']} ok, {counts['unstable']} unstable, "
          f"{counts['failed']} failed; {study.reused} reused) in {study.wall_time:.1f} s; report: {index}")
    return 0
