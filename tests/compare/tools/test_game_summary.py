"""The headless game's JSON says what it counts: every key documented, the long names agree
with the short ones, and the counts fit together on the shipped demo."""
from __future__ import annotations

import json

import pytest

from compare import cli
from compare.tools.game.demo import DEMO_PATH
from compare.tools.game.game import SUMMARY_KEYS
from compare.tools.game.recording import Replay, load
from compare.tools.game.rules import GOAL, OVER, TOO_CLOSE

SAME = {"kicks": "key_presses", "kick_distances": "last_kick_distances_m", "shots": "shots_from_1m_or_more",
        "too_close": "goals_too_close_not_counted", "rounds": "passes_played", "outcomes": "round_outcomes",
        "steps": "physics_steps", "seed": "pass_seed"}


@pytest.fixture(scope="module")
def demo():
    recording = load(DEMO_PATH)
    return recording, Replay.start(recording).run().summary()


def test_every_key_is_documented_and_every_documented_key_is_there(demo):
    _, summary = demo
    assert set(summary) == set(SUMMARY_KEYS)


def test_long_names_repeat_the_short_ones(demo):
    _, summary = demo
    for short, long in SAME.items():
        assert summary[short] == summary[long], (short, long)


def test_the_counts_fit_together(demo):
    _, s = demo
    # one distance and one attempt per ball that reached the goal line after a kick
    assert s["balls_at_goal_line"] == len(s["kick_distances"]) == len(s["attempts"])
    assert [a["last_kick_distance_m"] for a in s["attempts"]] == s["kick_distances"]
    outcomes = [a["outcome"] for a in s["attempts"]]
    assert s["goals"] == outcomes.count(GOAL) and s["too_close"] == outcomes.count(TOO_CLOSE)
    assert s["shots"] == sum(a["counted"] for a in s["attempts"]) >= s["goals"]
    assert all(o in (GOAL, TOO_CLOSE, OVER) for o in outcomes)
    # key presses count every press, so they are at least the kicked balls and need not match
    assert s["key_presses"] >= s["balls_at_goal_line"]
    assert len(s["round_outcomes"]) == s["passes_played"]


def test_an_older_recording_still_matches_on_the_keys_it_saved(demo):
    recording, _ = demo
    assert set(recording.result) < set(SUMMARY_KEYS), "the demo was saved before the long keys"
    replay = Replay.start(recording)
    replay.run()
    assert replay.matches_recording() is True


def test_help_lists_every_key(capsys):
    with pytest.raises(SystemExit):
        cli.main(["play", "--help"])
    out = capsys.readouterr().out
    for key in SUMMARY_KEYS:
        assert f"  {key} " in out, key


def test_headless_prints_every_key(capsys):
    assert cli.main(["play", "--replay", "demo", "--headless"]) == 0
    assert set(json.loads(capsys.readouterr().out.strip().splitlines()[-1])) == set(SUMMARY_KEYS)
