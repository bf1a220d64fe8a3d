"""The pytest plugin (entry point group pytest11): `pytest --contact-sim MODULE:FUNCTION` adds one
test per scene, `contact-sim::SCENE`, failing with `run`'s verdict lines and the diagnosis; a
scene the code does not do is a skip with its reason. The fixture `contact_harness` gives the
Python API (compare.judge, compare.identify) inside a user's own tests. Without --contact-sim the
plugin adds nothing; importing it imports only pytest (the harness loads when a test uses it).
See docs/python-api.md.
"""
from __future__ import annotations

from pathlib import Path

import pytest

COLLECTOR = "contact-sim"   # the collector's name: items are contact-sim::SCENE


def pytest_addoption(parser) -> None:
    group = parser.getgroup("contact-sim", "judging a contact simulator against MuJoCo (contact-sim-harness)")
    group.addoption("--contact-sim", metavar="SIM", default=None,
                    help="MODULE:FUNCTION of a step function step(state, scene, dt) -> state (a dotted module or a "
                         "path to a .py file): one test per scene, contact-sim::SCENE")
    group.addoption("--contact-scenes", metavar="A,B", default=None,
                    help="scenes to judge, comma-separated built-in names or .toml paths (default: every built-in)")
    group.addoption("--contact-law", metavar="identified|FILE", default=None,
                    help="judge under the law identify finds (identified) or a law file's [contact] (run --law)")
    group.addoption("--contact-whole", action="store_true", default=False,
                    help="--contact-sim names simulate(scene) -> array (steps + 1, 6) (run --whole)")


def _scenes(config) -> tuple[str, ...] | None:
    text = config.getoption("contact_scenes")
    return None if not text else tuple(s.strip() for s in text.split(",") if s.strip())


def _harness(config):
    from compare.api.harness import Harness
    return Harness(config.getoption("contact_sim"), _scenes(config), config.getoption("contact_law"),
                   config.getoption("contact_whole"))


def pytest_report_header(config):
    sim = config.getoption("contact_sim")
    if sim:
        return f"contact-sim: {sim} on {', '.join(_scenes(config) or ['every built-in scene'])}"
    return None


@pytest.hookimpl(tryfirst=True)   # before -k and -m deselect
def pytest_collection_modifyitems(session, config, items) -> None:
    if not config.getoption("contact_sim"):
        return
    collector = ContactSim.from_parent(session, name=COLLECTOR, nodeid=COLLECTOR)
    session.ihook.pytest_collectstart(collector=collector)   # as pytest collects a file: counted, reported
    report = session.ihook.pytest_make_collect_report(collector=collector)
    session.ihook.pytest_collectreport(report=report)
    if report.passed:
        items.extend(report.result)


class ContactSim(pytest.Collector):
    """The scenes --contact-scenes names (every built-in by default), one item each; the scenes
    are read now, so a bad name is a collection error (one line) before any test runs."""

    def collect(self):
        from compare.api.judge import scene_specs
        from compare.scenarios import load_all
        from scene_types import BadInput, SceneError

        try:
            scenes = load_all(scene_specs(_scenes(self.config)))
        except (BadInput, SceneError) as exc:
            raise self.CollectError(f"--contact-scenes: {exc}") from None
        return [ContactScene.from_parent(self, name=s.name, spec=s.source) for s in scenes]


class ContactFailure(Exception):
    """A scene outside its tolerance, or with no verdict: the lines pytest shows."""


class ContactScene(pytest.Item):
    """One scene's test: its row of the session's judgement (every scene still selected after -k
    and -m is judged at the first test that needs it, in parallel, as `run` judges them)."""

    def __init__(self, *, spec: str, **kwargs):
        super().__init__(**kwargs)
        self.spec = spec   # the scene file

    def runtest(self) -> None:
        judgement = _judgement(self.session)
        if isinstance(judgement, Exception):
            raise ContactFailure(str(judgement))
        scene = judgement[self.name]
        from compare.api.status import Status

        if scene.status is Status.SKIPPED:   # reported at the scene's file, not at this line
            raise pytest.skip.Exception(scene.reason or "skipped by the code under test", _use_item_location=True)
        if not scene.passed:
            text = list(scene.lines)
            if scene.diagnosis is not None:
                text.append(f"diagnosis: {scene.diagnosis.verdict}")
                text.extend(f"law: {law}" for law in scene.diagnosis.laws)
            raise ContactFailure("\n".join(text))

    def repr_failure(self, excinfo, style=None):
        if isinstance(excinfo.value, ContactFailure):
            return str(excinfo.value)
        return super().repr_failure(excinfo, style)

    def reportinfo(self):
        return Path(self.spec), 0, f"{COLLECTOR}::{self.name}"


_JUDGED = pytest.StashKey[object]()


def _judgement(session):
    """The judgement of every scene selected to run, made once per session; bad input (a module
    that does not load, a law file that is not one) is kept as its exception: every test shows it."""
    config = session.config
    if _JUDGED not in config.stash:
        from scene_types import BadInput, SceneError

        specs = [item.spec for item in session.items if isinstance(item, ContactScene)]
        try:
            config.stash[_JUDGED] = _harness(config).judge(scenes=specs)
        except (BadInput, SceneError) as exc:
            config.stash[_JUDGED] = exc
    return config.stash[_JUDGED]


@pytest.fixture
def contact_harness(request):
    """The Python API (compare.judge, compare.identify) with --contact-sim, --contact-scenes and
    --contact-law as defaults: `contact_harness.judge("my_sim.py:step", ["box_drop"]).passed`."""
    return _harness(request.config)
