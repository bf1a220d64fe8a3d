"""The project's documentation points only inside the project: every relative link in README.md
and docs/*.md reaches a file (and a heading, for #anchors), and no tracked file cites the notes
the project was built from, which are not part of it."""
from __future__ import annotations

import functools
import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
LINK = re.compile(r"(?<!!)\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)|!\[[^\]]*\]\(([^)\s]+)\)")
# Names of files outside the repository that the project once cited; built from parts so that
# this test file itself does not mention them.
OUTSIDE = ["PHYSICS" + ".md", "CONTRACT" + ".md", "STYLE" + ".md", "../" + "shared"]


def anchor(heading: str) -> str:
    """GitHub's anchor of a markdown heading: lower case, punctuation but - and _ dropped,
    spaces to -."""
    text = re.sub(r"[`*]", "", heading.strip().lower())
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path: Path) -> set[str]:
    return {anchor(m.group(1)) for m in re.finditer(r"^#+\s+(.*)$", path.read_text(), re.M)}


def links(path: Path) -> list[str]:
    text = re.sub(r"```.*?```", "", path.read_text(), flags=re.S)   # code blocks are not links
    return [a or b for a, b in LINK.findall(text)]


def relative_targets():
    for doc in DOCS:
        for target in links(doc):
            if re.match(r"^[a-z]+:", target) or target.startswith("//"):
                continue  # http:, https:, mailto:
            yield doc, target


@pytest.mark.parametrize("doc,target", list(relative_targets()), ids=lambda x: x.name if isinstance(x, Path) else x)
def test_relative_link_reaches_a_file(doc, target):
    path, _, frag = target.partition("#")
    dest = (doc.parent / path).resolve() if path else doc
    # in git, not merely on this disk: a generated file is absent from a fresh checkout
    tracked = set(tracked_files())
    there = dest in tracked or any(dest in f.parents for f in tracked)
    assert there, f"{doc.relative_to(ROOT)}: link {target!r} points nowhere in a checkout ({dest} is not in git)"
    assert ROOT in dest.parents or dest == ROOT, f"{doc.relative_to(ROOT)}: link {target!r} leaves the repository"
    if frag and dest.suffix == ".md":
        assert frag in anchors(dest), f"{doc.relative_to(ROOT)}: link {target!r}: no heading #{frag} in {dest.name}"


def test_the_link_finder_finds_links(tmp_path):
    """The check fails on a known mistake: a broken link is found, a code block is skipped."""
    doc = tmp_path / "x.md"
    doc.write_text("see [a](missing.md) and ![p](img/p.png)\n```\n[not](a_link.md)\n```\n## A `b` heading: c\n")
    assert links(doc) == ["missing.md", "img/p.png"]
    assert anchors(doc) == {"a-b-heading-c"}
    assert anchor("Trajectory files (`a_b.csv`)") == "trajectory-files-a_bcsv"


@functools.cache
def tracked_files() -> tuple[Path, ...]:
    try:
        out = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        pytest.skip("not a git checkout")
    return tuple(ROOT / line for line in out.splitlines() if line)


def test_no_tracked_file_cites_a_file_outside_the_project():
    found = []
    for path in tracked_files():
        try:
            text = path.read_text(encoding="utf-8")
        except (UnicodeDecodeError, OSError):
            continue  # binary or absent
        for n, line in enumerate(text.splitlines(), start=1):
            for name in OUTSIDE:
                if name in line:
                    found.append(f"{path.relative_to(ROOT)}:{n}: {name}")
    assert not found, "cites a file that is not in the project:\n" + "\n".join(found)
