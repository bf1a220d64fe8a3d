"""The state of the body, named once: its six components, in order, and their units. Every
array of states (steps + 1, 6), every trajectory CSV and every message that lists the state
takes its order and its units from here."""
from __future__ import annotations

# centre of mass x, y (m); angle theta (rad, counter-clockwise); velocities vx, vy (m/s) and omega (rad/s)
STATE_COMPONENTS = ("x", "y", "theta", "vx", "vy", "omega")
STATE_UNITS = ("m", "m", "rad", "m/s", "m/s", "rad/s")
UNIT_OF = dict(zip(STATE_COMPONENTS, STATE_UNITS))
POSE = STATE_COMPONENTS[:3]               # x, y, theta: where the body is
STATE_TEXT = f"[{', '.join(STATE_COMPONENTS)}]"     # "[x, y, theta, vx, vy, omega]", for messages
UNITS_TEXT = f"({', '.join(STATE_UNITS)})"          # "(m, m, rad, m/s, m/s, rad/s)"
