"""The mutation test's catalogue stays applicable: every mistake is one real edit of custom_sim.

The mutation run itself (`python -m compare tools mutation`, a CI step of its own) compiles a copy of
custom_sim per mistake; this fast test only guards that each edit still finds its text, so that
a change to custom_sim cannot silently turn a mistake into a no-op.
"""
from pathlib import Path

import pytest

from compare.tools.mutation.mutants import mutated_copy
from compare.tools.mutation.catalogue import MISTAKES

ROOT = Path(__file__).resolve().parents[3]
ENOUGH = 15  # the issue asks for at least fifteen typical mistakes


def test_catalogue_is_large_and_distinct():
    names = [m.name for m in MISTAKES]
    assert len(names) >= ENOUGH and len(set(names)) == len(names)
    assert len({(m.file, m.old, m.new) for m in MISTAKES}) == len(MISTAKES)


@pytest.mark.parametrize("mistake", MISTAKES, ids=lambda m: m.name)
def test_each_mistake_changes_custom_sim(mistake, tmp_path):
    original = (ROOT / "custom_sim" / mistake.file).read_text()
    assert mistake.old in original, f"{mistake.name}: text not found in custom_sim/{mistake.file}"
    copy = mutated_copy(mistake, tmp_path)
    changed = (copy / mistake.file).read_text()
    assert changed != original and mistake.new in changed
    compile(changed, mistake.file, "exec")  # still valid Python: the mistake runs, it does not crash


def test_a_mistake_both_catalogues_know_has_one_name():
    """The mutation test and the diagnosis name a shared mistake alike: the same name, the same
    seed line (a name reused for another mistake would show as another seed line)."""
    from compare.diagnosis.mistakes import CATALOGUE
    diagnosed = {m.name: m for m in CATALOGUE}
    shared = [m for m in MISTAKES if m.name in diagnosed]
    assert len(shared) >= 9   # the inertias, gravity, friction's slip, rotation, integrator, contact height
    for m in shared:
        assert m.seed_line == diagnosed[m.name].seed_line, m.name
