"""The user's simulator as source text, so that a worker that cannot see the user's files runs it.

    bundle = Bundle.of("my_sim.py:step")     # on the user's machine: the module, and the .py
                                             # files beside it that it imports, read once
    simulator = bundle.simulator()           # on a worker: written once to a private folder,
                                             # imported from there, fresh at every run

What travels: the module's file and every .py file under its folder (the folder it was found
in, for a dotted name) that an `import` statement of a shipped file names, anywhere in the file
(top level or inside a function), followed from file to file; a package imported from that
folder travels whole (its .py files). Not the harness's own packages (the worker has them), not
what is installed, not data files. On the worker the files are written under
<tempdir>/contact-harness-sim-<digest>/ (the digest of every file's text: another version of the
code is another folder), the module is imported from its file under a private name (as `run`
imports a path), and that folder alone of the shipped folders is on sys.path, so the module's
`import helper` finds its own helper.py, not one another study shipped.
"""
from __future__ import annotations

import ast
import hashlib
import importlib.util
import os
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

from .errors import UserCodeError
from .functions import StepFunction, WholeFunction, _module_path, declared_shapes, load_function

HARNESS = ("compare", "custom_sim", "mujoco_models", "scene_types")   # on every worker already
PREFIX = "contact-harness-sim-"   # the shipped folders under the worker's temp folder
MAX_BYTES = 5_000_000             # the shipped files, together: source code, not data


@dataclass(frozen=True)
class Bundle:
    """spec: MODULE:FUNCTION as the user gave it (messages name it); entry: the module's file,
    relative to the shipped folder; function: FUNCTION; whole: --whole; files: (relative path,
    text) of every shipped file, sorted."""

    spec: str
    entry: str
    function: str
    whole: bool
    files: tuple[tuple[str, str], ...]

    @classmethod
    def of(cls, spec: str, whole: bool = False) -> Bundle:
        """The bundle of --sim spec (bad input, one line, where the module cannot be found)."""
        module, _, function = spec.rpartition(":")
        path, root = _locate(module, spec)
        files = _imported_files(path, root)
        texts = tuple(sorted((p.relative_to(root).as_posix(), p.read_text(encoding="utf-8")) for p in files))
        size = sum(len(t) for _, t in texts)
        if size > MAX_BYTES:
            raise UserCodeError(f"--sim {spec}: the .py files it imports from {root} hold {size} bytes "
                                f"(expected source code, at most {MAX_BYTES})")
        return cls(spec, path.relative_to(root).as_posix(), function, whole, texts)

    @property
    def digest(self) -> str:
        """A hash of what the worker runs: every file's path and text."""
        h = hashlib.sha256()
        for rel, text in self.files:
            h.update(rel.encode() + b"\0" + text.encode() + b"\0")
        return h.hexdigest()[:16]

    @property
    def names(self) -> list[str]:
        """The files' names as imported (dotted; a package's __init__ by the package's)."""
        out = []
        for rel, _ in self.files:
            parts = rel[:-3].split("/")
            out.append(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
        return out

    def unpack(self) -> Path:
        """The folder on this machine holding the files (written once; a file is renamed into
        place whole, so two processes unpacking at once both find it complete)."""
        folder = Path(tempfile.gettempdir()) / f"{PREFIX}{self.digest}"
        for rel, text in self.files:
            target = folder / rel
            if target.is_file() and target.read_text(encoding="utf-8") == text:
                continue
            target.parent.mkdir(parents=True, exist_ok=True)
            part = target.with_name(f".{target.name}.{os.getpid()}.part")
            part.write_text(text, encoding="utf-8")
            os.replace(part, target)
        return folder

    def simulator(self):
        """The simulator from the shipped files (a StepFunction, or a WholeFunction with
        --whole), imported on this machine; messages name the user's spec."""
        folder = self.unpack()
        _only_this_folder(folder, self.names)
        kind = ShippedWhole if self.whole else ShippedStep
        return kind(self.spec, f"{folder / self.entry}:{self.function}")


class _Shipped:
    """A user's function imported from its shipped copy: the spec the user gave in every message,
    the copy's path for the import."""

    spec: str
    signature: str

    def __init__(self, spec: str, local: str):
        self.local = local
        super().__init__(spec)  # type: ignore[call-arg]  # a mixin: the function class after it takes spec

    def fresh(self) -> None:
        self.function, self.module = load_function(self.local, self.signature)
        self.shapes = declared_shapes(getattr(self.module, "SHAPES", None), f"{self.spec}: SHAPES")

    def __reduce__(self):
        return (type(self), (self.spec, self.local))


class ShippedStep(_Shipped, StepFunction):
    """A step function run from its shipped copy."""


class ShippedWhole(_Shipped, WholeFunction):
    """A whole run (--whole) run from its shipped copy."""


def _only_this_folder(folder: Path, names: list[str]) -> None:
    """Other shipped folders off sys.path, and the modules imported from them under this
    bundle's names forgotten: `import helper` finds this bundle's helper.py."""
    mine = str(folder)
    sys.path[:] = [p for p in sys.path if p == mine or not Path(p).name.startswith(PREFIX)]
    for name in names:
        mod = sys.modules.get(name)
        where = getattr(mod, "__file__", None) or ""
        if mod is not None and not where.startswith(mine):
            del sys.modules[name]
    if mine not in sys.path:
        sys.path.append(mine)


def _locate(module: str, spec: str) -> tuple[Path, Path]:
    """(the module's file, the folder its imports are found in)."""
    path = _module_path(module)
    if path is not None:
        path = path.resolve()
        return path, path.parent
    found = importlib.util.find_spec(module)   # the loader imported it already: it is found
    if found is None or not found.origin or not found.origin.endswith(".py"):
        raise UserCodeError(f"--sim {spec}: {module} is not a .py file the workers can be sent "
                            "(expected a path to a .py file, or a module of .py files)")
    path = Path(found.origin).resolve()
    depth = module.count(".") + (1 if path.name == "__init__.py" else 0)
    return path, path.parents[depth]


def _imported_names(path: Path, root: Path) -> set[str]:
    """Dotted names an import statement of the file names (relative ones made absolute)."""
    try:
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    except (SyntaxError, UnicodeDecodeError, ValueError):
        return set()
    package = path.parent.relative_to(root).parts if path.parent != root else ()
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = list(package[:len(package) - node.level + 1]) if node.level else []
            head = ".".join([*base, *(node.module.split(".") if node.module else [])])
            if head:
                names.add(head)
            names |= {f"{head}.{alias.name}" if head else alias.name for alias in node.names}
    return names


def _files_of(name: str, root: Path) -> list[Path]:
    """The files under root that importing `name` runs: each package's __init__.py on the way,
    the module's file; a package's every .py file."""
    parts = name.split(".")
    if parts[0] in HARNESS:
        return []
    out = []
    for i in range(1, len(parts) + 1):
        base = root.joinpath(*parts[:i])
        if (base / "__init__.py").is_file():
            out.append(base / "__init__.py")
            if i == len(parts):
                out += sorted(base.rglob("*.py"))
        elif base.with_suffix(".py").is_file():
            out.append(base.with_suffix(".py"))
            break
        else:
            break
    return out


def _imported_files(path: Path, root: Path) -> list[Path]:
    """The module's file and every file under root its imports reach, followed file to file."""
    seen, todo = {path}, [path]
    while todo:
        current = todo.pop()
        for name in sorted(_imported_names(current, root)):
            for found in _files_of(name, root):
                found = found.resolve()
                if found not in seen and root in found.parents:
                    seen.add(found)
                    todo.append(found)
    return sorted(seen)
