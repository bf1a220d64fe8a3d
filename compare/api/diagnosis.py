"""What the diagnosis of a user's run says, typed: the catalogued mistakes that explain it, the
laws that differ from the scene's, and its one-line verdict (metrics.json `diagnosis`)."""
from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any
from collections.abc import Mapping


@dataclass(frozen=True)
class Mistake:
    """A catalogued departure from the seed's algorithm that reproduces every probed step."""

    name: str            # e.g. friction_on_com_velocity
    seed_line: str       # the line of the seed it departs from
    description: str     # what the code does instead


@dataclass(frozen=True)
class Diagnosis:
    """The diagnosis of one scene's run (only for a simulator other than custom_sim)."""

    verdict: str                          # one line: what explains the run, or that nothing needs to
    named: tuple[Mistake, ...] = ()       # every mistake that explains it
    laws: tuple[str, ...] = ()            # where no mistake is named: each effect whose law differs
    data: Mapping[str, Any] = field(default_factory=dict, compare=False, repr=False)   # the metrics.json block

    @property
    def text(self) -> str:
        """The verdict and each law sentence, one a line."""
        return "\n".join([self.verdict, *self.laws])

    @classmethod
    def from_json(cls, block: dict | None) -> Diagnosis | None:
        """metrics.json `diagnosis` (None: no diagnosis, custom_sim under test)."""
        if not block:
            return None
        named = tuple(Mistake(m.get("name", ""), m.get("seed_line", ""), m.get("description", ""))
                      for m in block.get("named") or [])
        laws = tuple(law["text"] for law in block.get("laws") or [])
        return cls(block.get("verdict", ""), named, laws, MappingProxyType(dict(block)))
