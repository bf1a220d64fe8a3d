"""The largest stable step by theory, effect by effect: which effect a step violates.

    limits(scene, integrator) -> {"contact": h, "friction": h, "rolling_friction": h}   (s; inf: none)
    stable_step(scene, integrator) = min(limits), a float with .reason (what sets it; why 0)
    limit_modes(scene, integrator) -> every mode's limit (s), each with what sets it

"Stable" is custom_sim/chatter.py's: no blow-up, no chatter. Each limit is the step at which one
stiff mode's amplification reaches 1: the contact's spring-damper modes (per damping law), the
friction's rate mu alpha Fn / m_t and the rolling resistance's mu_roll S Fn / I (1/s), at the
largest load Fn (N) a point carries. A bare sign law's limit is 0; implicit Euler has none.
Derivations: docs/stability.md#theory.
"""
from __future__ import annotations

import functools
import math

import numpy as np

from .bodies import mass_properties
from .chatter import CHATTER_STEPS, unstable_law
from scene_types.schema import Scene

RK4_REAL_LIMIT = 2.785      # h |lambda| on the negative real axis: R(-2.785) = 1
EULER_REAL_LIMIT = 2.0      # |1 - h lambda| < 1
ANGLE_SAMPLES = 3600        # angles at which the lowest point is found (0.1 degree apart)
RHO_TOLERANCE = 1e-12       # an undamped symplectic map has rho = 1 to round-off: not growth


class StableStep(float):
    """A stable step (s), usable as the float it is, with `reason`: the mode that sets it
    (limit_modes' name), why no step is stable when it is 0, or "" when nothing limits it."""

    reason: str

    def __new__(cls, h: float, reason: str = ""):
        step = super().__new__(cls, h)
        step.reason = reason
        return step


# ---------------------------------------------------------------------------------------
# The body's contact configurations


@functools.lru_cache(maxsize=64)
def _configurations(body) -> dict:
    """Normal modes w^2 / k (1/kg) of the body on its lowest point(s), the smallest normal and
    tangential effective masses (kg) at a lowest point, how many support edges (two points
    level and lowest) it has, and the COM's least height above its lowest point (m)."""
    props = mass_properties(body)
    m, inertia, pts = props.mass, props.inertia, props.points
    inv_i = 1.0 / inertia if props.rotates else 0.0
    if props.points_rotate:
        th = np.linspace(0.0, 2.0 * np.pi, ANGLE_SAMPLES, endpoint=False)
    else:
        th = np.zeros(1)
    c, s = np.cos(th)[:, None], np.sin(th)[:, None]
    rx, ry = c * pts[:, 0] - s * pts[:, 1], s * pts[:, 0] + c * pts[:, 1]   # (angles, points)
    low = np.argmin(ry, axis=1)
    rx_low, ry_low = rx[np.arange(len(th)), low], ry[np.arange(len(th)), low]
    m_n = 1.0 / (1.0 / m + rx_low ** 2 * inv_i)
    m_t = 1.0 / (1.0 / m + ry_low ** 2 * inv_i)
    modes = list(1.0 / m_n)
    # two points level and lowest: the angle that makes their edge horizontal
    for i in range(len(pts)):
        for j in range(i + 1, len(pts)):
            d = pts[j] - pts[i]
            if not props.points_rotate or np.hypot(*d) < 1e-12:
                continue
            for a in (-math.atan2(d[1], d[0]), math.pi - math.atan2(d[1], d[0])):
                ca, sa = math.cos(a), math.sin(a)
                y = sa * pts[:, 0] + ca * pts[:, 1]
                if y[i] - y.min() > 1e-12 * (1 + abs(y.min())):
                    continue
                xs = ca * pts[[i, j], 0] - sa * pts[[i, j], 1]
                stiff = sum(np.outer((1.0, x), (1.0, x)) for x in xs)
                modes.append(float(np.max(np.linalg.eigvals(np.diag((1.0 / m, inv_i)) @ stiff).real)))
    return {"modes": modes, "max_mode": float(max(modes)), "m_n": float(m_n.min()), "m_t": float(m_t.min()),
            "support_edges": len(modes) - len(th),
            "clearance": float(np.min(-ry_low)), "mass": m, "inertia": inertia,
            "support": -ry_low, "angles": th,
            "turns_normal": bool(props.points_rotate)}


def contact_frequency(scene: Scene) -> tuple[float, float]:
    """(w rad/s, zeta) of the stiffest contact mode, or (0, 0) without contact; zeta of the
    viscous damper c (0 under hunt_crossley, whose damping grows with the depth:
    hunt_crossley_limit)."""
    if not scene.has("contact"):
        return 0.0, 0.0
    w = math.sqrt(scene.contact.k * _configurations(scene.body)["max_mode"])
    return w, scene.contact.c * w / (2.0 * scene.contact.k)


# ---------------------------------------------------------------------------------------
# Loads


def _gravity(scene: Scene) -> float:
    return scene.g if scene.has("gravity") else 0.0


def available_energy(scene: Scene) -> float:
    """E(0) above the body's lowest pose (J): kinetic plus m g (y - least COM height)."""
    cfg = _configurations(scene.body)
    i = scene.initial
    e = 0.5 * cfg["mass"] * (i.velocity[0] ** 2 + i.velocity[1] ** 2) + 0.5 * cfg["inertia"] * i.angular_velocity ** 2
    return max(0.0, e + cfg["mass"] * _gravity(scene) * (i.position[1] - cfg["clearance"]))


def reachable_clearance(scene: Scene) -> float:
    """The least COM height (m) over a lowest point at the angles the body can turn to: those
    connected to its initial angle at which resting on the lowest point, s(theta), needs no more
    energy than it has (m g s <= E). A box at rest on one face cannot reach a lower one."""
    cfg = _configurations(scene.body)
    g = _gravity(scene)
    support, angles = cfg["support"], cfg["angles"]
    if len(support) == 1 or g == 0.0:
        return float(support.min())
    i = scene.initial
    m = cfg["mass"]
    top = i.position[1] + (0.5 * m * (i.velocity[0] ** 2 + i.velocity[1] ** 2)
                           + 0.5 * cfg["inertia"] * i.angular_velocity ** 2) / (m * g)
    start = int(np.argmin(np.abs(np.angle(np.exp(1j * (angles - i.angle))))))
    # a body that starts touching, pressed in by d, stands at its support less d: the spring
    # gives back k d^2 / 2 at most, far below any barrier a step of the angle grid sees
    top = max(top, float(support[start]))
    n, best = len(support), float(support[start])
    for step in (1, -1):
        j = start
        for _ in range(n):
            j = (j + step) % n
            if support[j] > top:
                break
            best = min(best, float(support[j]))
    return best


def normal_energy(scene: Scene) -> float:
    """E_n (J): the energy that can reach a contact's normal: kinetic and potential energy above
    the lowest reachable pose, less m vx^2 / 2, and less the spin's where no lever can turn it into
    a push (docs/stability.md#friction-and-rolling-resistance)."""
    cfg = _configurations(scene.body)
    i = scene.initial
    e = 0.5 * cfg["mass"] * i.velocity[1] ** 2
    if cfg["turns_normal"]:  # the spin reaches the normal only where a lever r_x can exist
        e += 0.5 * cfg["inertia"] * i.angular_velocity ** 2
    return max(0.0, e + cfg["mass"] * _gravity(scene) * (i.position[1] - reachable_clearance(scene)))


PROFILE_STEP = 1e-4         # of the unit oscillator's time w t: the profile to 1e-4 of a period


def unit_load(x: float, v: float, damping: float, law: str) -> float:
    """The normal load of the unit oscillator (depth x, rate x' = v into the ground), unclamped:
    x + 2 zeta x' (linear, unclamped), x + 2 zeta max(0, x') (compression), or
    x (1 + beta x') (hunt_crossley); damping is zeta, or beta = dissipation v_n."""
    if law == "hunt_crossley":
        return x * (1.0 + damping * v)
    if law == "compression" and v <= 0.0:
        return x
    return x + 2.0 * damping * v


@functools.lru_cache(maxsize=256)
def load_profile(damping: float, law: str) -> np.ndarray:
    """The normal load of an impact, unit_load clamped at 0, along the unit oscillator
    x'' = -load from touchdown (x = 0, x' = 1) to leaving, sampled every PROFILE_STEP of w t.
    In units of v_n sqrt(k m_n). The unclamped law is taken as the linear one: its pull after
    the clamp's release is what no load bound needs."""
    h = PROFILE_STEP
    x, v = 0.0, 1.0
    out: list[float] = []
    while len(out) < 10 ** 6:
        f = unit_load(x, v, damping, law)
        if f <= 0.0 and out and (x <= 0.0 or law != "hunt_crossley"):
            break
        out.append(max(f, 0.0))
        a = -max(f, 0.0)
        x, v = x + h * v + 0.5 * h * h * a, v + h * a     # Taylor step, error O(h^3) per step
    return np.array(out)


def peak_factor(zeta: float, law: str = "compression") -> float:
    """f(zeta): the peak of load_profile (1 without damping)."""
    return float(load_profile(zeta, law).max())


@functools.lru_cache(maxsize=256)
def peak_depth(damping: float, law: str) -> float:
    """The deepest x of the unit impact of load_profile (in units of v_n / w)."""
    h, x, v = PROFILE_STEP, 0.0, 1.0
    while v > 0.0:
        a = -max(unit_load(x, v, damping, law), 0.0)
        x, v = x + h * v + 0.5 * h * h * a, v + h * a
    return x


def impact(scene: Scene) -> dict:
    """The hardest impact energy allows: all of E_n into one point at the smallest normal
    effective mass m_n, v_n = sqrt(2 E_n / m_n). Peak normal load Fn (N) = v_n sqrt(k m_n)
    f(zeta_n) + m g = sqrt(2 k E_n) f(zeta_n) + m g, zeta_n = c / (2 sqrt(k m_n)) (under
    hunt_crossley f is the peak of its own profile, at beta = dissipation v_n); the load
    profile (N, every PROFILE_STEP / w_n s), w_n (rad/s), v_n (m/s) and the peak depth (m,
    with the resting sag m g / k)."""
    return _impact(scene.body, normal_energy(scene), _gravity(scene), scene.contact)


@functools.lru_cache(maxsize=256)
def _impact(body, e_n: float, g: float, contact) -> dict:
    cfg = _configurations(body)
    k, m_n = contact.k, cfg["m_n"]
    w_n, v_n = math.sqrt(k / m_n), math.sqrt(2.0 * e_n / m_n)
    damping = (contact.dissipation * v_n if contact.damping_law == "hunt_crossley"
               else contact.c / (2.0 * math.sqrt(k * m_n)))
    profile = math.sqrt(2.0 * k * e_n) * load_profile(damping, contact.damping_law) + cfg["mass"] * g
    depth = peak_depth(damping, contact.damping_law) * v_n / w_n + cfg["mass"] * g / k
    return {"peak": float(profile.max()), "profile": profile, "w_n": w_n, "v_n": v_n, "depth": depth}


def peak_load(scene: Scene) -> float:
    """The largest normal load (N) a contact point carries: the impact's peak, or the weight."""
    if not scene.has("contact"):
        return 0.0
    return max(impact(scene)["peak"], _configurations(scene.body)["mass"] * _gravity(scene))


def held_impact_limit(scene: Scene, bound: float, rate_per_newton: float) -> float:
    """The largest h (s) at which the impact's load keeps h lambda > bound for fewer than
    CHATTER_STEPS steps (lambda = rate_per_newton Fn, 1/s): a shorter excursion past the limit
    makes a few flips, bounded by the impact's impulse, not chatter (chatter.py). inf when no
    step makes it last that long."""
    imp = impact(scene)
    dt_profile = PROFILE_STEP / imp["w_n"]
    loads = -np.sort(-imp["profile"])                # descending: time above F = count * dt
    with np.errstate(over="ignore"):                 # a vanishing rate: h_peak is inf, said below
        h_peak = bound / (rate_per_newton * loads[0]) if rate_per_newton * loads[0] > 0.0 else math.inf
    if not math.isfinite(h_peak):
        return math.inf                              # no load makes this rate stiff
    ratio = 1.0025
    with np.errstate(over="ignore"):                 # a huge h_peak: its ladder reaches inf, harmlessly
        for h in h_peak * ratio ** np.arange(2800):  # up to 1e3 h_peak, 0.25 % apart
            crit = bound / (rate_per_newton * h)
            above = np.searchsorted(-loads, -crit, side="right") * dt_profile
            if above >= CHATTER_STEPS * h:
                return float(h / ratio)
    return math.inf


def friction_slope(contact) -> float:
    """The friction law's slope at zero slip per unit mu Fn (s/m): alpha for tanh, ramp and
    smooth_coulomb; inf for the bare sign."""
    return math.inf if contact.friction_law == "sign" else contact.alpha


def roll_slope(contact) -> float:
    """The rolling law's slope at omega = 0 per unit mu_roll Fn (s/rad): roll_sharpness; inf for sign."""
    return math.inf if contact.roll_law == "sign" else contact.roll_sharpness


def friction_rate(scene: Scene, load: float | None = None) -> float:
    """lambda_f = mu Fn alpha / m_t (1/s) at the load Fn (N; default: the impact's peak), m_t
    the smallest tangential effective mass at a lowest point (alpha: friction_slope)."""
    if not scene.has("friction"):
        return 0.0
    load = impact(scene)["peak"] if load is None else load
    return scene.contact.mu * load * friction_slope(scene.contact) / _configurations(scene.body)["m_t"]


def rolling_rate(scene: Scene, load: float | None = None) -> float:
    """lambda_r = mu_roll S Fn / I (1/s) at the load Fn (N; default: the impact's peak), S the
    scene's roll_sharpness (roll_slope)."""
    if not scene.has("rolling_friction"):
        return 0.0
    fn = impact(scene)["peak"] if load is None else load
    return scene.contact.mu_roll * roll_slope(scene.contact) * fn / _configurations(scene.body)["inertia"]



# ---------------------------------------------------------------------------------------
# One-step maps of the damped oscillator x'' = -w^2 x - 2 zeta w x' (w = 1, step hw)


def step_matrix(method: str, hw, zeta: float, damped: bool = True) -> np.ndarray:
    """The method's one-step map of (x, v) for the unit oscillator, shape (..., 2, 2)."""
    hw = np.asarray(hw, dtype=float)[..., None, None]
    z2 = 2.0 * zeta if damped else 0.0
    jac = np.array([[0.0, 1.0], [-1.0, -z2]])
    eye = np.eye(2)
    if method == "explicit_euler":
        return eye + hw * jac
    if method == "semi_implicit_euler":  # v1 = v + h a(x, v), x1 = x + h v1
        kick = eye + hw * np.array([[0.0, 0.0], [-1.0, -z2]])
        drift = eye + hw * np.array([[0.0, 1.0], [0.0, 0.0]])
        return drift @ kick
    hj = hw * jac  # RK4: R(hJ) = I + hJ + (hJ)^2/2 + (hJ)^3/6 + (hJ)^4/24
    out, term = eye + hj, hj
    for n in (2, 3, 4):
        term = term @ hj / n
        out = out + term
    return out


def spectral_radius(a: np.ndarray) -> np.ndarray:
    return np.max(np.abs(np.linalg.eigvals(a)), axis=-1)


HW_GRID = np.geomspace(1e-4, 4.0, 20001)   # relative spacing 5e-4


def first_growth(rho: np.ndarray) -> float:
    """hw at which rho first exceeds 1 on HW_GRID (the grid point before), inf if never."""
    bad = np.flatnonzero(rho > 1.0 + RHO_TOLERANCE)
    return math.inf if len(bad) == 0 else (float(HW_GRID[bad[0] - 1]) if bad[0] else 0.0)


@functools.lru_cache(maxsize=256)
def linear_limit(method: str, zeta: float) -> float:
    """hw limit of the linear (both ways) damper: rho(A) < 1."""
    return first_growth(spectral_radius(step_matrix(method, HW_GRID, zeta)))


@functools.lru_cache(maxsize=256)
def period2_limit(method: str, zeta: float) -> float:
    """hw limit of the compression law at rest: rho(A_d), rho(A_u) <= 1, and no period-2 growth:
    M = A_u A_d has no real eigenvalue above 1 whose eigenvector e alternates (v of e and of
    A_d e of opposite sign: the damper then really acts every other step). For semi-implicit
    Euler this lands on the Jury limit with zeta / 2: the damper works half the steps."""
    a_d = step_matrix(method, HW_GRID, zeta, damped=True)
    a_u = step_matrix(method, HW_GRID, zeta, damped=False)
    lam, vec = np.linalg.eig(a_u @ a_d)
    after = np.einsum("kij,kjm->kim", a_d, vec.real)       # A_d e for each eigenvector
    alternating = vec.real[:, 1, :] * after[:, 1, :] < 0.0
    grows = (np.abs(lam.imag) < RHO_TOLERANCE) & (lam.real > 1.0 + RHO_TOLERANCE) & alternating
    rho = np.maximum(spectral_radius(a_d), spectral_radius(a_u))
    rho = np.where(grows.any(axis=1), np.inf, rho)
    return first_growth(rho)


@functools.lru_cache(maxsize=256)
def energy_balance_limit(zeta: float, motion: str) -> float:
    """Explicit Euler, compression law: hw < 4 zeta int(s v^2) / int(a^2 + v^2) along the exact
    unit motion, a "bounce" (touchdown at v = 1 to leaving) or a cycle at "rest"."""
    h = 1e-4
    x, v = 0.0, 1.0           # x into the ground, v = x'
    damped_v2 = total = 0.0
    turns = 0                 # velocity reversals so far
    for _ in range(10 ** 6):  # a cycle lasts under 2 pi / sqrt(1 - zeta^2) < 100 time units
        s = 1.0 if v > 0.0 else 0.0
        a = -x - 2.0 * zeta * v * s
        damped_v2 += s * v * v * h
        total += (a * a + v * v) * h
        x_new, v_new = x + h * v + 0.5 * h * h * a, v + h * a   # fine Taylor step
        if v > 0.0 >= v_new or v < 0.0 <= v_new:
            turns += 1
        x, v = x_new, v_new
        if motion == "bounce" and turns >= 1 and x <= 0.0:
            break
        if motion == "rest" and turns >= 2 and x >= 0.0:
            break
    return 4.0 * zeta * damped_v2 / total


@functools.lru_cache(maxsize=256)
def hunt_crossley_energy_limit(dw: float, speed: float, sag: float) -> float:
    """Explicit Euler, hunt_crossley law: hw < 2 int(P) / int(a^2 + v^2) along the exact motion
    of the mode, in time w t: x'' = a = sag - max(0, x (1 + dw x')), from touchdown (x = 0,
    x' = speed) until it leaves or has made one full cycle. x, sag (the resting depth) and
    speed (the impact speed / w) in m, dw = dissipation w (1/m). P = dw x x'^2 is the rate the
    damper takes the energy E = x'^2 + (x - sag)^2 away; explicit Euler changes E by
    -2 hw P + (hw)^2 (a^2 + x'^2) a step. inf when nothing moves (no speed, no sag)."""
    if speed <= 0.0 and sag <= 0.0:
        return math.inf
    h = 1e-4
    x, v = 0.0, speed
    dissipated = total = 0.0
    turns = 0
    for _ in range(10 ** 6):   # a cycle lasts about 2 pi
        a = sag - max(0.0, x * (1.0 + dw * v))
        dissipated += -v * (a + x - sag) * h
        total += (a * a + v * v) * h
        x_new, v_new = x + h * v + 0.5 * h * h * a, v + h * a
        if v > 0.0 >= v_new or v < 0.0 <= v_new:
            turns += 1
        x, v = x_new, v_new
        if x < 0.0 or turns >= 2:
            break
    return 2.0 * dissipated / total if dissipated > 0.0 else 0.0


def resting_depth(scene: Scene) -> float:
    """The lightest resting depth of a point (m): the weight shared by a support edge's two
    points where the body has one, else the whole weight, over k; 0 without gravity."""
    cfg = _configurations(scene.body)
    share = 2.0 if cfg["support_edges"] else 1.0
    return cfg["mass"] * _gravity(scene) / (share * scene.contact.k)


def hunt_crossley_limit(scene: Scene, method: str, w: float) -> dict[str, float]:
    """hunt_crossley's contact limits (s) for the mode w (rad/s): the linear oscillator's with
    the damper k d D linearised at the impact's peak depth and at the resting depth, and for
    explicit Euler the energy balance of the hardest impact (docs/stability.md#contact)."""
    dissipation = scene.contact.dissipation
    hit = impact(scene)
    rest = resting_depth(scene)
    depths = {"impact peak": hit["depth"]}
    if rest > 0.0:
        depths["rest"] = rest
    out = {}
    for where, d in depths.items():
        out[f"contact (hunt_crossley damper at the {where} depth)"] = linear_limit(method, d * dissipation * w / 2.0) / w
    if method == "explicit_euler":
        out["contact (hunt_crossley impact energy balance)"] = hunt_crossley_energy_limit(
            dissipation * w, hit["v_n"] / w, rest) / w
    return out


def contact_limit(scene: Scene, method: str) -> dict[str, float]:
    """The contact modes' limits (s), by mode."""
    if not scene.has("contact") or method == "implicit_euler":
        return {}
    k, c = scene.contact.k, scene.contact.c
    out = {}
    for inv_m in (_configurations(scene.body)["max_mode"],):
        w = math.sqrt(k * inv_m)
        zeta = c * w / (2.0 * k)
        if scene.contact.damping_law == "hunt_crossley":
            out.update(hunt_crossley_limit(scene, method, w))
        elif scene.contact.damping_law in ("linear", "unclamped"):
            out["contact (linear oscillator)"] = linear_limit(method, zeta) / w
        elif method == "explicit_euler":
            out["contact (bounce energy balance)"] = energy_balance_limit(zeta, "bounce") / w
            out["contact (rest energy balance)"] = energy_balance_limit(zeta, "rest") / w
        else:
            out["contact (period 2 at rest)"] = period2_limit(method, zeta) / w
    return out


def limit_modes(scene: Scene, integrator: str | None = None) -> dict[str, float]:
    """Every mode's limit (s): 'effect (what sets it)' -> h."""
    method = integrator or scene.integrator
    if method == "implicit_euler":
        return {}
    out = contact_limit(scene, method)
    bound = RK4_REAL_LIMIT if method == "rk4" else EULER_REAL_LIMIT
    cfg = _configurations(scene.body)
    rest = cfg["mass"] * _gravity(scene)
    if scene.has("friction") and scene.contact.friction_law == "sign":
        out["friction (sign law: no step is stable)"] = 0.0
    elif scene.has("friction"):
        per_newton = scene.contact.mu * friction_slope(scene.contact)
        if rest * per_newton > 0.0:
            out["friction (at rest)"] = bound * cfg["m_t"] / (per_newton * rest)
        if per_newton > 0.0:
            out[f"friction (at the impact, held {CHATTER_STEPS} steps)"] = held_impact_limit(
                scene, bound, per_newton / cfg["m_t"])
    if scene.has("rolling_friction") and scene.contact.roll_law == "sign":
        out["rolling_friction (sign law: no step is stable)"] = 0.0
    elif scene.has("rolling_friction"):
        per_newton = scene.contact.mu_roll * roll_slope(scene.contact) / cfg["inertia"]
        if rest * per_newton > 0.0:
            out["rolling_friction (at rest)"] = bound / (per_newton * rest)
        if per_newton > 0.0:
            out[f"rolling_friction (at the impact, held {CHATTER_STEPS} steps)"] = held_impact_limit(
                scene, bound, per_newton)
    return out


def limits(scene: Scene, integrator: str | None = None) -> dict[str, float]:
    """The largest stable step (s) for each effect the scene lists that limits it."""
    out: dict[str, float] = {}
    for mode, h in limit_modes(scene, integrator).items():
        if not math.isfinite(h):
            continue
        effect = mode.split(" ")[0]
        out[effect] = min(out.get(effect, math.inf), h)
    return out


def stable_step(scene: Scene, integrator: str | None = None) -> StableStep:
    """Largest stable step (s) by the theory (docs/stability.md#theory); inf when nothing limits
    it. Its .reason names the mode that sets it, or, when it is 0 under a bare sign law, why no step is."""
    modes = {m: h for m, h in limit_modes(scene, integrator).items() if math.isfinite(h)}
    if not modes:
        return StableStep(math.inf)
    mode = min(modes, key=modes.__getitem__)
    h = modes[mode]
    reason = unstable_law(scene, integrator) if h == 0.0 and "sign law" in mode else mode
    return StableStep(h, reason or mode)


def violated(scene: Scene, integrator: str | None = None) -> dict[str, float]:
    """The effects whose limit the scene's dt exceeds: effect -> limit (s)."""
    return {e: h for e, h in limits(scene, integrator).items() if scene.dt >= h}


def within_limits(scene: Scene, integrator: str | None = None) -> bool:
    """True when the scene's dt is inside the limit of every effect (metrics.json's
    dt_within_stability_limit)."""
    return not violated(scene, integrator)


def warning(scene: Scene, integrator: str | None = None) -> str | None:
    """One line for `run` and the report when dt is outside a theory limit, else None. It does
    not start with "warning:": the caller that prints it says that (run prints "warning: " +
    this line; metrics.json's `warnings` holds the bare sentence)."""
    bad = violated(scene, integrator)
    if not bad:
        return None
    method = integrator or scene.integrator
    never = unstable_law(scene, method)
    if never and stable_step(scene, method) == 0.0:
        return f"{scene.name}: {never} (see docs/contact-laws.md)"
    parts = ", ".join(f"{e} needs dt < {h:.3g} s" for e, h in sorted(bad.items(), key=lambda kv: kv[1]))
    return (f"{scene.name}: dt = {scene.dt:g} s is outside the stability limit of {method} "
            f"({parts}; see docs/stability.md): expect chatter or a blow-up")
