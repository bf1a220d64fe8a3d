"""What batching and Dask workers buy, measured in one run.

    python -m compare tools study-bench [--out DIR]

1. custom_sim: runs per second of simulate_batch (one compiled call, prange over the runs, 1 and
   2 threads) against custom_sim.simulate called once per run, on the same runs (box_drop with
   16 stiffnesses) at three step sizes; the minimum of 3 timings after a warm-up.
2. MuJoCo: runs per second of mujoco_models.batch (rollout over several models, 1 and 2
   threads) against simulate_mujoco once per run.
3. The study's wall time on 1 and 2 workers of one thread each, and on 1 worker allowed 2
   threads.

The machine's load average is printed before and after: on a shared machine the figures are
only as good as the quiet they were measured in. Writes DIR/benchmark.json (default
reports/study_benchmark). Needs Dask, as `study` does (pip install -e '.[study]'): without it,
one line and exit status 2.
"""
from __future__ import annotations


def add_arguments(parser) -> None:
    parser.add_argument("--out", default="reports/study_benchmark", metavar="DIR")


def main(args) -> int:
    from ...tools.study.benchmark import benchmark

    return benchmark(args.out)
