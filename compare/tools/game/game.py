"""The game loop without a screen: key events at physics steps in, the ball's motion and the score out.

The window, the video renderer, the replays and the tests all drive this one class: they
feed it `KeyEvent`s stamped with the physics step at which they act and ask it to
`advance_to` a step. It never looks at a clock, so the same events give the same game,
bit for bit, whatever the frame rate.

One physics step of size h (the scene's dt) from state z_n:

    F_key  = KEY_FORCE * (sum of the held keys' directions)        W up, A left, S down, D right
    F_goal = goal_contact.goal_force(z_n)                          posts, crossbar, net
    z_n+1  = Stepper.advance(1, force=F_key + F_goal)              ground, friction, rolling, gravity

Far from the goal with no key held only the ground acts, and many steps go to the compiled
loop at once (see `_free_steps`): the same arithmetic in the same order, so the result is
bit-identical to stepping one at a time (a test checks it).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from custom_sim import Stepper, mass_properties

from .ball import DT, ball_scene, resting_height
from .field import FIELD, Field
from .goal_contact import clearance, goal_force
from .passes import teammate_pass
from .rules import Referee

# N: a key held for 0.1 s gives the 0.43 kg ball 2.8 m/s; W (12 N > m g = 4.2 N) lifts it.
KEY_FORCE = 12.0
DIRECTIONS = {"w": (0.0, 1.0), "a": (-1.0, 0.0), "s": (0.0, -1.0), "d": (1.0, 0.0)}
RESTART, QUIT = "r", "q"
KEYS = (*DIRECTIONS, RESTART, QUIT)
PRESS, RELEASE = "press", "release"

ROUND_TIME = 12.0    # s a round lasts without an outcome
PAUSE_TIME = 2.5     # s between an outcome and the next pass (the ball rolls into the net)

# The free run (several steps per call) is allowed only while the ball cannot reach a goal
# capsule, the goal line or the edge of the pitch within it. Without applied force the ground
# only stores or dissipates energy, so the speed is bounded by the energy at the start:
#   m v^2 / 2 <= E + (m g)^2 / (2 k),  E = m v^2/2 + I w^2/2 + m g (y - R) + k d^2/2,
# the last term the most a spring can return below y = R. Semi-implicit Euler's energy error
# in contact is O(h wn) = 11 % at this step; SPEED_SAFETY covers it twice over.
SPEED_SAFETY = 1.5
GAP_MARGIN = 0.02     # m kept free at the end of a free run
MAX_FREE_STEPS = 400  # 0.2 s: keeps the speed bound fresh


@dataclass(frozen=True)
class KeyEvent:
    """A key pressed or released (action PRESS / RELEASE), acting from physics step `step`:
    the step that takes the state from `step` to `step + 1` is the first to feel it."""

    step: int
    key: str
    action: str = PRESS


# What each key of Game.summary() (the line `play --headless` prints) counts.
SUMMARY_KEYS = {
    "goals": "rounds that ended in a goal: the whole ball crossed the goal line under the bar, "
             "last kicked from at least 1 m",
    "shots": "balls that reached the goal line (under or over the bar) last kicked from at least 1 m; "
             "same as shots_from_1m_or_more",
    "kick_distances": "for each ball that reached the goal line after a kick, the distance (m) from the "
                      "ball's centre to the goal mouth at the last step the player's force acted; "
                      "same as last_kick_distances_m",
    "too_close": "balls that crossed under the bar but were last kicked from under 1 m (shown, not "
                 "counted); same as goals_too_close_not_counted",
    "kicks": "presses of W, A, S or D over the whole game, in every round, whether or not the ball "
             "reached the goal; same as key_presses",
    "rounds": "passes played (rounds begun); same as passes_played",
    "outcomes": "how each round ended: goal, too close, over, no kick, out, time; same as round_outcomes",
    "steps": "physics steps simulated; same as physics_steps",
    "seed": "the seed of the teammate's passes; same as pass_seed",
    "key_presses": "presses of W, A, S or D over the whole game",
    "balls_at_goal_line": "balls that reached the goal line after a kick (one per entry of "
                          "last_kick_distances_m and of attempts)",
    "last_kick_distances_m": "for each ball at the goal line, the distance (m) to the goal mouth of "
                             "its last kick",
    "shots_from_1m_or_more": "balls at the goal line last kicked from at least 1 m",
    "goals_too_close_not_counted": "balls under the bar last kicked from under 1 m",
    "passes_played": "rounds begun",
    "round_outcomes": "each round's outcome, in order",
    "physics_steps": "physics steps simulated",
    "pass_seed": "the seed of the teammate's passes",
    "attempts": "one entry per ball at the goal line: its round (from 0), outcome, "
                "last_kick_distance_m and whether it counted as a shot",
}


class Game:
    """The kick-the-ball game: one ball, the goal, the referee, rounds of passes.

    seed: the passes' random generator; dt: physics step (s); engine: an object with
    `.state` [x, y, theta, vx, vy, omega], `.advance(n, force)` and `.reset(state)`
    (a custom_sim.Stepper by default); fast: allow free runs (off: one step per call);
    obstacles: the goal capsules (default: the field's goal frame); pass_maker(seed, round,
    height) -> Pass: the ball's start of each round (default: the teammate's seeded pass).
    """

    def __init__(self, seed: int = 0, dt: float = DT, key_force: float = KEY_FORCE,
                 field: Field = FIELD, engine=None, fast: bool = True, obstacles=None,
                 pass_maker=teammate_pass):
        self.seed, self.dt, self.key_force, self.field, self.fast = seed, dt, key_force, field, fast
        self.pass_maker = pass_maker
        self.scene = ball_scene(dt)
        self.radius = self.scene.body.radius
        self.obstacles = field.obstacles() if obstacles is None else tuple(obstacles)
        self.engine = engine if engine is not None else Stepper(self.scene, watch_chatter=False)
        props = mass_properties(self.scene.body)
        self._m, self._inertia = props.mass, props.inertia
        self._g, self._k = self.scene.g, self.scene.contact.k
        self.referee = Referee(field, self.radius)
        self.step = 0
        self.held: list[str] = []          # movement keys held, in the order pressed
        self.events: list[KeyEvent] = []   # every event applied: the recording
        self.quit = False
        self.round = -1
        self.round_start = 0
        self.next_round_step: int | None = None
        self.round_steps = int(round(ROUND_TIME / dt))
        self.pause_steps = int(round(PAUSE_TIME / dt))
        self._new_round()

    # ----------------------------------------------------------------------------- input
    def apply(self, event: KeyEvent) -> None:
        """Act on a key event stamped with the current step."""
        if event.step != self.step:
            raise ValueError(f"event {event} is for step {event.step}, the game is at step {self.step}")
        if event.key not in KEYS or event.action not in (PRESS, RELEASE):
            raise ValueError(f"unknown key event {event} (keys: {', '.join(KEYS)}; actions: press, release)")
        if self.quit:
            return
        if event.key in DIRECTIONS:
            if event.action == PRESS and event.key not in self.held:
                self.held.append(event.key)
                self.referee.kick()
            elif event.action == RELEASE and event.key in self.held:
                self.held.remove(event.key)
            else:
                return   # a repeat of the key's state: nothing changes, nothing recorded
        elif event.action == RELEASE:
            return
        elif event.key == RESTART:
            self._new_round()
        else:
            self.quit = True
        self.events.append(event)

    def press(self, key: str) -> None:
        self.apply(KeyEvent(self.step, key, PRESS))

    def release(self, key: str) -> None:
        self.apply(KeyEvent(self.step, key, RELEASE))

    def player_force(self) -> tuple[float, float]:
        """The player's force (N) from the keys held."""
        fx = sum(DIRECTIONS[k][0] for k in self.held)
        fy = sum(DIRECTIONS[k][1] for k in self.held)
        return self.key_force * fx, self.key_force * fy

    # --------------------------------------------------------------------------- physics
    @property
    def state(self):
        """The ball's [x, y, theta, vx, vy, omega] (a copy)."""
        return self.engine.state.copy()

    @property
    def time(self) -> float:
        return self.step * self.dt

    def advance_to(self, target: int) -> None:
        """Run the physics up to step `target` (nothing happens after a quit)."""
        while self.step < target and not self.quit:
            n = self._free_steps(min(target, self._next_scheduled()) - self.step) if self.fast else 0
            if n > 1:
                self.engine.advance(n, force=(0.0, 0.0, 0.0))
                self.step += n
            else:
                self._one_step()
            self._judge()

    def _one_step(self) -> None:
        x, y, _, vx, vy, _ = self.engine.state.tolist()
        fx, fy = goal_force(self.obstacles, self.radius, x, y, vx, vy)
        if self.held:
            kx, ky = self.player_force()
            fx += kx
            fy += ky
            self.referee.force_applied(x, y)
        self.engine.advance(1, force=(fx, fy, 0.0))
        self.step += 1

    def _free_steps(self, limit: int) -> int:
        """How many steps may run without the goal frame, a key, or the referee: 0 if any
        could act. Travel in n steps <= n h v_max (energy bound above)."""
        if self.held or limit < 2:
            return 0
        x, y, _, vx, vy, om = self.engine.state.tolist()
        f, r = self.field, self.radius
        gap = min(clearance(self.obstacles, r, x, y), x - f.left_edge, f.right_edge - x)
        if self.referee.outcome is None:
            gap = min(gap, f.goal_line + r - x)   # the whole ball crosses at x = goal line + R
        d = max(0.0, r - y)
        energy = (0.5 * self._m * (vx * vx + vy * vy) + 0.5 * self._inertia * om * om
                  + self._m * self._g * (y - r) + 0.5 * self._k * d * d)
        v2 = 2.0 * (energy + (self._m * self._g) ** 2 / (2.0 * self._k)) / self._m
        v_max = SPEED_SAFETY * math.sqrt(max(v2, 0.0)) + 1e-9
        n = int((gap - GAP_MARGIN) / (v_max * self.dt))
        return max(0, min(n, limit, MAX_FREE_STEPS))

    # ---------------------------------------------------------------------------- rounds
    def _next_scheduled(self) -> int:
        """The next step at which a round starts or times out."""
        if self.next_round_step is not None:
            return self.next_round_step
        return self.round_start + self.round_steps

    def _judge(self) -> None:
        """After a step: the referee looks at the ball, then the round clock."""
        x, y = float(self.engine.state[0]), float(self.engine.state[1])
        if self.referee.watch(self.step, x, y) is not None:
            self.next_round_step = self.step + self.pause_steps
        elif self.next_round_step is None and self.step >= self.round_start + self.round_steps:
            self.referee.time_up()
            self.next_round_step = self.step + self.pause_steps
        if self.next_round_step is not None and self.step >= self.next_round_step:
            self._new_round()

    def _new_round(self) -> None:
        self.round += 1
        self.round_start = self.step
        self.next_round_step = None
        p = self.pass_maker(self.seed, self.round, resting_height(self.scene))
        self.engine.reset(p.state())
        self.referee.new_round(self.round)

    # --------------------------------------------------------------------------- results
    def summary(self) -> dict:
        """The outcome as plain data: what `play --headless` prints (SUMMARY_KEYS says what
        each key counts; the short keys came first and stay, the long ones say it in the name)."""
        ref = self.referee
        distances = [round(a.kick_distance, 4) for a in ref.attempts]
        return {
            "goals": ref.goals,
            "shots": ref.shots,
            "kick_distances": distances,
            "too_close": ref.too_close,
            "kicks": ref.kicks,
            "rounds": self.round + 1,
            "outcomes": list(ref.outcomes),
            "steps": self.step,
            "seed": self.seed,
            "key_presses": ref.kicks,
            "balls_at_goal_line": len(ref.attempts),
            "last_kick_distances_m": distances,
            "shots_from_1m_or_more": ref.shots,
            "goals_too_close_not_counted": ref.too_close,
            "passes_played": self.round + 1,
            "round_outcomes": list(ref.outcomes),
            "physics_steps": self.step,
            "pass_seed": self.seed,
            "attempts": [{"round": a.round, "outcome": a.outcome, "last_kick_distance_m": round(a.kick_distance, 4),
                          "counted": a.counted} for a in ref.attempts],
        }
