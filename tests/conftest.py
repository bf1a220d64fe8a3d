"""Shared helpers for the tests: scenes built in code from the schema of docs/scene-format.md."""
from __future__ import annotations

import copy

import pytest

from custom_sim import parse_scene


def make_scene(body: dict, initial: dict, **top):
    """A scene from dicts, with the given top-level overrides (contact={...} etc.)."""
    data = {"duration": 1.0, "dt": 1e-4, "body": body, "initial": initial}
    data.update(copy.deepcopy(top))
    return parse_scene(data, file="<test>")


@pytest.fixture
def scene_factory():
    return make_scene
