"""One command tree: every command and tool runs as `python -m compare ...` (compare/cli.py), its
help works, docs/cli.md has a section for it, no other module parses argv, and the tree is lazy
(a command imports only its own module)."""
import ast
import importlib
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from compare import cli

ROOT = Path(__file__).resolve().parents[2]
TREE = list(cli.command_tree())
# the only files under compare/ that may read the command line
ENTRY = {Path("cli.py"), Path("__main__.py")}


def test_the_tree_has_the_user_commands_and_the_tools():
    top = [w[0] for w in TREE if len(w) == 1]
    assert top == list(cli.COMMANDS) and {"run", "validate", "tools"} <= set(top)
    tools = [w[1] for w in TREE if w[0] == "tools" and len(w) == 2]
    assert {"mutation", "step-survey", "dynamics-survey", "energy-table", "stability-table"} <= set(tools)
    assert all(re.fullmatch(r"[a-z]+(-[a-z]+)*", name) for words in TREE for name in words)


@pytest.mark.parametrize("words", [(), *TREE], ids=lambda w: " ".join(w) or "python -m compare")
def test_help_on_every_command_and_tool(words, capsys):
    with pytest.raises(SystemExit) as exit_:
        cli.main([*words, "--help"])
    assert exit_.value.code == 0
    out = capsys.readouterr().out
    assert out.startswith("usage: " + " ".join(["python -m compare", *words]))
    if not words or words == ("tools",):   # a group's help lists every member with its help line
        below = [w[-1] for w in TREE if w[:-1] == words]
        assert all(re.search(rf"^    {re.escape(name)}\b", out, re.M) for name in below), out


def test_help_lines_read_without_importing_are_the_docstrings():
    modules = [cli.COMMANDS[w[0]] if len(w) == 1 else importlib.import_module(cli.COMMANDS[w[0]]).SUBCOMMANDS[w[1]]
               for w in TREE]
    for name in modules:
        doc = importlib.import_module(name).__doc__
        assert cli._docstring(name) == doc and cli.summary(doc), name


def test_docs_cli_has_a_section_for_every_command_and_tool():
    headings = set(re.findall(r"^#+ (.+?)(?: \(CI\))?$", (ROOT / "docs" / "cli.md").read_text(), re.M))
    missing = [" ".join(w) for w in TREE if " ".join(w) not in headings]
    assert not missing, f"docs/cli.md has no section for {missing}"


def _reads_the_command_line(path: Path) -> list[str]:
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import) and any(a.name == "argparse" for a in node.names):
            found.append(f"line {node.lineno}: import argparse")
        elif isinstance(node, ast.ImportFrom) and node.module == "argparse":
            found.append(f"line {node.lineno}: from argparse import")
        elif isinstance(node, ast.Attribute) and node.attr == "argv" and getattr(node.value, "id", "") == "sys":
            found.append(f"line {node.lineno}: sys.argv")
        elif isinstance(node, ast.ImportFrom) and node.module == "sys" and any(a.name == "argv" for a in node.names):
            found.append(f"line {node.lineno}: from sys import argv")
        elif (isinstance(node, ast.Compare) and getattr(node.left, "id", "") == "__name__"
              and any(getattr(c, "value", None) == "__main__" for c in node.comparators)):
            found.append(f"line {node.lineno}: if __name__ == '__main__'")
    return found


def test_only_the_command_line_modules_read_argv():
    """compare/cli.py parses, compare/__main__.py runs it, compare/commands/ declares the
    arguments; every other module is logic, called by a command, and no `python -m compare.X`."""
    offenders = {}
    for path in sorted((ROOT / "compare").rglob("*.py")):
        inside = path.relative_to(ROOT / "compare")
        if inside in ENTRY or inside.parts[0] == "commands":
            continue
        if path.name == "__main__.py":
            offenders[str(inside)] = ["a __main__.py: an entry point of its own"]
        elif found := _reads_the_command_line(path):
            offenders[str(inside)] = found
    assert not offenders, offenders


def test_no_file_runs_an_old_module_entry_point():
    files = [ROOT / "README.md", *(ROOT / "docs").glob("*.md"), *(ROOT / ".ci").iterdir(),
             *(ROOT / "compare").rglob("*.py"), *(ROOT / "tests").rglob("*.py"), *(ROOT / "examples").rglob("*.py")]
    old = re.compile(r"-m compare\.[a-z]|\"-m\", \"compare\.")
    stale = [f"{p.relative_to(ROOT)}:{i}" for p in files if p.is_file() and p.resolve() != Path(__file__).resolve()
             for i, line in enumerate(p.read_text().splitlines(), 1) if old.search(line)]
    assert not stale, stale


IMPORTED = """
import contextlib, io, json, sys
from compare import cli
with contextlib.redirect_stdout(io.StringIO()):
    try:
        cli.main(ARGV)
    except SystemExit:
        pass
print(json.dumps(sorted(m for m in sys.modules if m.startswith("compare.commands.")
                        or m.split(".")[0] in ("numpy", "numba", "scipy", "matplotlib", "mujoco"))))
"""


def imported_by(argv: list[str]) -> set[str]:
    proc = subprocess.run([sys.executable, "-c", f"ARGV = {argv!r}\n" + IMPORTED], cwd=ROOT,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    return set(json.loads(proc.stdout.strip().splitlines()[-1]))


def test_the_tree_is_lazy():
    """--help imports no command module and no numpy; a command imports its own module alone."""
    assert imported_by(["--help"]) == set()
    assert imported_by(["tools", "--help"]) == {"compare.commands.tools"}
    listed = imported_by(["list"])
    assert {m for m in listed if m.startswith("compare.")} == {"compare.commands.list_scenes"}
    assert not {m.split(".")[0] for m in listed} & {"numba", "scipy", "matplotlib", "mujoco"}, listed
    assert {m for m in imported_by(["tools", "mutation", "--help"]) if m.startswith("compare.")} == {
        "compare.commands.tools", "compare.commands.tools.mutation"}
