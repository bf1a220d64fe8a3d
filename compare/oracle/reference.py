"""Reference solutions: custom_sim's equations solved far more accurately than any fixed step.

The equations are the scene's law (scene_types.laws), written here, independently, in plain
Python floats; the geometry too is computed here (compare/oracle/rigid_body.py: area moments
by Green's theorem), so that nothing checked against the reference is shared with custom_sim:

    m v' = sum_i (Ft_i, Fn_i) + (0, -m g)          I omega' = sum_i (r_i x F_i) - mu_roll Fn s(omega)
    d_i  = -(y + r_iy)  touching while d_i > 0      vc_i = v + omega x r_i
    Fn_i = k d_i + c max(0, -vc_iy)   (compression)  or  max(0, k d_i - c vc_iy)   (linear)
    Ft_i = -mu Fn_i tanh(alpha vc_ix)
    s(omega) = tanh(roll_sharpness omega) under the scene's roll_law "tanh", sign(omega) under
               "sign" (the seed's Algorithm 4)

The right-hand side is smooth except where a switch flips: a point touching or not (the force
jumps by c |vc_y| under the compression law), the kink of max() (compression: vc_y = 0; linear:
k d = c vc_y), and sign(omega) of the rolling resistance. An adaptive solver stepping across
such a point loses its order and its error estimate. So the motion is cut into *modes* (which
points touch, which branch of max() each is on, the sign of omega under the sign law); inside a mode the
right-hand side is one analytic expression, integrated by scipy's DOP853 (8th order, dense
output) at a tight tolerance; each switch is located as a terminal event by root-finding on
the dense output, and the integration restarts from there in the new mode.

The kinks of max() leave the force continuous. A body settling under the compression law has
vc_y -> 0 with ever smaller oscillations, which would make events pile up near round-off, so
their switching functions have a small hysteresis band (KINK_BAND): the force error it allows,
c * KINK_BAND_VELOCITY, is far below anything the sweep measures (see the constants).
"""
from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

from scene_types import Scene

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
KINK_BAND_VELOCITY = 1e-10   # m/s
KINK_BAND_DEPTH = 1e-13      # m

# The same for touching and for the sign of omega, only to keep a restart that lands exactly
# on the switch (d = 0 to the last bit) from firing the reverse event at once: above the
# round-off of d and omega at a located root (1e-16), far below any effect (k * 1e-14 N).
TOUCH_BAND = 1e-14           # m
SPIN_BAND = 1e-14            # rad/s

# More switches than this within ZENO_WINDOW seconds means a sliding mode (the state held on a
# switching surface, e.g. a circle whose rolling resistance holds omega at 0), which this
# reference does not model: raise instead of stepping forever.
ZENO_EVENTS = 50
ZENO_WINDOW = 1e-9          # s

REFERENCE_VERSION = 3       # bump when the equations or the method change (invalidates caches)

COMPRESSION, LINEAR = "compression", "linear"


class ReferenceError(RuntimeError):
    """The reference solver cannot follow this motion (sliding mode, solver failure)."""


@dataclass(frozen=True)
class Equations:
    """The numbers of the equations of motion, read from a scene (SI units).

    points: contact points relative to the COM in the body frame, shape (n, 2);
    turning: whether they turn with theta (False for the circle and the point mass);
    rotates: whether theta is a degree of freedom (False for the point mass).
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
            friction=scene.has("friction"), mu=ct.mu, alpha=ct.alpha,
            rolling=scene.has("rolling_friction"), mu_roll=ct.mu_roll,
            roll_sharpness=ct.roll_sharpness if ct.roll_law == "tanh" else None,
        )

    @property
    def sign_law(self) -> bool:
        """Rolling resistance switches with sign(omega): a switch located as an event."""
        return self.rolling and self.rotates and self.roll_sharpness is None

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
    active[i]:   compression law: the damping term acts (vc_y < 0); linear law: the force
                 pushes (k d - c vc_y > 0); meaningful only while touching;
    spin:        sign of omega in the rolling resistance (-1, 0 or +1).
    """

    touching: tuple[bool, ...]
    active: tuple[bool, ...]
    spin: int


def point_kinematics(eq: Equations, z, arm):
    """Depth d (m), contact velocity (vc_x, vc_y) (m/s) of the point with arm r at state z."""
    rx, ry = arm
    return -(z[1] + ry), z[3] - z[5] * ry, z[4] + z[5] * rx


def kink_value(eq: Equations, d: float, vcy: float) -> float:
    """Switching function of the max() kink: positive on the active branch.
    compression: -vc_y (m/s); linear: d - (c/k) vc_y (m), i.e. (k d - c vc_y) / k."""
    if eq.law == COMPRESSION:
        return -vcy
    return d - eq.c / eq.k * vcy


def kink_band(eq: Equations) -> float:
    return KINK_BAND_VELOCITY if eq.law == COMPRESSION else KINK_BAND_DEPTH


def right_hand_side(eq: Equations, mode: Mode):
    """f(t, z) = (v, a) for the given mode, as one analytic expression (no switches inside)."""
    m, inertia = eq.mass, eq.inertia
    inv_i = 1.0 / inertia if eq.rotates else 0.0
    k, c, mu, alpha, mu_roll = eq.k, eq.c, eq.mu, eq.alpha, eq.mu_roll
    compression = eq.law == COMPRESSION
    idx = [i for i, on in enumerate(mode.touching) if on and eq.contact]
    active = mode.active
    spin = float(mode.spin)
    sharp = eq.roll_sharpness

    def f(t, z):
        fx, fy, tau = 0.0, -m * eq.g, 0.0
        if idx:
            for i, arm in zip(idx, eq.lever_arms(z[2], idx)):
                d, vcx, vcy = point_kinematics(eq, z, arm)
                if compression:
                    fn = k * d - c * vcy if active[i] else k * d
                else:
                    fn = k * d - c * vcy if active[i] else 0.0
                ft = -mu * fn * math.tanh(alpha * vcx) if eq.friction else 0.0
                rx, ry = arm
                fx += ft
                fy += fn
                tau += rx * fn - ry * ft
                if eq.rolling:
                    tau -= mu_roll * fn * (spin if sharp is None else math.tanh(sharp * z[5]))
        return np.array([z[3], z[4], z[5], fx / m, fy / m, tau * inv_i])

    return f


def mode_events(eq: Equations, mode: Mode):
    """Terminal events that end the mode, each tagged with what it flips."""
    events, tags = [], []
    if not eq.contact:
        return events, tags
    band = kink_band(eq)
    for i in range(len(eq.points)):
        # touching ends when d falls below -TOUCH_BAND; not touching when it rises above it
        lift = TOUCH_BAND if mode.touching[i] else -TOUCH_BAND

        def depth(t, z, i=i, lift=lift):
            return point_kinematics(eq, z, eq.lever_arms(z[2], (i,))[0])[0] + lift
        depth.terminal = True
        depth.direction = -1.0 if mode.touching[i] else 1.0
        events.append(depth)
        tags.append(("touch", i))
        if not mode.touching[i]:
            continue
        # active branch ends when the kink value falls below -band; inactive when it rises above +band
        shift = band if mode.active[i] else -band

        def kink(t, z, i=i, shift=shift):
            d, _, vcy = point_kinematics(eq, z, eq.lever_arms(z[2], (i,))[0])
            return kink_value(eq, d, vcy) + shift
        kink.terminal = True
        kink.direction = -1.0 if mode.active[i] else 1.0
        events.append(kink)
        tags.append(("kink", i))
    if eq.sign_law:
        lift = SPIN_BAND * mode.spin

        def spin(t, z, lift=lift):
            return z[5] + lift
        spin.terminal = True
        spin.direction = -float(mode.spin) if mode.spin else 0.0
        events.append(spin)
        tags.append(("spin", -1))
    return events, tags


def initial_mode(eq: Equations, z) -> Mode:
    """The mode at a state, ties at a switch broken by where the motion goes next."""
    z = np.asarray(z, dtype=float)
    arms = eq.lever_arms(z[2])
    touching, active = [], []
    for arm in arms:
        d, _, vcy = point_kinematics(eq, z, arm)
        touching.append(eq.contact and d > 0.0)
        active.append(kink_value(eq, d, vcy) > 0.0)
    mode = Mode(tuple(touching), tuple(active), int(np.sign(z[5])) if eq.sign_law else 0)
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
    kind, fired = tag
    touching, active = list(mode.touching), list(mode.active)
    band = kink_band(eq)
    arms = eq.lever_arms(z[2])
    for i, arm in enumerate(arms):
        d, _, vcy = point_kinematics(eq, z, arm)
        was_touching = touching[i]
        if kind == "touch" and i == fired:
            touching[i] = not touching[i]
        elif eq.contact and (d > TOUCH_BAND if not touching[i] else d < -TOUCH_BAND):
            touching[i] = not touching[i]
        if touching[i] and not was_touching:  # entering: the branch follows the approach velocity
            active[i] = kink_value(eq, max(d, 0.0), vcy) > 0.0
        elif touching[i]:
            value = kink_value(eq, d, vcy)
            if kind == "kink" and i == fired:
                active[i] = not active[i]
            elif active[i] and value < -band:
                active[i] = False
            elif not active[i] and value > band:
                active[i] = True
    spin = mode.spin
    if kind == "spin":
        spin = -mode.spin if mode.spin else int(np.sign(z[5]))
    elif eq.sign_law and mode.spin and z[5] * mode.spin < -SPIN_BAND:
        spin = -mode.spin
    return Mode(tuple(touching), tuple(active), spin)


@dataclass(frozen=True)
class ReferenceSolution:
    """States at the requested times: t (T,) s, states (T, 6) [x, y, theta, vx, vy, omega]."""

    t: np.ndarray
    states: np.ndarray
    rtol: float
    atol: float
    method: str
    nfev: int           # right-hand-side evaluations
    segments: int       # smooth pieces between switches
    switches: dict      # events by kind: touch, kink, spin
    wall_time: float    # s

    @property
    def positions(self) -> np.ndarray:
        return self.states[:, :2]


def initial_state(scene: Scene) -> np.ndarray:
    i = scene.initial
    return np.array([*i.position, i.angle, *i.velocity, i.angular_velocity], dtype=float)


def solve_reference(scene: Scene, t_eval, rtol: float = REFERENCE_RTOL,
                    atol: float = REFERENCE_ATOL, method: str = "DOP853") -> ReferenceSolution:
    """Integrate the scene from t = 0 to t_eval[-1] mode by mode; states at t_eval (s, sorted)."""
    start = time.perf_counter()
    eq = Equations.from_scene(scene)
    t_eval = np.asarray(t_eval, dtype=float)
    t_end = float(t_eval[-1])
    z = initial_state(scene)
    mode = initial_mode(eq, z)
    t = 0.0
    out = np.empty((len(t_eval), 6))
    done = 0
    if t_eval[0] == 0.0:
        out[0] = z
        done = 1
    nfev, segments = 0, 0
    switches = {"touch": 0, "kink": 0, "spin": 0}
    recent: list[float] = []
    while t < t_end and done < len(t_eval):
        events, tags = mode_events(eq, mode)
        wanted = t_eval[done:]
        sol = solve_ivp(right_hand_side(eq, mode), (t, t_end), z, method=method, t_eval=wanted,
                        events=events or None, rtol=rtol, atol=atol)
        if sol.status < 0:
            raise ReferenceError(f"{scene.name}: {method} failed at t = {t:.6g} s: {sol.message}")
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
        mode = flip(eq, mode, tags[j], z)
        switches[tags[j][0]] += 1
        recent = [s for s in recent if t - s < ZENO_WINDOW] + [t]
        if len(recent) > ZENO_EVENTS:
            raise ReferenceError(
                f"{scene.name}: {len(recent)} switches within {ZENO_WINDOW:g} s near t = {t:.6g} s "
                f"(the state is held on a switching surface, a sliding mode this reference does not model)")
    if done != len(t_eval):
        raise ReferenceError(f"{scene.name}: reference stopped after {done} of {len(t_eval)} output times")
    return ReferenceSolution(t=t_eval, states=out, rtol=rtol, atol=atol, method=method, nfev=nfev,
                             segments=segments, switches=switches,
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
            return ReferenceSolution(t=data["t"], states=data["states"], **info)
    ref = solve_reference(scene, t_eval, rtol, atol, method)
    path.parent.mkdir(parents=True, exist_ok=True)
    info = {k: getattr(ref, k) for k in ("rtol", "atol", "method", "nfev", "segments", "switches",
                                         "wall_time")}
    tmp = path.with_suffix(".tmp.npz")
    np.savez(tmp, t=ref.t, states=ref.states, info=json.dumps(info))
    tmp.replace(path)
    return ref
