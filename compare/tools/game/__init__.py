"""The seed's assignment as a game: push the ball with W A S D and score from at least 1 m.

    ball.py          the football as a custom_sim circle scene
    field.py         pitch and goal geometry, the 1 m rule's distance
    goal_contact.py  the penalty spring-damper against crossbar, back post and roof net
    passes.py        the teammate's seeded pass of each round
    rules.py         the referee: kicks, goals, shots, too close
    game.py          the game loop without a screen (key events at steps -> physics)
    engines.py       custom_sim or the MuJoCo twin under the same interface
    mujoco_ball.py   the MuJoCo twin of the ball behind custom_sim.Stepper's interface
    recording.py     recordings (JSON) and their exact replay
    view.py          the matplotlib picture, blitted
    window.py        the interactive window (real time)
    video.py         a replay rendered to .mp4 / .gif
    demo.py          how demo_goal.json was made
"""
from .game import KEY_FORCE, Game, KeyEvent
from .recording import Recording, Replay, load

__all__ = ["KEY_FORCE", "Game", "KeyEvent", "Recording", "Replay", "load"]
