"""Many runs of one scene in one compiled call: each run its own parameters, integrator and step.

    simulate_batch(scenes, samples, threads) -> list[BatchRun]

Every run goes through the compiled loops of `integrators.integrate`, the ones `simulate`
calls, with the same model, guard and counters, so a run of the batch is bit for bit the run `simulate` makes (a
test checks it). The batch adds only the loop over runs: `numba.prange`, a chunk of one run
per thread at a time, so a long run does not hold up a thread's share of short ones. The call
releases the GIL (nogil), so the calling process (a Dask worker's heartbeat) keeps running
meanwhile, and reads the clock without it.

Each run records its whole trajectory into a buffer of its own (48 bytes a step, allocated
inside the loop: only `threads` of them exist at once) and keeps the rows asked for in
`samples`; a run that leaves the healthy range stops there, like `simulate`, and reports
the step and the state.
"""
from __future__ import annotations

import os
import time
from dataclasses import dataclass

import numba
import numpy as np
from llvmlite import ir
from numba import njit, prange
from numba.core import cgutils, types
from numba.extending import intrinsic

from .bodies import mass_properties
from .chatter import WATCH_COLUMNS
from .integrators import (FORCE_EVALS, IMPLICIT_EULER, INTEGRATORS, NEWTON_ITERS, integrate_explicit,
                          integrate_implicit)
from .model import Model, build_model, initial_state
from scene_types.schema import Scene
from .runner import blowup_guard

# OpenMP threads that finish their share of a batch sleep instead of spinning: a spinning
# thread takes the core from the one still working (measured: a batch of 16 short runs on two
# threads took 16 ms of wall time spinning, 2.6 ms passive, 1.8 ms on one thread). Only read
# when the OpenMP runtime starts, i.e. before the first parallel call of the process.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

# Model fields in the order of custom_sim.model.Model: the floats, then the switches.
_FLOATS = ("inv_mass", "inv_inertia", "g", "k", "c", "dissipation", "mu", "alpha", "mu_roll", "roll_sharpness")
_SWITCHES = ("damping_law", "friction_law", "roll_law", "gravity", "contact", "friction", "rolling", "points_rotate")
_GUARD = 7   # blowup_guard's numbers


@dataclass(frozen=True)
class BatchRun:
    """One run of a batch: states (len(samples), 6) at the requested step indices (rows past a
    divergence are NaN), failed_step (-1, or the 1-based step where the state left the healthy
    range), failed_state (6,), force_evals, newton_iterations, wall_time (s, the stepping)."""

    samples: np.ndarray
    states: np.ndarray
    failed_step: int
    failed_state: np.ndarray
    force_evals: int
    newton_iterations: int
    wall_time: float

    @property
    def diverged(self) -> bool:
        return self.failed_step >= 0


# The clock read around each run: clock_gettime(CLOCK_MONOTONIC), called from compiled code
# without the GIL (numba's objmode would take the GIL twice a run, and with two threads the
# waiting cost 0.5 ms a run, more than a short run itself).
MONOTONIC = getattr(time, "CLOCK_MONOTONIC", 1)


@intrinsic
def _monotonic(typingctx, clock_id):
    """Seconds on the clock `clock_id` (float64), by libc's clock_gettime."""
    sig = types.float64(types.int32)

    def codegen(context, builder, signature, args):
        i64, i32, f64 = ir.IntType(64), ir.IntType(32), ir.DoubleType()
        timespec = ir.LiteralStructType([i64, i64])   # tv_sec, tv_nsec
        fn = cgutils.get_or_insert_function(builder.module, ir.FunctionType(i32, [i32, timespec.as_pointer()]),
                                            "clock_gettime")
        ts = cgutils.alloca_once(builder, timespec)
        builder.call(fn, [args[0], ts])
        sec = builder.sitofp(builder.load(cgutils.gep_inbounds(builder, ts, 0, 0)), f64)
        nsec = builder.sitofp(builder.load(cgutils.gep_inbounds(builder, ts, 0, 1)), f64)
        return builder.fadd(sec, builder.fmul(nsec, ir.Constant(f64, 1e-9)))
    return sig, codegen


@njit(cache=True, parallel=True, nogil=True)
def _run_batch(floats, switches, points, n_points, z0, dt, steps, methods, guards,
               sample_rows, n_samples, out, failed, final, counters, wall, clock):
    """prange over runs b: integrate run b and copy the rows sample_rows[b, :n_samples[b]]
    (0 = the initial state, i = after step i) into out[b]."""
    for b in prange(floats.shape[0]):
        f = floats[b]
        s = switches[b]
        model = Model(f[0], f[1], f[2], f[3], f[4], f[5], f[6], f[7], f[8], f[9],
                      s[0], s[1], s[2], s[3] != 0, s[4] != 0, s[5] != 0, s[6] != 0, s[7] != 0)
        g = guards[b]
        guard = (g[0], g[1], g[2], g[3], g[4], g[5], g[6])
        pts = points[b, :n_points[b]].copy()
        n = steps[b]
        z = z0[b].copy()
        trajectory = np.empty((n, 6))
        ext = np.zeros((1, 3))
        count = np.zeros(4, dtype=np.int64)
        start = _monotonic(clock)
        watch = np.zeros((n_points[b], WATCH_COLUMNS))   # chatter counts as unstable, as in simulate
        if methods[b] == IMPLICIT_EULER:
            stop = integrate_implicit(model, pts, z, dt[b], n, methods[b], ext, trajectory, count, guard, watch)
        else:
            stop = integrate_explicit(model, pts, z, dt[b], n, methods[b], ext, trajectory, count, guard, watch)
        wall[b] = _monotonic(clock) - start
        failed[b] = stop
        final[b] = z
        counters[b] = count
        last = n if stop < 0 else stop   # rows after the divergence are not part of the run
        for j in range(n_samples[b]):
            row = sample_rows[b, j]
            if row == 0:
                out[b, j] = z0[b]
            elif row <= last:
                out[b, j] = trajectory[row - 1]
            else:
                out[b, j] = np.nan


def _model_numbers(model: Model) -> tuple[list[float], list[int]]:
    return [float(getattr(model, k)) for k in _FLOATS], [int(getattr(model, k)) for k in _SWITCHES]


def simulate_batch(scenes: list[Scene], samples: list[np.ndarray] | None = None,
                   threads: int | None = None) -> list[BatchRun]:
    """Run every scene (each with its own integrator, dt and parameters) in one compiled call.

    samples[b]: step indices 0..steps of scene b whose states to keep (default: every step);
    threads: numba threads for the call (default: numba's current setting)."""
    count = len(scenes)
    if samples is None:
        samples = [np.arange(s.steps + 1) for s in scenes]
    samples = [np.asarray(r, dtype=np.int64) for r in samples]
    for scene, rows in zip(scenes, samples):
        if rows.size and (rows.min() < 0 or rows.max() > scene.steps):
            raise ValueError(f"{scene.name}: sample rows must lie in 0..{scene.steps}")
    width = max((r.size for r in samples), default=0)
    floats = np.empty((count, len(_FLOATS)))
    switches = np.empty((count, len(_SWITCHES)), dtype=np.int64)
    props = [mass_properties(s.body) for s in scenes]
    n_points = np.array([p.points.shape[0] for p in props], dtype=np.int64)
    points = np.zeros((count, int(n_points.max(initial=1)), 2))
    z0 = np.empty((count, 6))
    guards = np.empty((count, _GUARD))
    sample_rows = np.zeros((count, width), dtype=np.int64)
    for b, (scene, prop, rows) in enumerate(zip(scenes, props, samples)):
        model, pts = build_model(scene, prop)
        floats[b], switches[b] = _model_numbers(model)
        points[b, :len(pts)] = pts
        z0[b] = initial_state(scene)
        guards[b] = blowup_guard(scene, prop, z0[b], applied_input=False)
        sample_rows[b, :rows.size] = rows
    dt = np.array([s.dt for s in scenes])
    steps = np.array([s.steps for s in scenes], dtype=np.int64)
    methods = np.array([INTEGRATORS[s.integrator].code for s in scenes], dtype=np.int64)
    n_samples = np.array([r.size for r in samples], dtype=np.int64)
    out = np.empty((count, width, 6))
    failed = np.empty(count, dtype=np.int64)
    final = np.empty((count, 6))
    counters = np.zeros((count, 4), dtype=np.int64)
    wall = np.zeros(count)
    previous = numba.get_num_threads()
    if threads:
        numba.set_num_threads(max(1, min(int(threads), numba.config.NUMBA_NUM_THREADS)))  # type: ignore[attr-defined]  # set at import
    numba.set_parallel_chunksize(1)   # one run per thread at a time: runs differ in length
    try:
        _run_batch(floats, switches, points, n_points, z0, dt, steps, methods, guards,
                   sample_rows, n_samples, out, failed, final, counters, wall, np.int32(MONOTONIC))
    finally:
        numba.set_parallel_chunksize(0)
        numba.set_num_threads(previous)
    return [BatchRun(samples=samples[b], states=out[b, :samples[b].size].copy(),
                     failed_step=int(failed[b]), failed_state=final[b].copy(),
                     force_evals=int(counters[b, FORCE_EVALS]),
                     newton_iterations=int(counters[b, NEWTON_ITERS]), wall_time=float(wall[b]))
            for b in range(count)]
