"""Play the seed's assignment: push the ball with W A S D and score from at least 1 m (or replay a game).

    python -m compare play                                    # a window; needs a display
    python -m compare play --record game.json                 # ... and save every key event
    python -m compare play --replay game.json                 # watch a recording in a window
    python -m compare play --replay game.json --video out.mp4 # render it without a screen (.mp4 or .gif)
    python -m compare play --replay game.json --headless      # print the outcome as one JSON line
    python -m compare play --replay demo --video demo.mp4     # the shipped demo (compare/tools/game/demo_goal.json)

--video needs the game extra (imageio, imageio-ffmpeg): pip install -e '.[game]'.

Keys: W up, A left, S down, D right (force while held), R new pass, Q quit. A goal counts
when the last kick is taken with the ball at least 1 m from the goal mouth and the whole
ball crosses the goal line under the crossbar.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

EXIT_OK, EXIT_BAD_INPUT = 0, 2


def add_arguments(parser) -> None:
    from compare.tools.game.game import SUMMARY_KEYS

    parser.epilog = "What --headless prints (one JSON object):\n" + "\n".join(
        f"  {key:<28} {text}" for key, text in SUMMARY_KEYS.items())
    parser.add_argument("--record", metavar="FILE", help="save every key event with its physics step (JSON)")
    parser.add_argument("--replay", metavar="FILE",
                        help="play a recording back exactly ('demo': the shipped demo recording)")
    parser.add_argument("--video", metavar="OUT", help="with --replay: render to OUT (.mp4 or .gif) without a screen")
    parser.add_argument("--headless", action="store_true",
                        help="with --replay: print the outcome as one JSON line (every key below)")
    parser.add_argument("--fps", type=float, default=None,
                        help="video frame rate (default 50 for .mp4, 25 for .gif)")
    parser.add_argument("--seed", type=int, default=None,
                        help="seed of the teammate's passes (default 0; a replay uses its recording's)")
    parser.add_argument("--engine", choices=("custom", "mujoco"), default=None,
                        help="the ball's simulator: custom_sim (default) or its MuJoCo twin; "
                             "a replay defaults to the engine it was recorded with")


def _fail(message: str) -> int:
    print(f"play: {message}", file=sys.stderr)
    return EXIT_BAD_INPUT


def main(args) -> int:
    from compare.tools.game.demo import DEMO_PATH
    from compare.tools.game.engines import EngineUnavailable, make_engine
    from compare.tools.game.game import Game
    from compare.tools.game.recording import RecordingError, Replay, load

    if (args.video or args.headless) and not args.replay:
        return _fail("--video and --headless play a recording: add --replay FILE "
                     "(record one with --record FILE, or use --replay demo)")
    if args.record and args.replay:
        return _fail("--record and --replay exclude each other (a replay is already a recording)")
    if args.video and Path(args.video).suffix.lower() not in (".mp4", ".gif"):
        return _fail(f"{args.video}: --video writes .mp4 or .gif (got {Path(args.video).suffix or 'no extension'!r})")
    if args.fps is not None and not args.fps > 0:
        return _fail(f"--fps: expected a number > 0, got {args.fps}")
    if args.video:
        from compare.tools.game.video import require_writer
        require_writer(args.video)   # the game extra: one line and exit 2, before the replay runs

    replay = None
    if args.replay:
        path = DEMO_PATH if args.replay == "demo" else Path(args.replay)
        try:
            recording = load(path)
        except RecordingError as exc:
            return _fail(str(exc))
        if args.seed is not None and args.seed != recording.seed:
            return _fail(f"--seed {args.seed}: {path} was played with seed {recording.seed} "
                         "(a replay keeps its recording's seed; leave --seed out)")
        engine_name = args.engine or recording.engine
        try:
            engine = make_engine(engine_name, recording.dt)
        except EngineUnavailable as exc:
            return _fail(str(exc))
        replay = Replay.start(recording, engine=engine)
        game = replay.game
    else:
        engine_name = args.engine or "custom"
        try:
            engine = make_engine(engine_name)
        except EngineUnavailable as exc:
            return _fail(str(exc))
        game = Game(seed=args.seed or 0, engine=engine)

    if replay is not None and (args.video or args.headless):
        if args.video:
            from compare.tools.game.video import render_video
            frames = render_video(replay, args.video, fps=args.fps)
            print(f"wrote {args.video}: {frames} frames", file=sys.stderr if args.headless else sys.stdout)
        else:
            replay.run()
        if args.headless:
            print(json.dumps(game.summary()))
        return _check(replay, engine_name)

    from compare.tools.game.window import Window, display_problem
    problem = display_problem()
    if problem:
        what = args.replay or "demo"
        return _fail(f"{problem}, so no window can open. Without a screen, render a recording: "
                     f"python -m compare play --replay {what} --video out.mp4 "
                     f"(or --headless for the score)")
    Window(game, replay=replay, record_path=args.record, engine_name=engine_name).run()
    return _check(replay, engine_name) if replay is not None and replay.done else EXIT_OK


def _check(replay, engine_name: str) -> int:
    """A replay on its recording's engine reproduces the recorded result, unless the physics
    or the rules changed since the recording was made: say so (the replay still ran)."""
    if engine_name == replay.recording.engine and replay.matches_recording() is False:
        print(f"play: note: the recording saved the result {json.dumps(replay.recording.result)}; "
              "this replay differs, so the game's physics or rules changed since it was recorded "
              "(python -m compare tools game-demo remakes the demo)", file=sys.stderr)
    return EXIT_OK
