"""The entry points pyproject.toml declares (installed by `pip install -e .`): the console command
`contact-harness`, the same as `python -m compare`, and the pytest plugin (group pytest11). Read
from pyproject.toml and called here, so the test needs no reinstall."""
from __future__ import annotations

import importlib
import subprocess
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]


def target(reference: str):
    module, _, attribute = reference.partition(":")
    found = importlib.import_module(module)
    return getattr(found, attribute) if attribute else found


def test_contact_harness_is_python_m_compare(monkeypatch, capsys):
    main = target(PROJECT["scripts"]["contact-harness"])
    monkeypatch.setattr(sys, "argv", ["contact-harness", "list"])
    status = main()
    printed = capsys.readouterr().out
    want = subprocess.run([sys.executable, "-m", "compare", "list"], capture_output=True, text=True, cwd=ROOT)
    assert (status, printed) == (want.returncode, want.stdout) == (0, want.stdout)
    monkeypatch.setattr(sys, "argv", ["contact-harness", "scene", "no_such_scene"])
    assert main() == 2   # bad input, as python -m compare answers it
    assert "no_such_scene: unknown scenario" in capsys.readouterr().err


def test_the_pytest_plugin_is_registered_for_pytest():
    plugin = target(PROJECT["entry-points"]["pytest11"]["contact_harness"])
    assert plugin.__name__ == "compare.pytest_plugin"
    assert callable(plugin.pytest_addoption) and callable(plugin.contact_harness)
