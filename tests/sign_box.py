"""box_drop under the bare sign friction (friction_law = "sign") and implicit Euler, and one
step of custom_sim's run of it that sits on the sign's jump: shared by the oracle's and the
step check's tests."""
from __future__ import annotations

import dataclasses

from compare.scenarios import load

# At t = 1.2272 s (step 24544 of h = 5e-5 s) the box lies on its two bottom corners (1.08 mm
# deep), rocking at -8.1e-3 rad/s, their slips +5.9e-10 and -9.8e-11 m/s; the levers differ by
# w sin(theta) = 8e-8 m, so which corner sticks hangs on slips of 1e-9 m/s. custom_sim's state
# and its next one, to the bit.
STATE = [0.1482882541664242, 0.04892420599998017, -4.2211513435646455e-07,
         0.00040687993688484126, 0.0036861286480105696, -0.008137593818945237]
NEXT = [0.14828827447907422, 0.04892439249190722, -8.283674601699119e-07,
        0.00040625300079496807, 0.003729838540949875, -0.008125046516268948]


def scene():
    """box_drop with friction_law = "sign" (no alpha) and implicit Euler."""
    base = load("box_drop")
    contact = dataclasses.replace(base.contact, friction_law="sign", alpha=None)
    return dataclasses.replace(base, name="sign_box", integrator="implicit_euler", contact=contact)
