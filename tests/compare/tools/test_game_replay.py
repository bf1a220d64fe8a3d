"""Recordings replay exactly; the shipped demo scores from at least 1 m; the `play` command."""
from __future__ import annotations

import json

import numpy as np
import pytest

from compare import cli
from compare.tools.game.demo import DEMO_PATH
from compare.tools.game.game import Game, KeyEvent
from compare.tools.game.recording import Recording, RecordingError, Replay, load, parse
from compare.tools.game.rules import GOAL


def states_along(replay: Replay, every: int) -> np.ndarray:
    """The ball's state every `every` steps to the end of the replay."""
    rows = []
    step = 0
    while not replay.done:
        step += every
        replay.advance_to(step)
        rows.append(replay.game.state)
    return np.array(rows)


def test_the_demo_scores_from_at_least_1_m():
    recording = load(DEMO_PATH)
    game = Replay.start(recording).run()
    goals = [a for a in game.referee.attempts if a.outcome == GOAL]
    assert game.referee.goals >= 1 and goals
    assert all(a.kick_distance >= game.field.min_kick_distance for a in goals)
    # what the demo shows; the exact distances follow custom_sim's physics (`python -m compare
    # tools game-demo` remakes the demo and its saved result after a change there)
    assert game.referee.outcomes == recording.result["outcomes"] == ["goal", "too close"]


def test_a_replay_is_bit_identical_twice():
    recording = load(DEMO_PATH)
    first = states_along(Replay.start(recording), every=40)
    second = states_along(Replay.start(recording), every=40)
    assert first.shape[0] > 300
    assert np.array_equal(first, second)


def test_free_runs_change_nothing():
    """Many steps per call far from the goal (fast) against one step per call: same bits."""
    recording = load(DEMO_PATH)
    fast = states_along(Replay.start(recording, fast=True), every=40)
    slow = states_along(Replay.start(recording, fast=False), every=40)
    assert np.array_equal(fast, slow)


def test_the_frame_rate_does_not_change_the_game():
    """A game played with frames at irregular steps (keys stamped at the frame's step, as the
    window does), saved and replayed straight through, ends in the same state, bit for bit."""
    rng = np.random.default_rng(11)
    live = Game(seed=5)
    script = {700: ("d", "press"), 1100: ("w", "press"), 1260: ("w", "release"),
              1400: ("d", "release"), 6000: ("a", "press"), 6300: ("a", "release")}
    frame_ends = np.cumsum(rng.integers(15, 60, size=400))
    done = set()
    for end in frame_ends:
        for step, (key, action) in script.items():
            if step not in done and live.step >= step:   # a key seen at the frame's step
                live.apply(KeyEvent(live.step, key, action))
                done.add(step)
        live.advance_to(int(end))
    recording = parse(json.loads(Recording.of(live).to_json()))
    replayed = Replay.start(recording).run()
    assert replayed.step == live.step
    assert np.array_equal(replayed.state, live.state)
    assert replayed.summary() == live.summary()


@pytest.mark.parametrize("text, field", [
    ("[]", "format"),
    ('{"format": "compare-game-recording", "version": 2}', "version"),
    ('{"format": "compare-game-recording", "version": 1, "seed": -1}', "seed"),
])
def test_bad_recordings_name_the_field(tmp_path, text, field):
    path = tmp_path / "bad.json"
    path.write_text(text)
    with pytest.raises(RecordingError) as err:
        load(path)
    assert err.value.field == field and str(path) in str(err.value)


def test_events_out_of_order_are_refused():
    data = json.loads(Recording.of(Game()).to_json())
    data["end_step"] = 100
    data["events"] = [{"step": 50, "key": "d", "action": "press"},
                      {"step": 10, "key": "d", "action": "release"}]
    with pytest.raises(RecordingError, match=r"events\[1\]\.step"):
        parse(data)


# ------------------------------------------------------------------------------ the command
def test_play_headless_prints_one_json_line(capsys):
    assert cli.main(["play", "--replay", "demo", "--headless"]) == 0
    out = capsys.readouterr().out.strip().splitlines()
    assert len(out) == 1
    result = json.loads(out[0])
    assert result["goals"] >= 1 and result["shots"] >= 1
    assert isinstance(result["kick_distances"], list)


def test_play_records_and_renders_a_gif_without_a_screen(tmp_path, capsys):
    game = Game(seed=3)
    game.advance_to(200)
    game.press("d")
    game.advance_to(400)
    game.release("d")
    game.advance_to(600)
    path = tmp_path / "short.json"
    Recording.of(game).save(path)
    out = tmp_path / "short.gif"
    assert cli.main(["play", "--replay", str(path), "--video", str(out), "--fps", "10"]) == 0
    import imageio.v3 as iio
    frames = iio.imread(out, index=None)
    # 0.3 s of game at 10 fps: frames at steps 0, 200, 400, 600, then one second held (Pillow
    # stores the held frames as one longer frame)
    assert "14 frames" in capsys.readouterr().out
    assert frames.shape[0] == 4 and frames.shape[1:3] == (432, 960)
    assert all(not np.array_equal(a, b) for a, b in zip(frames[:-1], frames[1:])), "the ball moves"


def test_play_without_a_display_says_so(monkeypatch, capsys):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.setattr("sys.platform", "linux")
    assert cli.main(["play"]) == 2
    err = capsys.readouterr().err
    assert "no display" in err and "--video" in err


@pytest.mark.parametrize("argv, message", [
    (["play", "--headless"], "--replay"),
    (["play", "--replay", "demo", "--video", "x.avi"], ".mp4 or .gif"),
    (["play", "--replay", "nope.json", "--headless"], "no such file"),
    (["play", "--replay", "demo", "--seed", "9", "--headless"], "seed"),
])
def test_play_bad_input_exits_2(argv, message, capsys):
    assert cli.main(argv) == 2
    assert message in capsys.readouterr().err


def test_the_demo_runs_on_the_mujoco_twin(capsys):
    """`--engine mujoco` replays the same key events on the MuJoCo twin of the ball: a
    different simulator, so only the form of the result is checked (no recorded result
    to reproduce)."""
    pytest.importorskip("mujoco_models")
    assert cli.main(["play", "--replay", "demo", "--engine", "mujoco", "--headless"]) == 0
    result = json.loads(capsys.readouterr().out.strip())
    assert result["steps"] == load(DEMO_PATH).end_step
    assert len(result["kick_distances"]) == result["shots"] + result["too_close"]
