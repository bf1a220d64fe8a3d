"""The harness's Python API (docs/python-api.md); the command line is `python -m compare`.

    compare.judge(sim, scenes=None, *, law=None, whole=False, out=None) -> Judgement
    compare.identify(sim, scenes=None) -> (Identification, ...)
    compare.Process("COMMAND")   a simulator in another language (--sim-process)

Nothing is imported until a name is used: `import compare` stays as light as the command line's start.
"""
from __future__ import annotations

import importlib

_NAMES = {   # public name -> (module, attribute)
    "judge": ("compare.api.judge", "judge"),
    "identify": ("compare.api.identify", "identify_scenes"),
    "Judgement": ("compare.api.judgement", "Judgement"),
    "SceneJudgement": ("compare.api.scene", "SceneJudgement"),
    "Check": ("compare.api.check", "Check"),
    "Diagnosis": ("compare.api.diagnosis", "Diagnosis"),
    "Mistake": ("compare.api.diagnosis", "Mistake"),
    "Status": ("compare.api.status", "Status"),
    "Identification": ("compare.api.identification", "Identification"),
    "Effect": ("compare.api.identification", "Effect"),
    "Process": ("compare.usersim.process", "Process"),
    "BadInput": ("scene_types", "BadInput"),
    "SceneError": ("scene_types", "SceneError"),
}

__all__ = list(_NAMES)


def __getattr__(name: str):
    if name not in _NAMES:
        raise AttributeError(f"module 'compare' has no attribute {name!r}")
    module, attribute = _NAMES[name]
    try:
        value = getattr(importlib.import_module(module), attribute)
    except ModuleNotFoundError as exc:
        if exc.name != module:
            raise
        raise AttributeError(f"compare.{name}: not in this version of the harness ({module} is missing)") from None
    globals()[name] = value
    return value


def __dir__():
    return sorted([*globals(), *_NAMES])
