"""A law given apart from the scenes (`run --law FILE.toml`): a [contact] table laid over each
scene's own, and the scene judged under it."""
from __future__ import annotations

import dataclasses
import tomllib
from pathlib import Path

from .errors import SceneError
from .laws import LAW_PARAMETERS, SEED_LAW
from .schema import CONTACT_FIELDS, Contact, Scene, _Validator, parse_contact

SHARED = ("k", "mu", "mu_roll")   # parameters every family of their effect takes


def load_law(path: str | Path) -> dict:
    """The [contact] table of a law file, its keys checked (values are checked per scene, once
    laid over the scene's own contact)."""
    path = Path(path)
    if not path.is_file():
        raise SceneError(str(path), "", "no such file (expected a .toml file with a [contact] table, "
                                        "or `identified`)")
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise SceneError(str(path), "", f"cannot be read as TOML ({exc})") from None
    v = _Validator(str(path))
    v.table(data, "", {"contact"})
    table = v.table(data.get("contact"), "contact", CONTACT_FIELDS, required=True)
    parse_contact(v, _laid_over(Contact(), table))   # every value checked once, on the defaults
    return table


def _laid_over(contact: Contact, table: dict) -> dict:
    """The [contact] table the scene would have with `table` laid over it: the scene's
    parameters that both its own families and the new ones take, then the table's fields (a
    parameter only the new family takes, hunt_crossley's dissipation, must come from the table)."""
    laws = {field: table.get(field, getattr(contact, field)) for field in SEED_LAW}
    taken = _parameters(laws) & _parameters({field: getattr(contact, field) for field in SEED_LAW})
    merged = {key: getattr(contact, key) for key in taken}
    merged.update(laws)
    merged.update(table)
    return merged


def _parameters(laws: dict) -> set[str]:
    """The parameters a choice of families takes (the shared ones included)."""
    taken = set(SHARED)
    for field, name in laws.items():
        taken |= set(LAW_PARAMETERS[field].get(name, ()))
    return taken


def without_untaken(table: dict, keep=()) -> dict:
    """A [contact] table without the parameters its families do not take (a study that varies
    friction_law to sign drops the file's alpha), except those named in `keep` (set on purpose:
    then the loader's error says they do not belong)."""
    laws = {field: table.get(field, name) for field, name in SEED_LAW.items()}
    taken = _parameters(laws)
    every = {p for families in LAW_PARAMETERS.values() for params in families.values() for p in params}
    return {key: value for key, value in table.items() if key not in every or key in taken or key in keep}


def with_law(scene: Scene, contact: Contact | dict, law_from: str) -> Scene:
    """The scene under another law: a Contact (an identified law) as it is, or a law file's
    table laid over the scene's [contact] (its errors name `law_from`, the file). The scene's
    own contact is kept in scene_contact for the report."""
    if isinstance(contact, dict):
        contact = parse_contact(_Validator(law_from), _laid_over(scene.contact, contact))
    return dataclasses.replace(scene, contact=contact, law_from=law_from,
                               scene_contact=scene.scene_contact or scene.contact)
