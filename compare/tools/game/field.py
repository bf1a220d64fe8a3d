"""The pitch seen from the side: ground y = 0, the goal on the right, the 1 m kicking limit.

In a side view the ball plays in the goal's middle plane. The two goal posts stand on
either side of that plane (the far one is drawn behind the ball), so the ball never meets
them; what crosses the plane, and what the ball bounces off, is the crossbar (seen end-on,
a circle at the top of the goal mouth), the back post of the goal, and the net (roof and
back, the back net hanging just in front of the back post).
Each is a capsule: a segment a-b thickened by a radius, with its own penalty spring-damper.

Lengths in m, stiffness in N/m, damping in N s/m.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .ball import MASS


def damping_for(zeta: float, k: float, mass: float = MASS) -> float:
    """c = 2 zeta sqrt(k m) (N s/m): the damping that gives the ball damping ratio zeta."""
    return 2.0 * zeta * math.sqrt(k * mass)


def compression_restitution(zeta: float) -> float:
    """Restitution of a spring-damper that damps only on compression (gravity ignored).

    Compression: x(t) = v0/wd exp(-zeta wn t) sin(wd t), which stops at tan(wd t*) = wd/(zeta wn);
    its depth x* = v0/wn exp(-zeta wn t*). Release is undamped, so v_out = wn x*:
        e = exp(-zeta / s * atan(s / zeta)),   s = sqrt(1 - zeta^2)          (zeta < 1)
        e = exp(-zeta / s * atanh(s / zeta)),  s = sqrt(zeta^2 - 1)          (zeta > 1, overdamped)
    and e = exp(-1) at zeta = 1, the limit of both.
    """
    if zeta == 1.0:
        return math.exp(-1.0)
    if zeta < 1.0:
        s = math.sqrt(1.0 - zeta * zeta)
        return math.exp(-zeta / s * math.atan(s / zeta))
    s = math.sqrt(zeta * zeta - 1.0)
    return math.exp(-zeta / s * math.atanh(s / zeta))


@dataclass(frozen=True)
class Segment:
    """A capsule obstacle: points within `radius` of the segment a-b (m) are solid.
    Contact with the ball: Fn = k d + c max(0, -vn) along the normal (damping law "compression")."""

    name: str
    a: tuple[float, float]
    b: tuple[float, float]
    radius: float
    k: float
    c: float


# Goal frame contact. The ball must never tunnel through a bar: its deepest penetration
# v / wn must stay below R + r. A 20 m/s strike on k = 1e5 N/m (wn = 482 rad/s) goes 4 cm
# deep (R + r = 0.17 m); semi-implicit Euler needs h wn < 2: at h = 5e-4 s, h wn = 0.24.
BAR_K = 1e5           # N/m, steel bar
BAR_ZETA = 0.2        # restitution 0.76 off the crossbar and the back post
# The net catches the ball: overdamped, restitution 0.15. Explicit damping needs h c / m < 2:
# c = 393 N s/m gives 0.46. A 20 m/s ball goes v / (wn (zeta + s)) ~ 2 cm deep, short of the
# post behind the back net (NET_GAP) and far from tunnelling (R + r = 0.13 m).
NET_K = 1e4           # N/m
NET_ZETA = 3.0
NET_GAP = 0.05        # m between the back net and the back post's surface


@dataclass(frozen=True)
class Field:
    """Where things are (m). The goal line is x = goal_line; the mouth is the segment of it
    from the ground up to the underside of the crossbar."""

    goal_line: float = 9.0         # x of the goal line
    crossbar_height: float = 2.44  # y of the crossbar's axis (a full-size goal)
    bar_radius: float = 0.06       # posts and crossbar are 12 cm thick
    depth: float = 1.2             # the back stanchion stands this far behind the goal line
    net_radius: float = 0.02       # m, the roof net's thickness as a capsule
    min_kick_distance: float = 1.0 # the rule: kick from at least this far from the mouth
    left_edge: float = -1.0        # a ball whose centre passes this is out of play
    right_edge: float = 14.0       # ... and this, behind the goal

    @property
    def mouth_top(self) -> float:
        """Height of the crossbar's underside (m): the top of the goal mouth."""
        return self.crossbar_height - self.bar_radius

    @property
    def back(self) -> float:
        """x of the back stanchion (m)."""
        return self.goal_line + self.depth

    def distance_to_mouth(self, x: float, y: float) -> float:
        """Distance (m) from the ball centre (x, y) to the goal mouth, the segment
        {x = goal_line, 0 <= y <= mouth_top}: the quantity the 1 m rule is about."""
        dx = x - self.goal_line
        dy = y - min(max(y, 0.0), self.mouth_top)
        return math.hypot(dx, dy)

    def obstacles(self) -> tuple[Segment, ...]:
        """The goal frame the ball can hit, as capsules."""
        g, h, r = self.goal_line, self.crossbar_height, self.bar_radius
        bar_c = damping_for(BAR_ZETA, BAR_K)
        net_c = damping_for(NET_ZETA, NET_K)
        return (
            Segment("crossbar", (g, h), (g, h), r, BAR_K, bar_c),
            Segment("back post", (self.back, 0.0), (self.back, h), r, BAR_K, bar_c),
            # the roof net hangs from behind the crossbar, so a hit on the bar meets the bar alone
            Segment("roof net", (g + r, h), (self.back, h), self.net_radius, NET_K, net_c),
            # the back net hangs NET_GAP in front of the post: a capsule around the post's axis
            Segment("back net", (self.back, 0.0), (self.back, h), r + NET_GAP, NET_K, net_c),
        )


FIELD = Field()
