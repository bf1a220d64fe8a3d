"""solref and solimp from a spring-damper (mass kg, k N/m, c N s/m), for each mapping, each with
its error measured on a drop test run there and then.

    conversion_table(mass, k, c, shape="point", ...) -> list[Conversion]

The drop test is the body dropped flat from DROP_HEIGHT with gravity and normal contact only
(no friction: the conversion is of the normal force), under the linear damping law, which is
MuJoCo's own, so the error measures the mapping and nothing else. A stored calibration
(calibration.json) adds a row: its solref/solimp gains and values on top of its base mapping
(its friction settings do not act here).
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

from custom_sim import parse_scene, simulate
from mujoco_models import MAPPINGS

from scene_types import BadInput
from .parameters import PARAMETERS
from .settings import calibrated
from .targets import Batch, errors, prepare

DROP_HEIGHT = 0.3        # m, the COM's start above the ground
DROP_DURATION = 1.0      # s: the impact, the bounces and the settling for k >= 1e3 N/m
DROP_DT = 1e-4           # s
POINT_CONTACT_HEIGHT = 0.05   # m, as the built-in point_drop
SHAPES = ("point", "box", "circle")


@dataclass(frozen=True)
class Conversion:
    mapping: str
    solref: tuple[float, float]
    solimp: tuple[float, ...]
    position_error_max: float | None   # m, MuJoCo against custom_sim on the drop test
    angle_error_max: float | None      # rad
    note: str = ""

    def mjcf(self) -> str:
        return (f'solref="{self.solref[0]:.6g} {self.solref[1]:.6g}" '
                f'solimp="{" ".join(f"{v:.6g}" for v in self.solimp)}"')


def _positive(name: str, value: float, allow_zero: bool = False) -> float:
    if not (math.isfinite(value) and (value >= 0.0 if allow_zero else value > 0.0)):
        raise BadInput(f"{name}: {value} (expected a number {'>= 0' if allow_zero else '> 0'})")
    return float(value)


def drop_scene(mass: float, k: float, c: float, shape: str = "point", size=(0.2, 0.1),
               radius: float = 0.1, dt: float = DROP_DT, duration: float = DROP_DURATION):
    """The drop test's scene for the spring-damper (validated like a scene file)."""
    mass, k = _positive("--mass", mass), _positive("--k", k)
    c = _positive("--c", c, allow_zero=True)
    if shape not in SHAPES:
        raise BadInput(f"--shape: {shape!r} (expected one of: {', '.join(SHAPES)})")
    body = {"shape": shape, "mass": mass}
    if shape == "point":
        body["contact_height"] = POINT_CONTACT_HEIGHT
    elif shape == "box":
        body["size"] = [_positive("--size", size[0]), _positive("--size", size[1])]
    else:
        body["radius"] = _positive("--radius", radius)
    return parse_scene({
        "name": f"drop_{shape}", "duration": duration, "dt": dt, "integrator": "semi_implicit_euler",
        "effects": ["gravity", "contact"], "body": body,
        "contact": {"k": k, "c": c, "damping_law": "linear"},
        "initial": {"position": [0.0, DROP_HEIGHT]},
    }, file="<solref drop test>")


def load_calibration(path: Path) -> dict | None:
    """A stored calibration.json (None if the file is absent; BadInput if unreadable)."""
    if not path.is_file():
        return None
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        data["parameters"], data["base_mapping"]
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise BadInput(f"{path}: not a calibration.json written by `calibrate` ({exc})") from exc
    return data


def conversion_table(mass: float, k: float, c: float, shape: str = "point", size=(0.2, 0.1),
                     radius: float = 0.1, calibration: Path | None = None,
                     nthread: int = 1) -> list[Conversion]:
    """One Conversion per mapping (seed, physical, penalty), plus "calibrated" when a stored
    calibration is given and present."""
    scene = drop_scene(mass, k, c, shape, size, radius)
    reference = simulate(scene)
    stored = load_calibration(Path(calibration)) if calibration else None
    rows = []
    with Batch(nthread) as batch:
        for mapping in MAPPINGS[::-1]:
            target = prepare(scene, mapping, reference)
            s = target.base.settings
            e = errors(target, batch.paths(target, [s])[0])
            rows.append(Conversion(mapping, s.solref, s.solimp, e["position_error_max"], e["angle_error_max"]))
        if stored:
            names = [n for n in stored["parameters"] if n in PARAMETERS]
            params = [PARAMETERS[n] for n in names]
            target = prepare(scene, stored["base_mapping"], reference)
            s = calibrated(target.base, params, [stored["parameters"][n] for n in names])
            e = errors(target, batch.paths(target, [s])[0])
            rows.append(Conversion("calibrated", s.solref, s.solimp, e["position_error_max"],
                                   e["angle_error_max"], f"from {calibration}" + (
                                       "" if stored.get("accepted", True) else
                                       f" (its fit was rejected: the {stored['base_mapping']} mapping's values)")))
    return rows
