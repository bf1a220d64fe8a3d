"""Each scenario in a process of its own: independent verdicts, and a run the user can stop.

A scenario runs in a fresh process forked for it alone, so no state of a user's module (or of
anything else) passes from one scenario to the next, and a crash, a hang or a timeout costs
only that scenario's row. The processes ignore Ctrl-C; the parent takes it, stops them, and
names the scene and the step each had reached. While they run, the parent shows each one's
steps per second (compare/usersim/progress.py).

    run_scenes(scenes, work, jobs, timeout) -> {scene name: Outcome}
"""
from __future__ import annotations

import multiprocessing as mp
import signal
import sys
import time
from dataclasses import dataclass
from multiprocessing.connection import wait

from .usersim import progress

POLL = 0.2            # s between two looks at the running processes (Ctrl-C is seen within it)
FIRST_REPORT = 1.0    # s of stepping before a scene's progress is first shown
REPORT_EVERY = 10.0   # s between two progress lines when stderr is not a terminal


@dataclass
class Outcome:
    """What one scenario's process sent back: exactly one field is set."""

    row: dict | None = None            # metrics.json of a scenario that reached a verdict
    failure: tuple | None = None       # (status, why): no verdict (error, unstable, timeout)
    bad_input: tuple | None = None     # (message, details): the user's code broke the protocol
    details: str = ""                  # with a failure: the user's own traceback, where their code raised


class Interrupted(Exception):
    """Ctrl-C: the message names each scene that was running and the step it had reached."""


def _child(index: int, scene, work, conn, shared) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)   # the parent stops us
    progress.attach(shared, index)
    try:
        outcome = work(scene)
    except BaseException as exc:  # noqa: BLE001 - anything left is this scenario's error row
        text = str(exc).strip().splitlines()
        outcome = Outcome(failure=("error", f"{type(exc).__name__}: {text[0]}" if text else type(exc).__name__))
    try:
        conn.send(outcome)
    finally:
        conn.close()


def _where(scene, shared, index: int) -> str:
    done, total, began = progress.read(shared, index)
    if not began:
        return f"{scene.name} (before its first step)"
    return f"{scene.name} at step {done} of {total} (t = {done * scene.dt:.6g} s)"


class _Display:
    """One line on stderr per look: scenarios done, and each running scene's steps per second."""

    def __init__(self, scenes, shared):
        self.scenes, self.shared = scenes, shared
        self.tty = sys.stderr.isatty()
        self.last = {}
        self.width = 0

    def show(self, running, done: int) -> None:
        now = time.time()
        parts = []
        for k in running:
            steps, total, began = progress.read(self.shared, k)
            if not began or now - began < FIRST_REPORT or steps >= total:
                continue
            rate = steps / max(now - began, 1e-9)
            left = (total - steps) / rate if rate > 0 else float("inf")
            text = f"{self.scenes[k].name}: step {steps} of {total}, {rate:,.0f} steps/s"
            if left < float("inf") and steps < total:
                text += f", about {left:.0f} s to go"
            if self.tty:
                parts.append(text)
            elif now - self.last.get(k, 0.0) >= REPORT_EVERY:
                self.last[k] = now
                print(f"[{done} of {len(self.scenes)} scenarios done] {text}", file=sys.stderr, flush=True)
        if self.tty and parts:
            line = f"[{done} of {len(self.scenes)} done] " + "; ".join(parts)
            print("\r" + line.ljust(self.width), end="", file=sys.stderr, flush=True)
            self.width = len(line)

    def close(self) -> None:
        if self.tty and self.width:
            print("\r" + " " * self.width + "\r", end="", file=sys.stderr, flush=True)


def run_scenes(scenes, work, jobs: int, timeout: float | None = None, cost=None) -> dict:
    """work(scene) -> Outcome, for every scene, in at most `jobs` processes at once (costliest
    first, by cost(scene)); a scene still running after `timeout` s is stopped. Raises
    Interrupted on Ctrl-C, after stopping every process."""
    ctx = mp.get_context("fork")
    shared = ctx.RawArray("d", progress.FIELDS * len(scenes))
    order = sorted(range(len(scenes)), key=lambda k: cost(scenes[k]) if cost else 0.0, reverse=True)
    running, outcomes = {}, {}
    display = _Display(scenes, shared)
    try:
        while order or running:
            while order and len(running) < max(1, jobs):
                k = order.pop(0)
                receive, send = ctx.Pipe(duplex=False)
                proc = ctx.Process(target=_child, args=(k, scenes[k], work, send, shared), daemon=True)
                proc.start()
                send.close()
                running[k] = (proc, receive, time.monotonic())
            wait([c for _, c, _ in running.values()] + [p.sentinel for p, _, _ in running.values()], POLL)
            for k, (proc, conn, began) in list(running.items()):
                outcome = None
                if conn.poll():
                    try:
                        outcome = conn.recv()
                    except EOFError:
                        outcome = None
                    proc.join()
                    if outcome is None:
                        outcome = _died(proc)
                elif not proc.is_alive():
                    proc.join()
                    outcome = _died(proc)
                elif timeout is not None and time.monotonic() - began > timeout:
                    where = _where(scenes[k], shared, k)
                    proc.kill()
                    proc.join()
                    outcome = Outcome(failure=("timeout", f"stopped after {timeout:g} s (--timeout), at {where}"))
                if outcome is not None:
                    conn.close()
                    outcomes[scenes[k].name] = outcome
                    del running[k]
            display.show(running, len(outcomes))
    except KeyboardInterrupt:
        where = [_where(scenes[k], shared, k) for k in running]
        for proc, _, _ in running.values():
            proc.kill()
        for proc, _, _ in running.values():
            proc.join()
        raise Interrupted("; ".join(where) or "between two scenarios") from None
    finally:
        display.close()
    return outcomes


def _died(proc) -> Outcome:
    code = proc.exitcode
    how = f"killed by signal {-code}" if code is not None and code < 0 else f"exit code {code}"
    return Outcome(failure=("error", f"the process running it ended without a verdict ({how}): a crash "
                                     "outside Python, or the machine stopping it"))
