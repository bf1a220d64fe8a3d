"""The referee: the 1 m rule, the whole ball over the line, rounds, and the teammate's passes."""
from __future__ import annotations

import math

import pytest

from compare.tools.game.ball import RADIUS
from compare.tools.game.field import FIELD
from compare.tools.game.game import Game
from compare.tools.game.passes import Pass, teammate_pass
from compare.tools.game.rules import GOAL, NO_KICK, TIME, TOO_CLOSE

LINE = FIELD.goal_line


def resting_at(x: float):
    def make(seed, round_index, rest):
        return Pass((x, rest), (0.0, 0.0))
    return make


def tap(game: Game, key: str = "d", seconds: float = 0.1) -> None:
    game.press(key)
    game.advance_to(game.step + int(round(seconds / game.dt)))
    game.release(key)


def run_until(game: Game, done, limit_s: float = 6.0, every: int = 1) -> Game:
    """Advance `every` steps at a time until done(game); fails after limit_s of game time."""
    limit = game.step + int(limit_s / game.dt)
    while not done(game):
        assert game.step < limit, "the situation the test waits for never came"
        game.advance_to(game.step + every)
    return game


def play_out(game: Game) -> Game:
    return run_until(game, lambda g: g.referee.outcome is not None, every=10)


def test_distance_to_the_goal_mouth():
    """The mouth is the segment x = goal line, 0 <= y <= underside of the crossbar."""
    top = FIELD.mouth_top
    assert FIELD.distance_to_mouth(LINE - 1.5, 0.11) == pytest.approx(1.5)
    assert FIELD.distance_to_mouth(LINE - 1.5, top) == pytest.approx(1.5)
    assert FIELD.distance_to_mouth(LINE - 0.6, top + 0.8) == pytest.approx(1.0)   # 0.6-0.8-1.0
    assert FIELD.distance_to_mouth(LINE + 0.2, 1.0) == pytest.approx(0.2)


def test_a_goal_from_inside_1_m_is_not_counted():
    game = Game(pass_maker=resting_at(LINE - 0.8))
    tap(game)
    play_out(game)
    ref = game.referee
    assert ref.outcome == TOO_CLOSE
    assert (ref.goals, ref.shots, ref.too_close) == (0, 0, 1)
    assert ref.last_kick_distance < FIELD.min_kick_distance
    assert "TOO CLOSE" in ref.message and "not counted" in ref.message


def test_the_same_tap_from_beyond_1_m_scores():
    game = Game(pass_maker=resting_at(LINE - 1.5))
    tap(game, seconds=0.15)
    play_out(game)
    ref = game.referee
    assert ref.outcome == GOAL
    assert (ref.goals, ref.shots, ref.too_close) == (1, 1, 0)
    # the kick ends where the force stops: the ball moved a little during the 0.15 s tap
    assert FIELD.min_kick_distance <= ref.last_kick_distance < 1.5
    assert game.summary()["kick_distances"] == [round(ref.last_kick_distance, 4)]


def test_the_last_kick_decides():
    """A push from 3 m, then a tap inside 1 m: the goal is from too close."""
    game = Game(pass_maker=resting_at(LINE - 3.0))
    tap(game, seconds=0.2)
    run_until(game, lambda g: g.state[0] >= LINE - 0.7)
    tap(game, seconds=0.02)
    play_out(game)
    assert game.referee.outcome == TOO_CLOSE
    assert game.referee.goals == 0


def test_holding_the_key_into_the_net_is_a_kick_from_the_line():
    """The kick's distance is taken at the last step the force acts: here, past the line."""
    game = Game(pass_maker=resting_at(LINE - 3.0))
    game.press("d")
    play_out(game)
    assert game.referee.outcome == TOO_CLOSE
    assert game.referee.last_kick_distance < RADIUS + 0.05


def test_a_goal_needs_the_whole_ball_over_the_line():
    """A ball stopped straddling the line is no goal; the outcome comes when x - R passes the line."""
    game = Game(pass_maker=resting_at(LINE - 1.5))
    tap(game, seconds=0.15)
    x_before = game.state[0]
    for _ in range(int(6.0 / game.dt)):
        x_before = game.state[0]
        game.advance_to(game.step + 1)
        if game.referee.outcome is not None:
            break
    assert game.referee.outcome == GOAL
    assert x_before - RADIUS <= LINE < game.state[0] - RADIUS


def test_a_pass_rolling_in_by_itself_counts_for_nothing():
    def fast_pass(seed, round_index, rest):
        return Pass((LINE - 3.0, rest), (6.0, 0.0), spin=-6.0 / RADIUS)
    game = play_out(Game(pass_maker=fast_pass))
    ref = game.referee
    assert ref.outcome == NO_KICK
    assert (ref.goals, ref.shots, ref.too_close) == (0, 0, 0)


def test_passes_stop_short_of_the_goal():
    """60 seeded passes without a key: none reaches the goal line (the ball stops on the pitch)."""
    for seed in range(3):
        game = Game(seed=seed)
        for _ in range(20):
            round_index = game.round
            furthest = 0.0
            for _ in range((game.round_steps + game.pause_steps) // 200 + 1):
                game.advance_to(game.step + 200)
                if game.round != round_index:
                    break
                furthest = max(furthest, game.state[0])
            assert furthest < LINE - 1.0, f"seed {seed} round {round_index}: the pass reached x = {furthest:.2f} m"
        assert set(game.referee.outcomes) == {TIME}


def test_passes_are_seeded_per_round():
    assert teammate_pass(4, 2) == teammate_pass(4, 2)
    assert teammate_pass(4, 2) != teammate_pass(4, 3)
    assert teammate_pass(4, 2) != teammate_pass(5, 2)


def test_r_starts_a_new_pass_and_q_stops_the_game():
    game = Game(seed=2)
    game.advance_to(1000)
    game.press("r")
    assert game.round == 1 and game.round_start == 1000
    assert tuple(game.state) == tuple(teammate_pass(2, 1, game.state[1]).state())
    game.advance_to(1500)
    game.press("q")
    game.advance_to(3000)
    assert game.step == 1500, "nothing runs after Q"
    assert [e.key for e in game.events] == ["r", "q"]


def test_a_round_times_out_and_the_next_pass_comes():
    game = Game(seed=0)
    end = game.round_steps + game.pause_steps
    game.advance_to(end - 1)
    assert game.round == 0 and game.referee.outcome == TIME
    game.advance_to(end)
    assert game.round == 1 and game.referee.outcome is None
    assert math.isclose(game.state[0], teammate_pass(0, 1).position[0])
