"""Recordings: every key event with its physics step, saved as JSON, and their exact replay.

    {"format": "compare-game-recording", "version": 1,
     "seed": 3, "engine": "custom", "dt": 0.0005, "key_force": 12.0,
     "end_step": 14000,
     "events": [{"step": 1480, "key": "d", "action": "press"}, ...],
     "result": {"goals": 1, "shots": 1, ...}}     # the summary when it was recorded

A replay rebuilds the game from seed, engine, dt and key force, and applies each event at
its step: the same arithmetic as the recorded game, so the same result bit for bit.
`result` lets a replay tell when the game's physics has changed since the recording.
"""
from __future__ import annotations

import json
from collections import deque
from dataclasses import dataclass, field
from pathlib import Path

from .game import KEYS, PRESS, RELEASE, Game, KeyEvent

FORMAT = "compare-game-recording"
VERSION = 1
ENGINES = ("custom", "mujoco")


class RecordingError(ValueError):
    """Bad recording file: `file: field: message`."""

    def __init__(self, file: str, field: str, message: str):
        self.file, self.field, self.message = file, field, message
        super().__init__(f"{file}: {field}: {message}" if field else f"{file}: {message}")


@dataclass(frozen=True)
class Recording:
    seed: int
    events: tuple[KeyEvent, ...]
    end_step: int
    dt: float
    key_force: float
    engine: str = "custom"
    result: dict | None = None

    @classmethod
    def of(cls, game: Game, engine: str = "custom") -> Recording:
        """The recording of a game played so far (ends at its current step)."""
        return cls(seed=game.seed, events=tuple(game.events), end_step=game.step, dt=game.dt,
                   key_force=game.key_force, engine=engine, result=game.summary())

    def to_json(self) -> str:
        """The file's text: one event per line, so a recording reads and diffs well."""
        head = {"format": FORMAT, "version": VERSION, "seed": self.seed, "engine": self.engine,
                "dt": self.dt, "key_force": self.key_force, "end_step": self.end_step}
        if self.result is not None:
            head["result"] = self.result
        lines = [f" {json.dumps(k)}: {json.dumps(v)}," for k, v in head.items()]
        events = [json.dumps({"step": e.step, "key": e.key, "action": e.action}) for e in self.events]
        body = ",\n  ".join(events)
        return "{\n" + "\n".join(lines) + '\n "events": [\n  ' + body + "\n ]\n}\n"

    def save(self, path: str | Path) -> None:
        Path(path).write_text(self.to_json(), encoding="utf-8")


def load(path: str | Path) -> Recording:
    """Read and validate a recording; raises RecordingError naming the file and the field."""
    file = str(path)
    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise RecordingError(file, "", "no such file (expected a recording written by `play --record`)") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise RecordingError(file, "", f"cannot be read as JSON ({exc})") from None
    return parse(data, file)


def parse(data, file: str = "<memory>") -> Recording:
    def fail(name, message):
        raise RecordingError(file, name, message)

    if not isinstance(data, dict) or data.get("format") != FORMAT:
        fail("format", f"expected \"{FORMAT}\" (a file written by `play --record`)")
    if data.get("version") != VERSION:
        fail("version", f"expected {VERSION}, got {data.get('version')!r}")

    def integer(name, minimum=0):
        x = data.get(name)
        if isinstance(x, bool) or not isinstance(x, int) or x < minimum:
            fail(name, f"expected an integer >= {minimum}, got {x!r}")
        return x

    def positive(name):
        x = data.get(name)
        if isinstance(x, bool) or not isinstance(x, (int, float)) or not x > 0:
            fail(name, f"expected a number > 0, got {x!r}")
        return float(x)

    seed, end_step = integer("seed"), integer("end_step")
    dt, key_force = positive("dt"), positive("key_force")
    engine = data.get("engine", "custom")
    if engine not in ENGINES:
        fail("engine", f"unknown engine {engine!r} (expected one of: {', '.join(ENGINES)})")
    raw = data.get("events")
    if not isinstance(raw, list):
        fail("events", "expected a list of {step, key, action}")
    events, last = [], 0
    for i, e in enumerate(raw):
        where = f"events[{i}]"
        if not isinstance(e, dict) or set(e) != {"step", "key", "action"}:
            fail(where, f"expected {{step, key, action}}, got {e!r}")
        step = e["step"]
        if isinstance(step, bool) or not isinstance(step, int) or not last <= step <= end_step:
            fail(where + ".step", f"expected an integer from {last} (the previous event) to end_step {end_step}, got {step!r}")
        if e["key"] not in KEYS:
            fail(where + ".key", f"expected one of {', '.join(KEYS)}, got {e['key']!r}")
        if e["action"] not in (PRESS, RELEASE):
            fail(where + ".action", f"expected press or release, got {e['action']!r}")
        events.append(KeyEvent(step, e["key"], e["action"]))
        last = step
    result = data.get("result")
    return Recording(seed=seed, events=tuple(events), end_step=end_step, dt=dt,
                     key_force=key_force, engine=engine, result=result if isinstance(result, dict) else None)


@dataclass
class Replay:
    """A recording played back: `advance_to(step)` applies the events due and runs the physics."""

    recording: Recording
    game: Game
    pending: deque = field(default_factory=deque)

    @classmethod
    def start(cls, recording: Recording, engine=None, fast: bool = True) -> Replay:
        game = Game(seed=recording.seed, dt=recording.dt, key_force=recording.key_force,
                    engine=engine, fast=fast)
        return cls(recording, game, deque(recording.events))

    @property
    def done(self) -> bool:
        return self.game.quit or self.game.step >= self.recording.end_step

    def advance_to(self, step: int) -> None:
        step = min(step, self.recording.end_step)
        while self.pending and self.pending[0].step <= step:
            event = self.pending.popleft()
            self.game.advance_to(event.step)
            self.game.apply(event)
        self.game.advance_to(step)

    def run(self) -> Game:
        """Play to the end; returns the game (its `summary()` is the outcome)."""
        self.advance_to(self.recording.end_step)
        return self.game

    def matches_recording(self) -> bool | None:
        """Whether the outcome equals the one saved with the recording (None if none was saved),
        on the keys the recording saved (an older recording lacks the keys added since)."""
        if self.recording.result is None:
            return None
        summary = self.game.summary()
        return all(summary.get(key) == value for key, value in self.recording.result.items())
