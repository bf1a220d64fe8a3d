"""The referee: kicks, the 1 m rule, goals, shots and the outcome of each round.

A kick is a press of W, A, S or D; while a key is held its force acts on the ball. The
distance of a kick is the distance from the ball's centre to the goal mouth at the last
physics step on which the player's force acted, so the whole kick must be taken from at
least 1 m (holding D and pushing the ball into the net is a kick from 0 m).

A round ends at the first of:
    the whole ball crosses the goal line (x - R > goal line):
        below the crossbar (centre under the bar's axis; the bar and the roof net stop a
        ball that crossed above from getting there):
            never kicked this round       "no kick"    (the pass rolled in: nothing counts)
            last kick >= 1 m              "goal"       a shot and a goal
            last kick <  1 m              "too close"  shown, not counted
        above it                          "over"       a shot if kicked from >= 1 m
    the ball leaves the pitch             "out"
    the round's time runs out             "time"
"""
from __future__ import annotations

from dataclasses import dataclass, field

from .field import Field

GOAL, TOO_CLOSE, OVER, NO_KICK, OUT, TIME = "goal", "too close", "over", "no kick", "out", "time"


@dataclass(frozen=True)
class Attempt:
    """A kicked ball that reached the goal line: round (0-based), step, outcome, kick distance (m)."""

    round: int
    step: int
    outcome: str
    kick_distance: float
    counted: bool


@dataclass
class Referee:
    """Keeps the score. Call `new_round`, `kick` on each press, `force_applied` on each step the
    player's force acts (with the ball's position at the start of that step), `watch` after
    each step."""

    field: Field
    radius: float
    goals: int = 0
    shots: int = 0
    too_close: int = 0
    kicks: int = 0
    attempts: list[Attempt] = field(default_factory=list)
    outcomes: list[str] = field(default_factory=list)
    round: int = -1
    kicked: bool = False                 # the player's force acted in this round
    last_kick_distance: float | None = None  # m, this round's last kick (None before any)
    outcome: str | None = None           # this round's outcome, None while it is in play
    message: str = ""

    def new_round(self, round_index: int) -> None:
        self.round = round_index
        self.kicked = False
        self.last_kick_distance = None
        self.outcome = None
        self.message = "Here comes the pass!"

    def kick(self) -> None:
        self.kicks += 1
        if self.outcome is None:
            self.message = ""

    def force_applied(self, x: float, y: float) -> None:
        if self.outcome is None:
            self.kicked = True
            self.last_kick_distance = self.field.distance_to_mouth(x, y)

    def time_up(self) -> None:
        self._end(TIME, "Time up: new pass")

    def watch(self, step: int, x: float, y: float) -> str | None:
        """Judge the ball at (x, y) (m) after `step`; returns the outcome if the round ended now."""
        if self.outcome is not None:
            return None
        f = self.field
        if x - self.radius > f.goal_line:
            return self._crossed(step, below_bar=y < f.crossbar_height)
        if x < f.left_edge or x > f.right_edge:
            return self._end(OUT, "Out of play")
        return None

    def _crossed(self, step: int, below_bar: bool) -> str:
        if not self.kicked:
            return self._end(NO_KICK, "The pass rolled in by itself: kick it to score")
        d = self.last_kick_distance
        far = d >= self.field.min_kick_distance
        if below_bar and far:
            self.goals += 1
            outcome, text = GOAL, f"GOAL! kicked from {d:.2f} m"
        elif below_bar:
            self.too_close += 1
            outcome = TOO_CLOSE
            text = f"TOO CLOSE: kicked from {d:.2f} m < {self.field.min_kick_distance:g} m, not counted"
        else:
            outcome, text = OVER, f"Over the bar (kicked from {d:.2f} m)"
        self.shots += far
        self.attempts.append(Attempt(self.round, step, outcome, d, far))
        return self._end(outcome, text)

    def _end(self, outcome: str, text: str) -> str:
        self.outcome = outcome
        self.outcomes.append(outcome)
        self.message = text
        return outcome
