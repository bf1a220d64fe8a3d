"""Reference solutions: the scene's equations solved far more accurately than any fixed step.

    solve_reference(scene, t_eval) -> ReferenceSolution: states (T, 6) [x, y, theta, vx, vy,
        omega] at t_eval (s), and work (T, 3) (J) removed by damping, friction and rolling
    cached_reference(scene, t_eval, cache_dir)   the same, stored as .npz
    energy(eq, states)                           E (J), so that E(t) - E(0) + W(t) = 0

The scene's law (scene_types.laws) is written here, independently, in plain Python floats,
with the geometry of compare/oracle/rigid_body.py. The motion is cut into modes at every switch
(touch, the normal law's kinks, the ramp's kinks, the sign friction's stick or slide, the sign
of omega), each integrated by DOP853 at a tight tolerance, each switch a located event;
ReferenceFailed where the motion enters a sliding mode not modelled (two points stuck at once).
Derivation: docs/oracle-laws.md#the-reference-modes-and-switches.
"""
from __future__ import annotations

import dataclasses
import hashlib
import itertools
import json
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from scene_types import Diverged, Scene

from .rigid_body import RigidBody, rigid_body

# Tight tolerances of the adaptive solver. DOP853 holds its local error below
# atol + rtol |z| per step; 1e-11 on states of order 1 (m, m/s, rad) keeps the accumulated
# error near 1e-10 m over a few seconds, far below the smallest error the sweep measures
# (about 1e-8 m, RK4 at the smallest step), and still clear of double round-off (1e-16 |z|).
REFERENCE_RTOL = 1e-11
REFERENCE_ATOL = 1e-11

# Hysteresis of the max() kinks. Compression law: the damping branch switches when vc_y
# crosses +-KINK_BAND_VELOCITY (m/s), a force error of at most c * 1e-10 N (2e-9 N for
# c = 20 N s/m). Linear law: when k d - c vc_y crosses +-k KINK_BAND_DEPTH, at most 1e-13 k N.
# Hunt-Crossley: when 1/D - vc_y crosses +-KINK_BAND_VELOCITY, at most k d D 1e-10 N.
KINK_BAND_VELOCITY = 1e-10   # m/s
KINK_BAND_DEPTH = 1e-13      # m
# The ramp's kinks: its piece switches when alpha vc_x crosses +-(1 +- RAMP_BAND), a force error
# of at most mu Fn 1e-12: no pile-up threatens there (a body comes to rest at slip 0, far from
# the kinks), so the band need only clear the round-off of alpha vc_x at a located root (1e-16).
RAMP_BAND = 1e-12

# The same for touching and for the sign of omega, only to keep a restart that lands exactly
# on the switch (d = 0 to the last bit) from firing the reverse event at once: above the
# round-off of d and omega at a located root (1e-16), far below any effect (k * 1e-14 N).
TOUCH_BAND = 1e-14           # m
SPIN_BAND = 1e-14            # rad/s
SLIP_BAND = 1e-14            # m/s: the sign friction's slip past zero at its event

# A clamped point (Fn = 0 while d > 0) lets the solver step over a lift-off and landing unseen:
# its step is held to CLAMPED_STEP sqrt(m / k) (docs/oracle-laws.md#the-reference-modes-and-switches)
CLAMPED_STEP = 0.1
# The solver's first guess is checked only at its end, not where t_eval reads the dense output:
# each segment starts at FIRST_STEP sqrt(m / k), a tenth of the contact's time scale (same doc)
FIRST_STEP = 0.1

# More switches than this within ZENO_WINDOW seconds means a sliding mode this reference does not
# model (the state held on a switching surface, e.g. a circle whose rolling resistance holds
# omega at 0, or a stick-slip chatter): raise instead of stepping forever.
ZENO_EVENTS = 50
ZENO_WINDOW = 1e-9          # s

REFERENCE_VERSION = 4       # bump when the equations or the method change (invalidates caches)

COMPRESSION, LINEAR, UNCLAMPED, HUNT_CROSSLEY = "compression", "linear", "unclamped", "hunt_crossley"
TANH, RAMP, SMOOTH_COULOMB, SIGN = "tanh", "ramp", "smooth_coulomb", "sign"


class ReferenceFailed(Diverged):
    """The reference solver cannot follow this motion (sliding mode, solver failure); t: the
    time (s) it stopped at, when known."""

    def __init__(self, message: str, t: float | None = None):
        super().__init__(message)
        self.t = t


@dataclass(frozen=True)
class Equations:
    """The numbers of the equations of motion, read from a scene (SI units).

    points: contact points relative to the COM in the body frame, shape (n, 2);
    turning: whether they turn with theta (False for the circle and the point mass);
    rotates: whether theta is a degree of freedom (False for the point mass);
    law, friction_law: the damping and friction families (scene_types.laws);
    alpha: the friction's sharpness (s/m), inf under the sign law (its alpha -> inf limit);
    roll_sharpness: s/rad under the tanh rolling law, None under sign;
    dissipation: Hunt-Crossley's D (s/m), 0 under the other damping laws.
    """

    mass: float
    inertia: float
    points: tuple[tuple[float, float], ...]
    turning: bool
    rotates: bool
    g: float
    contact: bool
    k: float
    c: float
    law: str
    friction: bool
    mu: float
    alpha: float
    rolling: bool
    mu_roll: float
    roll_sharpness: float | None = None   # s/rad: tanh law; None: sign(omega) law
    dissipation: float = 0.0              # s/m: hunt_crossley
    friction_law: str = TANH

    @classmethod
    def from_scene(cls, scene: Scene, body: RigidBody | None = None) -> Equations:
        """The scene's equations; body: its mass properties (default: computed from the scene
        file by rigid_body, never custom_sim's)."""
        props = body or rigid_body(scene.body)
        ct = scene.contact
        return cls(
            mass=props.mass, inertia=props.inertia, points=props.points,
            turning=props.turning, rotates=props.rotates,
            g=scene.g if scene.has("gravity") else 0.0,
            contact=scene.has("contact"), k=ct.k, c=ct.c, law=ct.damping_law,
            friction=scene.has("friction"), mu=ct.mu,
            alpha=ct.alpha if ct.alpha is not None else math.inf,
            rolling=scene.has("rolling_friction"), mu_roll=ct.mu_roll,
            roll_sharpness=ct.roll_sharpness if ct.roll_law == "tanh" else None,
            dissipation=ct.dissipation, friction_law=ct.friction_law,
        )

    @property
    def sign_law(self) -> bool:
        """Rolling resistance switches with sign(omega): a switch located as an event."""
        return self.rolling and self.rotates and self.roll_sharpness is None

    @property
    def has_kink(self) -> bool:
        """The normal force has a max() kink (every damping law but unclamped, and
        Hunt-Crossley without dissipation)."""
        return self.law in (COMPRESSION, LINEAR) or (self.law == HUNT_CROSSLEY and self.dissipation > 0.0)

    @property
    def ramp(self) -> bool:
        """Friction is the ramp: kinks at alpha vc_x = +-1, located as events."""
        return self.contact and self.friction and self.friction_law == RAMP

    @property
    def coulomb(self) -> bool:
        """Friction is the bare sign: a jump at vc_x = 0, where a point may stick."""
        return self.contact and self.friction and self.friction_law == SIGN

    @property
    def slip_band(self) -> float:
        """1/alpha (m/s): the slip below which friction is regularised (0 under the sign law)."""
        return 1.0 / self.alpha

    def lever_arms(self, theta: float, which=None):
        """World-frame arms r_i = R(theta) l_i (m) of the contact points, or of those whose
        indices `which` lists (the right-hand side and the events need only a few)."""
        points = self.points if which is None else [self.points[i] for i in which]
        if self.turning:
            cs, sn = math.cos(theta), math.sin(theta)
            return [(cs * lx - sn * ly, sn * lx + cs * ly) for lx, ly in points]
        return list(points)


@dataclass(frozen=True)
class Mode:
    """Which smooth branch of the right-hand side holds.

    touching[i]: point i is below the ground (d > 0);
    active[i]:   the normal force's branch: compression: the damping term acts (vc_y < 0);
                 linear: the force pushes (k d - c vc_y > 0); hunt_crossley: 1 - D vc_y > 0;
                 unclamped: always; meaningful only while touching;
    spin:        sign of omega in the rolling resistance (-1, 0 or +1);
    slide[i]:    the friction's piece: ramp: -1, 0, +1 for alpha vc_x below -1, within, above
                 +1; sign: -1 or +1 the way the point slides, 0 stuck; unused (0 or empty)
                 for the smooth laws.
    """

    touching: tuple[bool, ...]
    active: tuple[bool, ...]
    spin: int
    slide: tuple[int, ...] = ()


def point_kinematics(eq: Equations, z, arm):
    """Depth d (m), contact velocity (vc_x, vc_y) (m/s) of the point with arm r at state z."""
    rx, ry = arm
    return -(z[1] + ry), z[3] - z[5] * ry, z[4] + z[5] * rx


def kink_value(eq: Equations, d: float, vcy: float) -> float:
    """Switching function of the max() kink: positive on the active branch.
    compression: -vc_y (m/s); linear: d - (c/k) vc_y (m), i.e. (k d - c vc_y) / k;
    hunt_crossley: 1/D - vc_y (m/s); no kink (unclamped, D = 0): 1."""
    if eq.law == COMPRESSION:
        return -vcy
    if eq.law == LINEAR:
        return d - eq.c / eq.k * vcy
    if eq.law == HUNT_CROSSLEY and eq.dissipation > 0.0:
        return 1.0 / eq.dissipation - vcy
    return 1.0


def kink_band(eq: Equations) -> float:
    return KINK_BAND_DEPTH if eq.law == LINEAR else KINK_BAND_VELOCITY


def ramp_region(eq: Equations, vcx: float, old: int | None = None) -> int:
    """The ramp's piece at slip vcx (m/s): -1, 0, +1; with hysteresis RAMP_BAND about the
    piece `old` (None: none)."""
    u = eq.alpha * vcx
    if old is None:
        return 1 if u > 1.0 else (-1 if u < -1.0 else 0)
    up = 1.0 + (RAMP_BAND if old <= 0 else -RAMP_BAND)
    down = -1.0 - (RAMP_BAND if old >= 0 else -RAMP_BAND)
    return 1 if u > up else (-1 if u < down else 0)


def _normal_law(eq: Equations, active):
    """fn(i, d, vc_y) -> Fn (N) of touching point i on its branch of the damping law."""
    k, c, diss = eq.k, eq.c, eq.dissipation
    if eq.law == COMPRESSION:
        return lambda i, d, vcy: k * d - c * vcy if active[i] else k * d
    if eq.law == LINEAR:
        return lambda i, d, vcy: k * d - c * vcy if active[i] else 0.0
    if eq.law == UNCLAMPED:
        return lambda i, d, vcy: k * d - c * vcy
    return lambda i, d, vcy: k * d * (1.0 - diss * vcy) if active[i] else 0.0


def _friction_law(eq: Equations, slide, held: int):
    """ft(i, fn, vc_x) -> Ft (N) of touching point i on its piece of the friction law (0 at the
    point `held` stuck, whose friction the constraint sets)."""
    mu, alpha = eq.mu, eq.alpha
    fr = eq.friction_law if eq.friction else None
    if fr is None:
        return lambda i, fn, vcx: 0.0
    if fr == TANH:
        return lambda i, fn, vcx: -mu * fn * math.tanh(alpha * vcx)
    if fr == RAMP:
        return lambda i, fn, vcx: -mu * fn * (alpha * vcx if slide[i] == 0 else float(slide[i]))
    if fr == SMOOTH_COULOMB:
        inv_alpha2 = 1.0 / alpha ** 2
        return lambda i, fn, vcx: -mu * fn * (vcx / math.sqrt(vcx * vcx + inv_alpha2))
    return lambda i, fn, vcx: 0.0 if i == held else -mu * fn * float(slide[i])


def holding_friction(eq: Equations, z, fx: float, tau: float, arm) -> float:
    """lam (N): the friction at the point with arm r that holds its slip's rate at zero, given
    the other forces fx (N) and torque tau (N m). The rate vc_x' = ax - alpha_theta r_y
    - omega^2 r_x (r_y' = omega r_x when the arm turns) is b + lam (1/m + r_y^2 / I)."""
    rx, ry = arm
    inv_i = 1.0 / eq.inertia if eq.rotates else 0.0
    b = fx / eq.mass - tau * inv_i * ry - (z[5] * z[5] * rx if eq.turning else 0.0)
    return -b / (1.0 / eq.mass + ry * ry * inv_i)


def mode_forces(eq: Equations, mode: Mode):
    """forces(z) -> (fx N, fy N, tau N m, p_damp W, p_fric W, p_roll W, lam N, fn N) in the
    given mode: the total force and torque, the power each dissipative effect removes, and for
    the point the sign friction holds stuck (if any) its friction lam and normal force fn."""
    k, mu_roll, gravity = eq.k, eq.mu_roll, eq.mass * eq.g
    idx = [i for i, on in enumerate(mode.touching) if on and eq.contact]
    slide = mode.slide or (0,) * len(eq.points)
    stuck = [i for i in idx if eq.coulomb and slide[i] == 0]
    if len(stuck) > 1:
        raise ReferenceFailed(two_stuck_reason(stuck))
    held = stuck[0] if stuck else -1
    normal, friction = _normal_law(eq, mode.active), _friction_law(eq, slide, held)
    spin, sharp = float(mode.spin), eq.roll_sharpness

    def forces(z):
        fx, fy, tau = 0.0, -gravity, 0.0
        p_damp = p_fric = p_roll = lam = fn_held = 0.0
        for i, arm in zip(idx, eq.lever_arms(z[2], idx)):
            d, vcx, vcy = point_kinematics(eq, z, arm)
            fn = normal(i, d, vcy)
            ft = friction(i, fn, vcx)
            fx += ft
            fy += fn
            tau += arm[0] * fn - arm[1] * ft
            if eq.rolling:
                s = spin if sharp is None else math.tanh(sharp * z[5])
                tau -= mu_roll * fn * s
                p_roll += mu_roll * fn * s * z[5]
            p_damp -= (fn - k * d) * vcy
            p_fric -= ft * vcx
            if i == held:
                held_arm, held_slip, fn_held = arm, vcx, fn
        if held >= 0:
            lam = holding_friction(eq, z, fx, tau, held_arm)
            fx += lam
            tau -= held_arm[1] * lam
            p_fric -= lam * held_slip
        return fx, fy, tau, p_damp, p_fric, p_roll, lam, fn_held

    return forces


def right_hand_side(eq: Equations, mode: Mode, work: bool = False):
    """f(t, z) = (v, a) for the given mode, as one analytic expression (no switches inside);
    work: z and f carry the three works W (damping, friction, rolling, J) too, f their rates."""
    m = eq.mass
    inv_i = 1.0 / eq.inertia if eq.rotates else 0.0
    forces = mode_forces(eq, mode)

    def f(t, z):
        fx, fy, tau, p_damp, p_fric, p_roll, _, _ = forces(z)
        if work:
            return np.array([z[3], z[4], z[5], fx / m, fy / m, tau * inv_i, p_damp, p_fric, p_roll])
        return np.array([z[3], z[4], z[5], fx / m, fy / m, tau * inv_i])

    return f


def two_stuck_reason(points) -> str:
    return (f"the sign friction would hold points {', '.join(map(str, points))} stuck at once: "
            "this reference models one stuck point at a time (with two, the friction's split "
            "between them hangs on a lever of w sin(theta), ill-posed as the body comes to rest "
            "flat), so the motion from here is not judged")


def _point_event(eq: Equations, i: int, value):
    """An event on point i's kinematics: value(d, vc_x, vc_y) at the state."""
    def event(t, z):
        return value(*point_kinematics(eq, z, eq.lever_arms(z[2], (i,))[0]))
    return event


def _terminal(event, direction: float):
    event.terminal = True
    event.direction = direction
    return event


def _normal_events(eq: Equations, mode: Mode, i: int):
    """Point i's touch event and, while it touches, its max() kink event: [(event, tag)]."""
    # touching ends when d falls below -TOUCH_BAND; not touching when it rises above it
    lift = TOUCH_BAND if mode.touching[i] else -TOUCH_BAND
    out = [(_terminal(_point_event(eq, i, lambda d, vcx, vcy: d + lift),
                      -1.0 if mode.touching[i] else 1.0), ("touch", i))]
    if mode.touching[i] and eq.has_kink:
        # active branch ends when the kink value falls below -band; inactive when it rises above +band
        shift = kink_band(eq) if mode.active[i] else -kink_band(eq)
        out.append((_terminal(_point_event(eq, i, lambda d, vcx, vcy: kink_value(eq, d, vcy) + shift),
                              -1.0 if mode.active[i] else 1.0), ("kink", i)))
    return out


def _ramp_events(eq: Equations, piece: int, i: int):
    """The ramp's kink events of a touching point i on piece -1, 0 or +1: [(event, tag)]."""
    alpha = eq.alpha
    # (edge of alpha vc_x, shift, direction, piece after); the shift puts the root RAMP_BAND past the edge
    edges = {0: [(1.0, -RAMP_BAND, 1.0, 1), (-1.0, RAMP_BAND, -1.0, -1)],
             1: [(1.0, RAMP_BAND, -1.0, 0)], -1: [(-1.0, -RAMP_BAND, 1.0, 0)]}[piece]
    return [(_terminal(_point_event(eq, i, lambda d, vcx, vcy, e=edge, s=shift: alpha * vcx - e + s),
                       direction), ("friction", i, after)) for edge, shift, direction, after in edges]


def _sign_events(eq: Equations, mode: Mode, i: int, forces, z):
    """The sign friction's event of a touching point i: its slip reaching zero (sliding: SLIP_BAND
    past zero, or past the slip at the mode's start z where that lies the other side, as a slip
    held stuck may) or the friction that holds it reaching mu Fn (stuck)."""
    s = mode.slide[i] if mode.slide else 0
    if s:
        start = point_kinematics(eq, z, eq.lever_arms(z[2], (i,))[0])[1]
        shift = SLIP_BAND + max(0.0, -s * start)
        return [(_terminal(_point_event(eq, i, lambda d, vcx, vcy: s * vcx + shift), -1.0),
                 ("friction", i, "slip"))]

    def unstick(t, z):
        *_, lam, fn = forces(z)
        return eq.mu * fn - abs(lam)
    return [(_terminal(unstick, -1.0), ("friction", i, "unstick"))]


def mode_events(eq: Equations, mode: Mode, z=None):
    """Terminal events that end the mode, each tagged with what it flips (z: the state the mode
    starts from, needed under the sign friction)."""
    pairs = []
    if not eq.contact:
        return [], []
    forces = mode_forces(eq, mode) if eq.coulomb else None
    for i in range(len(eq.points)):
        pairs += _normal_events(eq, mode, i)
        if not mode.touching[i]:
            continue
        if eq.ramp:
            pairs += _ramp_events(eq, mode.slide[i] if mode.slide else 0, i)
        if eq.coulomb:
            pairs += _sign_events(eq, mode, i, forces, z)
    if eq.sign_law:
        lift = SPIN_BAND * mode.spin

        def spin(t, z, lift=lift):
            return z[5] + lift
        pairs.append((_terminal(spin, -float(mode.spin) if mode.spin else 0.0), ("spin", -1)))
    return [p[0] for p in pairs], [p[1] for p in pairs]


def slip_rate(eq: Equations, mode: Mode, z, i: int) -> float:
    """vc_x' (m/s^2) of point i at z in the mode: ax - alpha_theta r_y (- omega^2 r_x when the
    arm turns, r_y' = omega r_x)."""
    fx, _, tau, *_ = mode_forces(eq, mode)(z)
    rx, ry = eq.lever_arms(z[2], (i,))[0]
    spin = tau / eq.inertia if eq.rotates else 0.0
    return fx / eq.mass - spin * ry - (z[5] * z[5] * rx if eq.turning else 0.0)


def _agrees(eq: Equations, mode: Mode, z, points) -> bool:
    """The sign friction's pieces of `points` agree with the forces they make at z: a stuck
    point's holding friction is within mu Fn, a sliding point's slip moves the way it slides."""
    *_, lam, fn = mode_forces(eq, mode)(z)
    for i in points:
        piece = mode.slide[i]
        if piece == 0 and abs(lam) > eq.mu * fn:
            return False
        if piece != 0 and piece * slip_rate(eq, mode, z, i) <= 0.0:
            return False
    return True


def stick_or_slide(eq: Equations, mode: Mode, z, points) -> Mode:
    """The mode whose sign-friction pieces of `points` (slips at zero, or stuck) agree with the
    forces they make (_agrees), each piece tried stuck first, then sliding either way. The
    friction's monotone law makes the slips' rates unique, so one assignment agrees; where only
    one with two points stuck could, ReferenceFailed (not modelled)."""
    for pieces in itertools.product((0, 1, -1), repeat=len(points)):
        if pieces.count(0) > 1:
            continue
        slide = list(mode.slide)
        for i, piece in zip(points, pieces):
            slide[i] = piece
        trial = dataclasses.replace(mode, slide=tuple(slide))
        if _agrees(eq, trial, z, points):
            return trial
    raise ReferenceFailed(two_stuck_reason(points))


def _sign_slides(eq: Equations, mode: Mode, z, tag, entered) -> tuple[int, ...]:
    """The sign friction's pieces after the switch `tag` at z (entered: points that just
    touched). Away from zero the law decides: the piece is the slip's sign. A point whose stuck
    friction reached mu Fn slides against it. Every point whose slip is at zero, or that is
    stuck, is decided together with the others (stick_or_slide)."""
    kind, fired = tag[0], tag[1]
    slide, open_points = list(mode.slide), []
    for i, arm in enumerate(eq.lever_arms(z[2])):
        if not mode.touching[i]:
            slide[i] = 0
            continue
        vcx = point_kinematics(eq, z, arm)[1]
        if kind == "friction" and fired == i and tag[2] == "unstick":
            lam = mode_forces(eq, mode)(z)[6]
            slide[i] = -1 if lam > 0.0 else 1
        elif abs(vcx) <= 2.0 * SLIP_BAND or (slide[i] == 0 and i not in entered):
            open_points.append(i)
        else:
            slide[i] = 1 if vcx > 0.0 else -1
    new = dataclasses.replace(mode, slide=tuple(slide))
    return stick_or_slide(eq, new, z, open_points).slide if open_points else new.slide


def initial_mode(eq: Equations, z) -> Mode:
    """The mode at a state, ties at a switch broken by where the motion goes next."""
    z = np.asarray(z, dtype=float)[:6]
    arms = eq.lever_arms(z[2])
    touching, active, slide = [], [], []
    for arm in arms:
        d, vcx, vcy = point_kinematics(eq, z, arm)
        touching.append(eq.contact and d > 0.0)
        active.append(kink_value(eq, d, vcy) > 0.0)
        slide.append(ramp_region(eq, vcx) if eq.ramp and touching[-1] else
                     (1 if vcx >= 0.0 else -1) if eq.coulomb and touching[-1] else 0)
    mode = Mode(tuple(touching), tuple(active), int(np.sign(z[5])) if eq.sign_law else 0, tuple(slide))
    # a kink value exactly 0 (a body starting at rest): the force is continuous there, so
    # the branch the state enters next is the sign of the kink value's rate of change
    acc = right_hand_side(eq, mode)(0.0, z)
    h = 1e-9
    ahead = z + h * acc
    arms_ahead = eq.lever_arms(ahead[2])
    new_active = list(active)
    for i, arm in enumerate(arms):
        if touching[i]:
            d, _, vcy = point_kinematics(eq, z, arm)
            if kink_value(eq, d, vcy) == 0.0:
                d1, _, vcy1 = point_kinematics(eq, ahead, arms_ahead[i])
                new_active[i] = kink_value(eq, d1, vcy1) > 0.0
    mode = dataclasses.replace(mode, active=tuple(new_active))
    if eq.coulomb:
        mode = dataclasses.replace(mode, slide=_sign_slides(
            eq, mode, z, ("start", -1), [i for i, on in enumerate(touching) if on]))
    if eq.sign_law and z[5] == 0.0:
        # omega = 0: spin up in the direction the other torques turn the body, if they beat
        # the rolling resistance mu_roll Fn; otherwise it stays at rest (spin 0, no torque)
        free = right_hand_side(eq, dataclasses.replace(mode, spin=0))(0.0, z)[5] * eq.inertia
        fn = sum(eq.k * point_kinematics(eq, z, a)[0] for a, on in zip(arms, mode.touching) if on)
        if abs(free) > eq.mu_roll * fn:
            mode = dataclasses.replace(mode, spin=int(np.sign(free)))
    return mode


def flip(eq: Equations, mode: Mode, tag, z) -> Mode:
    """The mode after the switch `tag` fired at state z.

    The fired switch flips. Every other switch is checked against the state too: two corners
    of a box landing flat cross the ground in the same instant, and the root finder may put
    the second crossing a hair before the restart, where its event (a sign change) would
    never fire again."""
    kind, fired = tag[0], tag[1]
    touching, active = list(mode.touching), list(mode.active)
    slide = list(mode.slide) if mode.slide else [0] * len(eq.points)
    band = kink_band(eq)
    arms = eq.lever_arms(z[2])
    entered = []
    for i, arm in enumerate(arms):
        d, vcx, vcy = point_kinematics(eq, z, arm)
        was_touching = touching[i]
        if kind == "touch" and i == fired:
            touching[i] = not touching[i]
        elif eq.contact and (d > TOUCH_BAND if not touching[i] else d < -TOUCH_BAND):
            touching[i] = not touching[i]
        if touching[i] and not was_touching:  # entering: the branch follows the approach velocity
            active[i] = kink_value(eq, max(d, 0.0), vcy) > 0.0
            entered.append(i)
        elif touching[i]:
            value = kink_value(eq, d, vcy)
            if kind == "kink" and i == fired:
                active[i] = not active[i]
            elif active[i] and value < -band:
                active[i] = False
            elif not active[i] and value > band:
                active[i] = True
        if eq.ramp and touching[i]:
            fired_here = kind == "friction" and i == fired
            slide[i] = tag[2] if fired_here else ramp_region(eq, vcx, slide[i] if was_touching else None)
    spin = mode.spin
    if kind == "spin":
        spin = -mode.spin if mode.spin else int(np.sign(z[5]))
    elif eq.sign_law and mode.spin and z[5] * mode.spin < -SPIN_BAND:
        spin = -mode.spin
    new = Mode(tuple(touching), tuple(active), spin, tuple(slide))
    if eq.coulomb:
        new = dataclasses.replace(new, slide=_sign_slides(eq, new, z, tag, entered))
    return new


def first_step(eq: Equations, t: float, t_end: float) -> float | None:
    """A segment's first step (s): FIRST_STEP sqrt(m / k) (at most what is left), None without
    contact (the solver's own guess)."""
    return min(FIRST_STEP * math.sqrt(eq.mass / eq.k), t_end - t) if eq.contact else None


def max_step(eq: Equations, mode: Mode) -> float:
    """The largest step (s) the solver may take in a mode: CLAMPED_STEP sqrt(m / k) while a
    touching point is on a clamped branch (linear, Hunt-Crossley: Fn = 0), else unbounded."""
    clamped = eq.law in (LINEAR, HUNT_CROSSLEY) and any(
        on and not act for on, act in zip(mode.touching, mode.active))
    return CLAMPED_STEP * math.sqrt(eq.mass / eq.k) if clamped and eq.contact else math.inf


def unclamped_spring(eq: Equations, before: Mode, after: Mode, z) -> float:
    """The spring energy (J) the damping work of a clamped point counted below the ground.

    A point on the clamped branch (linear or Hunt-Crossley, Fn = 0) feels no force, so its
    lift-off changes nothing in the motion, and a step that carries it out and back in (or out,
    past the next event) may leave the lift-off unlocated: the mode still says touching while
    d < 0. Its damping power (Fn - k d)(-vc_y) = k d vc_y then integrates -k d^2/2 from d = 0,
    a spring that is not there. Returned at the switch that drops it, to be added back to
    W_damping: exact, since the motion did not depend on it. A missed lift-off on a pushing
    branch is a wrong motion, and is left for the energy balance to show."""
    if eq.law not in (LINEAR, HUNT_CROSSLEY):
        return 0.0
    spring = 0.0
    for i, arm in enumerate(eq.lever_arms(z[2])):
        if before.touching[i] and not after.touching[i] and not before.active[i]:
            d = point_kinematics(eq, z, arm)[0]
            spring += 0.5 * eq.k * d * d if d < 0.0 else 0.0
    return spring


def energy(eq: Equations, states) -> np.ndarray:
    """E (T,) J at states (T, 6): kinetic (m |v|^2 + I omega^2) / 2 + m g y + the springs'
    k d^2 / 2 summed over the touching points (d > 0), with this module's geometry."""
    Z = np.atleast_2d(np.asarray(states, dtype=float))
    kinetic = 0.5 * eq.mass * (Z[:, 3] ** 2 + Z[:, 4] ** 2)
    if eq.rotates:
        kinetic = kinetic + 0.5 * eq.inertia * Z[:, 5] ** 2
    total = kinetic + eq.mass * eq.g * Z[:, 1]
    if eq.contact:
        pts = np.asarray(eq.points, dtype=float)
        if eq.turning:
            ry = np.sin(Z[:, 2:3]) * pts[None, :, 0] + np.cos(Z[:, 2:3]) * pts[None, :, 1]
        else:
            ry = np.broadcast_to(pts[None, :, 1], (Z.shape[0], pts.shape[0]))
        d = -(Z[:, 1:2] + ry)
        total = total + 0.5 * eq.k * np.where(d > 0.0, d * d, 0.0).sum(axis=1)
    return total


@dataclass(frozen=True)
class ReferenceSolution:
    """States at the requested times: t (T,) s, states (T, 6) [x, y, theta, vx, vy, omega],
    work (T, 3) J: the work removed by damping, friction and rolling resistance since t = 0."""

    t: np.ndarray
    states: np.ndarray
    work: np.ndarray
    rtol: float
    atol: float
    method: str
    nfev: int           # right-hand-side evaluations
    segments: int       # smooth pieces between switches
    switches: dict      # events by kind: touch, kink, friction, spin
    wall_time: float    # s

    @property
    def positions(self) -> np.ndarray:
        return self.states[:, :2]


def initial_state(scene: Scene) -> np.ndarray:
    i = scene.initial
    return np.array([*i.position, i.angle, *i.velocity, i.angular_velocity], dtype=float)


def solve_reference(scene: Scene, t_eval, rtol: float = REFERENCE_RTOL,
                    atol: float = REFERENCE_ATOL, method: str = "DOP853") -> ReferenceSolution:
    """Integrate the scene from t = 0 to t_eval[-1] mode by mode; states and works at t_eval
    (s, sorted). Raises ReferenceFailed (with the time it stopped at) where the motion enters a
    sliding mode this reference does not model."""
    start = time.perf_counter()
    eq = Equations.from_scene(scene)
    t_eval = np.asarray(t_eval, dtype=float)
    t_end = float(t_eval[-1])
    z = np.concatenate([initial_state(scene), np.zeros(3)])
    t = 0.0
    try:
        mode = initial_mode(eq, z)
    except ReferenceFailed as exc:
        raise ReferenceFailed(f"{scene.name}: at t = 0 s: {exc}", t=0.0) from None
    out = np.empty((len(t_eval), 9))
    done = 0
    if t_eval[0] == 0.0:
        out[0] = z
        done = 1
    from scipy.integrate import solve_ivp   # here: a run whose reference is in the cache never needs scipy

    nfev, segments = 0, 0
    switches = {"touch": 0, "kink": 0, "friction": 0, "spin": 0}
    recent: list[float] = []
    while t < t_end and done < len(t_eval):
        events, tags = mode_events(eq, mode, z)
        wanted = t_eval[done:]
        sol = solve_ivp(right_hand_side(eq, mode, work=True), (t, t_end), z, method=method, t_eval=wanted,
                        events=events or None, rtol=rtol, atol=atol, max_step=max_step(eq, mode),
                        first_step=first_step(eq, t, t_end))
        if sol.status < 0:
            raise ReferenceFailed(f"{scene.name}: {method} failed at t = {t:.6g} s: {sol.message}", t=t)
        nfev += sol.nfev
        segments += 1
        n = len(sol.t)
        if n:
            out[done:done + n] = sol.y.T
        done += n
        if sol.status == 0:  # reached t_end
            break
        fired = [j for j, te in enumerate(sol.t_events) if te.size]
        j = min(fired, key=lambda j: sol.t_events[j][0])
        t = float(sol.t_events[j][0])
        z = np.array(sol.y_events[j][0], dtype=float)
        try:
            before, mode = mode, flip(eq, mode, tags[j], z)
        except ReferenceFailed as exc:
            raise ReferenceFailed(f"{scene.name}: at t = {t:.6g} s: {exc}", t=t) from None
        z[6] += unclamped_spring(eq, before, mode, z)
        switches[tags[j][0]] += 1
        recent = [s for s in recent if t - s < ZENO_WINDOW] + [t]
        if len(recent) > ZENO_EVENTS:
            raise ReferenceFailed(
                f"{scene.name}: {len(recent)} switches within {ZENO_WINDOW:g} s near t = {t:.6g} s "
                f"(the state is held on a switching surface, a sliding mode this reference does not model)",
                t=t)
    if done != len(t_eval):
        raise ReferenceFailed(f"{scene.name}: reference stopped after {done} of {len(t_eval)} output times", t=t)
    return ReferenceSolution(t=t_eval, states=out[:, :6].copy(), work=out[:, 6:].copy(), rtol=rtol,
                             atol=atol, method=method, nfev=nfev, segments=segments, switches=switches,
                             wall_time=time.perf_counter() - start)


# ---------------------------------------------------------------------------------------
# Cache: a reference takes seconds; the sweep reuses it across runs.


def cache_key(scene: Scene, t_eval, rtol: float, atol: float, method: str) -> str:
    """Hash of everything the solution depends on (the scene without its file path)."""
    t_eval = np.asarray(t_eval, dtype=float)
    text = repr((REFERENCE_VERSION, repr(dataclasses.replace(scene, source="")),
                 rtol, atol, method, t_eval.size, float(t_eval[0]), float(t_eval[-1]),
                 hashlib.sha1(t_eval.tobytes()).hexdigest()))
    return hashlib.sha1(text.encode()).hexdigest()[:16]


def cached_reference(scene: Scene, t_eval, cache_dir: str | Path | None,
                     rtol: float = REFERENCE_RTOL, atol: float = REFERENCE_ATOL,
                     method: str = "DOP853") -> ReferenceSolution:
    """solve_reference, stored in cache_dir/reference_<name>_<key>.npz (None: no cache)."""
    if cache_dir is None:
        return solve_reference(scene, t_eval, rtol, atol, method)
    path = Path(cache_dir) / f"reference_{scene.name}_{cache_key(scene, t_eval, rtol, atol, method)}.npz"
    if path.is_file():
        with np.load(path) as data:
            info = json.loads(str(data["info"]))
            return ReferenceSolution(t=data["t"], states=data["states"], work=data["work"], **info)
    ref = solve_reference(scene, t_eval, rtol, atol, method)
    path.parent.mkdir(parents=True, exist_ok=True)
    info = {k: getattr(ref, k) for k in ("rtol", "atol", "method", "nfev", "segments", "switches",
                                         "wall_time")}
    tmp = path.with_suffix(".tmp.npz")
    np.savez(tmp, t=ref.t, states=ref.states, work=ref.work, info=json.dumps(info))
    tmp.replace(path)
    return ref
