"""What the user sees while tasks run: a bar of runs done, or each running task's steps per second.

A display has four methods, called by Executor.run: start(tasks, todo), finished(task),
show(running, done) after every look at the running tasks (running: (task, steps) pairs, steps
as steps.py reads them) and close().
"""
from __future__ import annotations

import sys
import time

FIRST_REPORT = 1.0    # s of stepping before a task's progress is first shown
REPORT_EVERY = 10.0   # s between two progress lines when stderr is not a terminal


def where(task, steps: tuple[int, int, float]) -> str:
    """`box_drop at step 120 of 3000 (t = 0.012 s)`, or `box_drop (before its first step)`."""
    done, total, began = steps
    if not began:
        return f"{task.key} (before its first step)"
    dt = task.meta.get("dt")
    at = f" (t = {done * dt:.6g} s)" if dt else ""
    return f"{task.key} at step {done} of {total}{at}"


class Bar:
    """A tqdm bar on stderr counting runs (Task.runs), shown after a second."""

    def __init__(self, desc: str, enabled: bool = True):
        self.desc, self.enabled, self.bar = desc, enabled, None

    def start(self, tasks, todo) -> None:
        from tqdm import tqdm

        total = sum(t.runs for t in tasks)
        self.bar = tqdm(total=total, initial=total - sum(t.runs for t in todo), desc=self.desc, unit="run",
                        file=sys.stderr, delay=1, disable=not self.enabled)

    def finished(self, task) -> None:
        self.bar.update(task.runs)

    def show(self, running, done: int) -> None:
        pass

    def close(self) -> None:
        self.bar.close()


class StepLines:
    """One line on stderr per look: tasks done, and each running task's steps per second (on a
    terminal rewritten in place; else a line per task every REPORT_EVERY s)."""

    def __init__(self, noun: str = "tasks"):
        self.noun = noun
        self.tty = sys.stderr.isatty()
        self.last: dict[str, float] = {}
        self.width = 0
        self.total = 0

    def start(self, tasks, todo) -> None:
        self.total = len(tasks)

    def finished(self, task) -> None:
        pass

    def show(self, running, done: int) -> None:
        now = time.time()
        parts = []
        for task, (steps, total, began) in running:
            if not began or now - began < FIRST_REPORT or steps >= total:
                continue
            rate = steps / max(now - began, 1e-9)
            left = (total - steps) / rate if rate > 0 else float("inf")
            text = f"{task.key}: step {steps} of {total}, {rate:,.0f} steps/s"
            if left < float("inf"):
                text += f", about {left:.0f} s to go"
            if self.tty:
                parts.append(text)
            elif now - self.last.get(task.key, 0.0) >= REPORT_EVERY:
                self.last[task.key] = now
                print(f"[{done} of {self.total} {self.noun} done] {text}", file=sys.stderr, flush=True)
        if self.tty and parts:
            line = f"[{done} of {self.total} done] " + "; ".join(parts)
            print("\r" + line.ljust(self.width), end="", file=sys.stderr, flush=True)
            self.width = len(line)

    def close(self) -> None:
        if self.tty and self.width:
            print("\r" + " " * self.width + "\r", end="", file=sys.stderr, flush=True)
