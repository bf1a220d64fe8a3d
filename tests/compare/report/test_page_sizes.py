"""What a user reads first is short: a passing scene's page at most 8 KB of text before its
folded details, and a verdict line at most 160 characters (the rest on the page)."""
import re
from pathlib import Path

from compare.cli import main

ROOT = Path(__file__).resolve().parents[3]
PAGE_LIMIT = 8 * 1024      # bytes of a passing scene's page outside its <details> blocks
LINE_LIMIT = 160           # characters of a verdict line


def short_file(tmp_path, builtin: str, duration: float) -> str:
    text = (ROOT / "scenarios" / f"{builtin}.toml").read_text()
    path = tmp_path / f"{builtin}.toml"
    path.write_text("\n".join(f"duration = {duration}" if line.startswith("duration") else line
                              for line in text.splitlines()))
    return str(path)


def unfolded(page: str) -> str:
    return re.sub(r"<details>.*?</details>", "", page, flags=re.DOTALL)


def test_a_passing_page_and_a_failing_line_are_short(tmp_path, capsys):
    """box_drop (0.3 s, past its landing) with custom_sim passes: its page's unfolded text fits
    8 KB and still holds every check's verdict; under the buggy example the FAIL line, which
    was 500 to 700 characters, fits 160 and names every failed check."""
    scene = short_file(tmp_path, "box_drop", 0.3)
    assert main(["run", scene, "--out", str(tmp_path / "ours")]) == 0
    printed = capsys.readouterr().out
    page = (tmp_path / "ours" / "box_drop" / "index.md").read_text()
    shown = unfolded(page)
    assert len(shown.encode()) <= PAGE_LIMIT < len(page.encode()), (len(shown.encode()), len(page.encode()))
    assert "**PASS**" in shown and all(f"| {label} " in shown for label in ("step (rk4)", "contact (semi_implicit_euler)",
                                                                            "ground (semi_implicit_euler)"))
    assert "## Why the two differ" in page and "## Why the two differ" not in shown
    assert all(len(line) <= LINE_LIMIT for line in printed.splitlines()), printed

    assert main(["run", scene, "--sim", f"{ROOT}/examples/buggy_sim.py:step", "--out", str(tmp_path / "buggy")]) == 1
    line = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("box_drop "))
    assert len(line) <= LINE_LIMIT and " FAIL " in line and line.endswith("(see the page)"), line
    failed = re.search(r"\*\*FAIL\*\*: ([^|]*)\|", (tmp_path / "buggy" / "index.md").read_text()).group(1).strip()
    assert all(label.split(" (")[0] in line for label in failed.split(", ")), (failed, line)
