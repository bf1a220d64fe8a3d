"""What `identify --json` prints for one scene, as objects: an Identification of Effects, each a
read-only view of its JSON entry (attribute access to its keys: `.k`, `.mu`, `.mass`, ...)."""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any
from collections.abc import Mapping

EFFECTS = ("integrator", "gravity", "normal", "friction", "rolling", "body")


@dataclass(frozen=True)
class Effect:
    """One entry of identify's answer (`normal`, `friction`, ...). `law` is the family found
    (the integrator's name for `integrator`), None when none reproduces the step or the effect
    is not exercised; every other key of the entry reads as an attribute (None when absent):
    normal.k (N/m), normal.c (N s/m), friction.mu, friction.alpha (s/m), rolling.mu_roll (m),
    gravity.g (m/s^2), body.mass (kg), body.inertia (kg m^2), normal.closest, ..."""

    effect: str
    law: str | None
    residual: float | None
    data: Mapping[str, Any] = field(default_factory=dict, compare=False, repr=False)

    def __getattr__(self, key: str):
        if key.startswith("__") or key == "data":
            raise AttributeError(key)
        return self.data.get(key)

    @property
    def exercised(self) -> bool:
        """Whether the scene exercised it (entries without the key: yes)."""
        return self.data.get("exercised", True) is not False

    @classmethod
    def from_json(cls, effect: str, entry: dict | None) -> Effect | None:
        if entry is None:
            return None
        law = entry.get("name") if effect == "integrator" else entry.get("law")
        return cls(effect, law, entry.get("residual"), MappingProxyType(entry))


@dataclass(frozen=True)
class Identification:
    """The law one scene's run is found to follow; `to_json()` is exactly the object `identify
    --json` prints for that scene."""

    scene: str
    integrator: Effect | None
    gravity: Effect | None
    normal: Effect | None
    friction: Effect | None
    rolling: Effect | None
    body: Effect | None
    matches_scene: Mapping[str, bool | None]      # per effect: the scene's own law and parameters?
    keeps_state: bool | None = None               # a step that keeps state between calls (no designed probes)
    skipped: str | None = None                    # a scene the code does not do: why (no effects then)
    data: Mapping[str, Any] = field(default_factory=dict, compare=False, repr=False)

    @property
    def matches(self) -> bool:
        """No exercised effect differs from the scene's law (identify's exit status 0)."""
        return not any(v is False for v in self.matches_scene.values())

    def to_json(self) -> dict:
        """The JSON object `identify --json` prints (a new copy)."""
        return json.loads(json.dumps(dict(self.data), default=dict))

    @classmethod
    def from_result(cls, result: dict) -> Identification:
        """From compare.identify's result dict, made plain JSON as `identify --json` makes it."""
        from ..identification.report import as_json

        data = json.loads(as_json(result))
        effects = {e: Effect.from_json(e, data.get(e)) for e in EFFECTS}
        return cls(data.get("scene", ""), **effects, matches_scene=MappingProxyType(data.get("matches_scene") or {}),
                   keeps_state=data.get("keeps_state"), skipped=data.get("skipped"), data=MappingProxyType(data))
