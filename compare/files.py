"""Where output goes and how it is written: the --out folder checked before anything is
written, report files written in one step, with the permissions the user's umask gives, and JSON
that never holds NaN or infinity.

tempfile.mkstemp and mkdtemp create their file 0600 and their folder 0700 whatever the umask
(they are meant for private scratch space); a report file renamed into place from them kept
those modes. Here the temporary file or folder gets the mode an ordinary open() or mkdir()
would have given (0644 and 0755 at umask 022) before it is renamed into place.

    write_text_atomically(path, text)       the file is complete or absent, never half-written
    temporary_folder(parent, prefix)        a hidden folder beside its final place, to os.replace
    finite_json(data, **json_dumps_kw)      JSON text: NaN and +-inf become null, listed in
                                            data["non_finite"] (for a dict) so nothing is silent
    output_folder(out)                      the --out folder, checked before anything is written
"""
from __future__ import annotations

import json
import math
import os
import tempfile
from pathlib import Path

FILE_MODE = 0o666     # what open(path, "w") asks for, before the umask
FOLDER_MODE = 0o777   # what mkdir asks for, before the umask
NON_FINITE_KEY = "non_finite"


def current_umask() -> int:
    """The process's umask, read without changing it where the system says it (Linux's
    /proc/self/status); elsewhere set and restored at once."""
    try:
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def write_text_atomically(path: str | Path, text: str, encoding: str = "utf-8") -> None:
    """Write text to path through a temporary file beside it, renamed over it when complete;
    the file gets the umask's permissions (0644 at umask 022), as open() would give it."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    try:
        os.fchmod(fd, FILE_MODE & ~current_umask())
        with os.fdopen(fd, "w", encoding=encoding) as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def temporary_folder(parent: str | Path, prefix: str) -> Path:
    """A new hidden folder in parent (tempfile.mkdtemp) with the umask's permissions (0755 at
    umask 022), as mkdir would give it: to fill, then os.replace into its final place."""
    tmp = Path(tempfile.mkdtemp(dir=parent, prefix=prefix))
    os.chmod(tmp, FOLDER_MODE & ~current_umask())
    return tmp


def _clean(value, where: str, found: list):
    """value with every non-finite float replaced by None (its path and value appended to
    found), numpy scalars and arrays as plain Python, tuples as lists."""
    if isinstance(value, float) or (hasattr(value, "dtype") and getattr(value, "ndim", None) == 0):
        if hasattr(value, "item"):
            value = value.item()
        if isinstance(value, float) and not math.isfinite(value):
            found.append({"key": where or "(top)", "value": repr(value)})
            return None
        return value
    if isinstance(value, dict):
        return {k: _clean(v, f"{where}.{k}" if where else str(k), found) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v, f"{where}[{i}]", found) for i, v in enumerate(value)]
    if hasattr(value, "tolist") and hasattr(value, "dtype"):   # a numpy array
        return _clean(value.tolist(), where, found)
    return value


def finite_json(data, **dumps_kw) -> str:
    """json.dumps(data, allow_nan=False, **dumps_kw) that never raises on NaN or infinity: each
    non-finite number is written as null, and a dict gets the key "non_finite", a list of
    {"key": its path (e.g. "checks[2].tolerance_position"), "value": "inf", "-inf" or "nan"},
    so a program reading the file sees which numbers were not finite. data is not changed."""
    found: list = []
    clean = _clean(data, "", found)
    if found and isinstance(clean, dict):
        clean[NON_FINITE_KEY] = found
    return json.dumps(clean, allow_nan=False, **dumps_kw)


def output_folder(out: str) -> Path:
    """The --out folder: a folder or a path still free, never an existing file, nor a path
    under one (`somefile.txt/sub`), checked on every existing ancestor before anything is
    written; the nearest existing one must be a folder this process can write into."""
    from scene_types import BadInput

    path = Path(out)
    if path.exists() and not path.is_dir():
        raise BadInput(f"{path}: --out: is a file (expected a folder)")
    # Path.exists() is False under a file (NotADirectoryError), so walk up to what exists
    for ancestor in [path, *path.parents]:
        try:
            ancestor.stat()
        except FileNotFoundError:
            continue
        except NotADirectoryError:   # a file further up: keep walking to find it
            continue
        except OSError as exc:
            raise BadInput(f"{path}: --out: {ancestor} cannot be read ({exc.strerror or exc}); "
                           "expected a folder or a path that can be created") from None
        if not ancestor.is_dir():
            raise BadInput(f"{path}: --out: {ancestor} is a file, so no folder can be made under it "
                           "(expected a folder or a path that can be created)")
        if not os.access(ancestor, os.W_OK | os.X_OK):
            raise BadInput(f"{path}: --out: {ancestor} is a folder this user cannot write into "
                           "(expected a writable folder or a path that can be created)")
        break
    return path
