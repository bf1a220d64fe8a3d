"""Scene files: the TOML schema of docs/scene-format.md loaded into frozen dataclasses.

Every error is a `SceneError` naming the file, the field (dotted path) and what was
expected. Unknown keys are errors, so a typo such as `mus = 0.5` never passes silently.
"""
from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .errors import SceneError
from .integrators import MUJOCO as MUJOCO_INTEGRATORS
from .integrators import OURS as INTEGRATORS
from .laws import DAMPING_LAWS, FRICTION_LAWS, LAW_PARAMETERS, ROLL_LAWS

EFFECTS = ("gravity", "contact", "friction", "rolling_friction")
SHAPES = ("point", "box", "compound", "circle")
SOLREF_MAPPINGS = ("penalty", "physical", "seed")
MAX_STEPS = 100_000_000  # a run's arrays take 48 bytes a step: 4.8 GB here, a typo beyond
CONES = ("elliptic", "pyramidal")


@dataclass(frozen=True)
class Part:
    """One box of a compound body: size (w, h) in m, centre offset in the body frame (m), mass (kg)."""

    size: tuple[float, float]
    offset: tuple[float, float]
    mass: float


@dataclass(frozen=True)
class Body:
    """The body's geometry and mass; only the fields of its shape are set (others None)."""

    shape: str
    mass: float
    size: tuple[float, float] | None = None
    radius: float | None = None
    contact_height: float | None = None
    parts: tuple[Part, ...] | None = None

    def of_shape(self, name: str) -> Any:
        """A field the body's shape sets (the schema guarantees it); an error, not None, when
        asked for another shape's field."""
        value = getattr(self, name)
        if value is None:
            raise AttributeError(f"a {self.shape} body has no {name}")
        return value


@dataclass(frozen=True)
class Contact:
    """Penalty contact and its law (scene_types.laws): k (N/m), c (N s/m), dissipation (s/m),
    mu (-), alpha (s/m), mu_roll (m), roll_sharpness (s/rad). A parameter the chosen family
    does not take holds its neutral value: c 0 under hunt_crossley, dissipation 0 otherwise,
    alpha None under the sign friction, roll_sharpness None under the sign rolling law."""

    k: float = 1e4
    c: float = 20.0
    damping_law: str = "compression"
    mu: float = 0.5
    alpha: float | None = 100.0
    mu_roll: float = 0.0
    dissipation: float = 0.0
    friction_law: str = "tanh"
    roll_law: str = "tanh"
    roll_sharpness: float | None = 100.0


@dataclass(frozen=True)
class Initial:
    """Initial state of the centre of mass: position (m), velocity (m/s), angle (rad), rate (rad/s)."""

    position: tuple[float, float]
    velocity: tuple[float, float] = (0.0, 0.0)
    angle: float = 0.0
    angular_velocity: float = 0.0


@dataclass(frozen=True)
class MujocoSettings:
    """How the MuJoCo twin is built and run; dt None means the scene's dt."""

    solref: str = "penalty"
    integrator: str = "Euler"
    cone: str = "elliptic"
    dt: float | None = None


@dataclass(frozen=True)
class Tolerance:
    """Optional override of the comparison tolerance (m, rad) with the physics behind it."""

    position: float | None = None
    angle: float | None = None
    reason: str = ""


@dataclass(frozen=True)
class Scene:
    name: str
    duration: float
    dt: float
    body: Body
    initial: Initial
    description: str = ""
    integrator: str = "semi_implicit_euler"
    effects: tuple[str, ...] = ("gravity", "contact", "friction")
    g: float = 9.81
    contact: Contact = field(default_factory=Contact)
    mujoco: MujocoSettings = field(default_factory=MujocoSettings)
    tolerance: Tolerance = field(default_factory=Tolerance)
    source: str = "<memory>"
    law_from: str = ""                  # "": the scene's own law; else where `contact` came from
    scene_contact: Contact | None = None   # the scene file's [contact] when `run --law` replaced it

    @property
    def steps(self) -> int:
        """Number of steps: duration / dt rounded to the nearest whole step."""
        return max(1, int(round(self.duration / self.dt)))

    def has(self, effect: str) -> bool:
        return effect in self.effects


# ---------------------------------------------------------------------------------------
# Loading and validation


def load_scene(path: str | Path) -> Scene:
    """Read and validate a scene file; raises SceneError naming file, field and expectation."""
    path = Path(path)
    file = str(path)
    if not path.exists():
        raise SceneError(file, "", "no such file (expected a path to a .toml scene file)")
    if path.is_dir():
        raise SceneError(file, "", "is a folder (expected a path to a .toml scene file)")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(file, "", f"cannot be read ({exc}); expected a UTF-8 TOML file") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(file, "", f"is not valid TOML ({exc})") from None
    return parse_scene(data, file=file, default_name=path.stem, check_initial_depth=True)


def parse_scene(data: dict[str, Any], file: str = "<memory>", default_name: str = "scene",
                check_initial_depth: bool = False) -> Scene:
    """Validate a scene given as a dict (the parsed TOML). check_initial_depth: also refuse an
    initial state with a contact point deeper below the ground than allowed_initial_depth (a
    scene file's start, as load_scene does; a scene built in code may start a spring pressed in
    on purpose, as the tests of one implicit Euler step and custom_sim's compile warm-up do)."""
    v = _Validator(file)
    top = v.table(data, "", {
        "name", "description", "duration", "dt", "integrator", "effects", "g",
        "body", "contact", "initial", "mujoco", "tolerance"})
    duration = v.positive(top, "duration", required=True)
    dt = v.positive(top, "dt", required=True)
    if dt > duration:
        raise SceneError(file, "dt", f"{dt} s is larger than duration {duration} s (expected dt <= duration)")
    if duration / dt > MAX_STEPS:
        raise SceneError(file, "dt", f"{dt} s gives {duration / dt:.3g} steps over {duration} s "
                                     f"(expected at most {MAX_STEPS:.0e} steps)")
    effects = v.effects(top)
    body = _parse_body(v, v.table(top.get("body"), "body", None, required=True), effects)
    contact = parse_contact(v, v.table(top.get("contact", {}), "contact", CONTACT_FIELDS))
    initial = _parse_initial(v, v.table(top.get("initial"), "initial",
                                        {"position", "velocity", "angle", "angular_velocity"}, required=True))
    if body.shape == "point" and (initial.angle != 0.0 or initial.angular_velocity != 0.0):
        raise SceneError(file, "initial.angle", "a point mass does not rotate (expected angle and angular_velocity 0)")
    if check_initial_depth and "contact" in effects:
        g_eff = v.number(top, "g", 9.81, minimum=0.0) if "gravity" in effects else 0.0
        _check_initial_depth(file, body, initial, g_eff, contact.k)
    mj = v.table(top.get("mujoco", {}), "mujoco", {"solref", "integrator", "cone", "dt"})
    mujoco = MujocoSettings(
        solref=v.choice(mj, "solref", SOLREF_MAPPINGS, "penalty", "mujoco."),
        integrator=v.choice(mj, "integrator", MUJOCO_INTEGRATORS, "Euler", "mujoco."),
        cone=v.choice(mj, "cone", CONES, "elliptic", "mujoco."),
        dt=v.positive(mj, "dt", prefix="mujoco."),
    )
    if mujoco.dt is not None and mujoco.dt > duration:
        raise SceneError(file, "mujoco.dt", f"{mujoco.dt} s is larger than duration {duration} s (expected dt <= duration)")
    tol = v.table(top.get("tolerance", {}), "tolerance", {"position", "angle", "reason"})
    tolerance = Tolerance(
        position=v.positive(tol, "position", prefix="tolerance."),
        angle=v.positive(tol, "angle", prefix="tolerance."),
        reason=v.string(tol, "reason", "", "tolerance."),
    )
    return Scene(
        name=v.string(top, "name", default_name),
        description=v.string(top, "description", ""),
        duration=duration,
        dt=dt,
        integrator=v.choice(top, "integrator", INTEGRATORS, "semi_implicit_euler"),
        effects=effects,
        g=v.number(top, "g", 9.81, minimum=0.0),
        body=body,
        contact=contact,
        initial=initial,
        mujoco=mujoco,
        tolerance=tolerance,
        source=file,
    )


# How far below the ground a scene may start a contact point. A body released from rest with a
# point pressed in by d, that point alone carrying it on its spring (the most any point of a
# resting body carries), oscillates between d and 2 m g / k - d: a start up to twice the
# resting compression m g / k keeps the point on the ground, like a body set down; deeper, the
# spring throws the body up (from 2 m g / k - d above rest), a start no resting body has, and
# the force k d it starts with is what a landing gives, not a resting load: a body placed
# partly through the floor is reported as chatter or a blow-up, not as the mistake it is.
# Without gravity nothing rests on the spring: only the round-off of placing a body on the
# ground (a millionth of its size, the farthest contact point from its centre of mass: a
# position written with six significant digits, or a turned box's cos(pi/2) = 6e-17) passes.
# Every built-in and stress scene starts at most at 1.01 m g / k (resting_60s). Checked for
# scene files (load_scene); a scene built in code (parse_scene) may ask for it, and the tests
# that start a spring pressed in on purpose (one implicit Euler step on a spring) do not.
INITIAL_DEPTH_REST_FACTOR = 2.0
INITIAL_DEPTH_PLACEMENT = 1e-6


def allowed_initial_depth(body: Body, g: float, k: float) -> float:
    """The deepest a contact point may start below the ground (m): the larger of
    INITIAL_DEPTH_REST_FACTOR m g / k (g: 0 without gravity) and INITIAL_DEPTH_PLACEMENT times
    the body's size."""
    size = _body_size(_contact_points(body)[0])
    return max(INITIAL_DEPTH_REST_FACTOR * body.mass * g / k, INITIAL_DEPTH_PLACEMENT * size)


def _body_size(points) -> float:
    """The farthest contact point from the centre of mass (m); 0 for a point touching at y."""
    return max((math.hypot(px, py) for px, py in points), default=0.0)


def _contact_points(body: Body) -> tuple[list[tuple[float, float]], bool]:
    """The contact points relative to the centre of mass (m) and whether they turn with the
    body: the placement check's own reading of the seed's geometry (a box's and each part's
    corners, the point at (0, -contact_height), the disk's point below its centre)."""
    if body.shape == "point":
        return [(0.0, -body.of_shape("contact_height"))], False
    if body.shape == "circle":
        return [(0.0, -body.of_shape("radius"))], False
    boxes = [((0.0, 0.0), body.of_shape("size"), body.mass)] if body.shape == "box" else \
        [(p.offset, p.size, p.mass) for p in body.of_shape("parts")]
    total = sum(m for _, _, m in boxes)
    cx = sum(o[0] * m for o, _, m in boxes) / total
    cy = sum(o[1] * m for o, _, m in boxes) / total
    return [(o[0] - cx + sx * w / 2, o[1] - cy + sy * h / 2)
            for o, (w, h), _ in boxes for sx, sy in ((-1, -1), (1, -1), (1, 1), (-1, 1))], True


def _check_initial_depth(file: str, body: Body, initial: Initial, g: float, k: float) -> None:
    """SceneError when the initial state puts a contact point deeper below the ground (y = 0)
    than allowed_initial_depth: the field is initial.angle when the angle alone does it (the
    same position at angle 0 would be allowed), else initial.position."""
    points, points_rotate = _contact_points(body)
    allowed = allowed_initial_depth(body, g, k)
    x, y = initial.position

    def lowest(angle: float) -> tuple[int, float, float]:
        c, s = (math.cos(angle), math.sin(angle)) if points_rotate else (1.0, 0.0)
        world = [(x + c * lx - s * ly, y + s * lx + c * ly) for lx, ly in points]
        i = min(range(len(world)), key=lambda j: world[j][1])
        return i, world[i][0], world[i][1]

    i, px, py = lowest(initial.angle)
    depth = -py
    if depth <= allowed:
        return
    field = "initial.position"
    if initial.angle != 0.0 and -lowest(0.0)[2] <= allowed and points_rotate:
        field = "initial.angle"
    lx, ly = points[i]
    rest = body.mass * g / k
    turned = f" turned by initial.angle = {initial.angle:g} rad" if initial.angle != 0.0 else ""
    raise SceneError(file, field,
                     f"puts contact point {i} (body frame ({lx:.4g}, {ly:.4g}) m{turned}) at y = {py:.4g} m, "
                     f"{depth:.3g} m below the ground (expected a start above the ground or pressed in by at "
                     f"most {allowed:.3g} m: the larger of {INITIAL_DEPTH_REST_FACTOR:g} x the resting "
                     f"compression m g / k = {rest:.3g} m (a body set down at rest stays on the ground) and "
                     f"{INITIAL_DEPTH_PLACEMENT:g} of the body's size {_body_size(points):.3g} m (round-off); "
                     f"raise initial.position's y by at least {depth - allowed:.3g} m)")


_SHAPE_FIELDS = {
    "point": {"shape", "mass", "contact_height"},
    "box": {"shape", "mass", "size"},
    "compound": {"shape", "mass", "parts"},
    "circle": {"shape", "mass", "radius"},
}


def _parse_body(v: _Validator, b: dict, effects: tuple[str, ...]) -> Body:
    shape = v.choice(b, "shape", SHAPES, None, "body.")
    for key in b:
        if key not in _SHAPE_FIELDS[shape]:
            allowed = ", ".join(sorted(_SHAPE_FIELDS[shape]))
            raise SceneError(v.file, f"body.{key}", f"does not belong to shape '{shape}' (expected one of: {allowed})")
    if "rolling_friction" in effects and shape != "circle":
        raise SceneError(v.file, "effects", f"rolling_friction acts on a rolling circle (body.shape is '{shape}')")
    if shape == "compound":
        raw = b.get("parts")
        if not isinstance(raw, list) or not raw:
            raise SceneError(v.file, "body.parts", "expected a non-empty list of {size, offset, mass} tables")
        parts = []
        for i, p in enumerate(raw):
            where = f"body.parts[{i}]."
            p = v.table(p, where[:-1], {"size", "offset", "mass"}, required=True)
            parts.append(Part(size=v.pair(p, "size", where, positive=True, required=True),
                              offset=v.pair(p, "offset", where, required=True),
                              mass=v.positive(p, "mass", prefix=where, required=True)))
        total = sum(p.mass for p in parts)
        mass = v.positive(b, "mass", prefix="body.")
        if mass is not None and not math.isclose(mass, total, rel_tol=1e-9):
            raise SceneError(v.file, "body.mass",
                             f"{mass} kg differs from the sum of the parts {total} kg (expected equal, or omit it)")
        return Body(shape=shape, mass=total, parts=tuple(parts))
    mass = v.positive(b, "mass", prefix="body.", required=True)
    if shape == "box":
        return Body(shape=shape, mass=mass, size=v.pair(b, "size", "body.", positive=True, required=True))
    if shape == "circle":
        return Body(shape=shape, mass=mass, radius=v.positive(b, "radius", prefix="body.", required=True))
    return Body(shape=shape, mass=mass, contact_height=v.number(b, "contact_height", 0.0, "body.", minimum=0.0))


CONTACT_FIELDS = {"k", "c", "damping_law", "dissipation", "mu", "alpha", "friction_law",
                  "mu_roll", "roll_law", "roll_sharpness"}


def parse_contact(v: _Validator, c: dict) -> Contact:
    """The [contact] table: each law named from its family, each parameter only where the
    family takes it (a `dissipation` beside a compression law, an `alpha` beside the sign
    friction are errors), and hunt_crossley's `dissipation` required."""
    d = Contact()
    laws = {"damping_law": v.choice(c, "damping_law", DAMPING_LAWS, d.damping_law, "contact."),
            "friction_law": v.choice(c, "friction_law", FRICTION_LAWS, d.friction_law, "contact."),
            "roll_law": v.choice(c, "roll_law", ROLL_LAWS, d.roll_law, "contact.")}
    taken = {param for law, name in laws.items() for param in LAW_PARAMETERS[law][name]}
    for law, name in laws.items():
        for param in sorted({p for params in LAW_PARAMETERS[law].values() for p in params}):
            if param in c and param not in taken:
                users = sorted(family for family, params in LAW_PARAMETERS[law].items() if param in params)
                raise SceneError(v.file, f"contact.{param}",
                                 f"is not a parameter of {law} = '{name}' (expected it only with "
                                 f"{law} = {' | '.join(users)}; remove it or change the law)")
    if laws["damping_law"] == "hunt_crossley" and "dissipation" not in c:
        raise SceneError(v.file, "contact.dissipation",
                         "is required by damping_law = 'hunt_crossley' (expected the dissipation in s/m, "
                         "a number >= 0: Fn = max(0, k d (1 - dissipation v_n)))")
    return Contact(
        k=v.positive(c, "k", d.k, "contact."),
        c=v.number(c, "c", d.c, "contact.", minimum=0.0) if "c" in taken else 0.0,
        dissipation=v.number(c, "dissipation", 0.0, "contact.", minimum=0.0) if "dissipation" in taken else 0.0,
        mu=v.number(c, "mu", d.mu, "contact.", minimum=0.0),
        alpha=v.positive(c, "alpha", d.alpha, "contact.") if "alpha" in taken else None,
        mu_roll=v.number(c, "mu_roll", d.mu_roll, "contact.", minimum=0.0),
        roll_sharpness=(v.positive(c, "roll_sharpness", d.roll_sharpness, "contact.")
                        if "roll_sharpness" in taken else None),
        **laws,
    )


def _parse_initial(v: _Validator, i: dict) -> Initial:
    return Initial(
        position=v.pair(i, "position", "initial.", required=True),
        velocity=v.pair(i, "velocity", "initial.", default=(0.0, 0.0)),
        angle=v.number(i, "angle", 0.0, "initial."),
        angular_velocity=v.number(i, "angular_velocity", 0.0, "initial."),
    )


class _Validator:
    """Typed field readers that raise SceneError with the file and dotted field name."""

    def __init__(self, file: str):
        self.file = file

    def fail(self, name: str, message: str):
        raise SceneError(self.file, name, message)

    def table(self, value, name: str, allowed: set[str] | None, required: bool = False) -> dict:
        if value is None:
            if required:
                self.fail(name, "missing (expected a table)")
            return {}
        if not isinstance(value, dict):
            self.fail(name or "<top>", f"expected a table, got {type(value).__name__}")
        if allowed is not None:
            for key in value:
                if key not in allowed:
                    full = f"{name}.{key}" if name else key
                    self.fail(full, f"unknown field (expected one of: {', '.join(sorted(allowed))})")
        return value

    def number(self, t: dict, key: str, default=None, prefix: str = "", minimum: float | None = None,
               required: bool = False):
        name = prefix + key
        if key not in t:
            if required:
                self.fail(name, "missing (expected a number)")
            return default
        x = t[key]
        if isinstance(x, bool) or not isinstance(x, (int, float)):
            self.fail(name, f"expected a number, got {type(x).__name__} {x!r}")
        x = float(x)
        if not math.isfinite(x):
            self.fail(name, f"expected a finite number, got {x}")
        if minimum is not None and x < minimum:
            self.fail(name, f"expected a number >= {minimum}, got {x}")
        return x

    def positive(self, t: dict, key: str, default=None, prefix: str = "", required: bool = False):
        x = self.number(t, key, default, prefix, required=required)
        if x is not None and x <= 0.0:
            self.fail(prefix + key, f"expected a number > 0, got {x}")
        return x

    def pair(self, t: dict, key: str, prefix: str = "", default=None, positive: bool = False,
             required: bool = False) -> tuple[float, float]:
        name = prefix + key
        if key not in t:
            if required:
                self.fail(name, "missing (expected a list of two numbers)")
            return default
        x = t[key]
        if not isinstance(x, list) or len(x) != 2:
            self.fail(name, f"expected a list of two numbers, got {x!r}")
        out = tuple(self.number({key: e}, key, prefix=prefix) for e in x)
        if positive and min(out) <= 0.0:
            self.fail(name, f"expected two numbers > 0, got {list(out)}")
        return out

    def string(self, t: dict, key: str, default: str, prefix: str = "") -> str:
        if key not in t:
            return default
        x = t[key]
        if not isinstance(x, str):
            self.fail(prefix + key, f"expected a string, got {type(x).__name__} {x!r}")
        return x

    def choice(self, t: dict, key: str, options: tuple[str, ...], default, prefix: str = "") -> str:
        name = prefix + key
        if key not in t:
            if default is None:
                self.fail(name, f"missing (expected one of: {', '.join(options)})")
            return default
        x = t[key]
        if x not in options:
            self.fail(name, f"unknown value {x!r} (expected one of: {', '.join(options)})")
        return x

    def effects(self, t: dict) -> tuple[str, ...]:
        if "effects" not in t:
            return ("gravity", "contact", "friction")
        x = t["effects"]
        if not isinstance(x, list) or not all(isinstance(e, str) for e in x):
            self.fail("effects", f"expected a list of strings, got {x!r}")
        for e in x:
            if e not in EFFECTS:
                self.fail("effects", f"unknown effect {e!r} (expected a subset of: {', '.join(EFFECTS)})")
        if len(set(x)) != len(x):
            self.fail("effects", f"lists an effect twice: {x}")
        for needs in ("friction", "rolling_friction"):
            if needs in x and "contact" not in x:
                self.fail("effects", f"{needs} acts through contact (expected 'contact' in the list too)")
        return tuple(e for e in EFFECTS if e in x)  # canonical order
