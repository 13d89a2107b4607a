"""components.yaml (panther_description / husarion_ugv_description): the validator of the
file kind, and the manual's ANT02 entry ("Use of GPS in Simulation").

Schema (panther-stack.md 1.7): ``components:`` a list of mappings with ``type``, and
``parent_link``, ``xyz`` ("x y z"), ``rpy`` ("r p y"), ``device_namespace``, optional ``name``.
"""

from __future__ import annotations

import re
from typing import Any

from panther_ops.core.yamldoc import YamlDocument
from panther_ops.errors import InputError, UsageError

KEYS = ("type", "parent_link", "xyz", "rpy", "device_namespace", "name")
ANT02 = {"type": "ANT02", "parent_link": "cover_link", "xyz": "0.185 -0.12 0.0", "rpy": "0.0 0.0 3.14",
         "device_namespace": "gps"}
"""The manual's entry."""
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_TYPE = re.compile(r"^[A-Z]{3}[0-9]{2}$")


def check_triple(value: Any, what: str) -> str:
    """``"x y z"``: three numbers separated by spaces (UsageError otherwise)."""
    parts = str(value).split()
    try:
        if len(parts) != 3:
            raise ValueError
        [float(p) for p in parts]
    except ValueError:
        raise UsageError(f"{what} {value!r}: three numbers separated by spaces, e.g. \"0.185 -0.12 0.0\"") from None
    return " ".join(parts)


def validate_components(doc: Any, path: str) -> None:
    """Raise InputError (naming the entry and key) unless ``doc`` is a valid components file."""
    if not isinstance(doc, dict) or "components" not in doc:
        raise InputError("expected a mapping with a components: list", path=path)
    items = doc["components"]
    if items is None:
        return
    if not isinstance(items, list):
        raise InputError("components must be a list", path=path, key="components")
    for i, item in enumerate(items):
        where = f"components[{i}]"
        if not isinstance(item, dict):
            raise InputError(f"{where} must be a mapping (type, parent_link, xyz, rpy, device_namespace)",
                             path=path, key=where)
        unknown = sorted(set(item) - set(KEYS))
        if unknown:
            raise InputError(f"{where}: unknown key {unknown[0]!r}", path=path, key=f"{where}.{unknown[0]}",
                             hint="allowed: " + ", ".join(KEYS))
        if not isinstance(item.get("type"), str) or not _TYPE.match(item["type"]):
            raise InputError(f"{where}.type {item.get('type')!r}: a Husarion component code such as ANT02, LDR01",
                             path=path, key=f"{where}.type")
        for key in ("xyz", "rpy"):
            if key in item:
                try:
                    check_triple(item[key], f"{where}.{key}")
                except UsageError as exc:
                    raise InputError(exc.message, path=path, key=f"{where}.{key}") from None
        for key in ("parent_link", "device_namespace", "name"):
            if key in item and (not isinstance(item[key], str) or not _NAME.match(item[key])):
                raise InputError(f"{where}.{key} {item[key]!r}: letters, digits and _", path=path,
                                 key=f"{where}.{key}")


def add_ant02(text: str, path: str, entry: dict[str, str]) -> tuple[str, str]:
    """The file with the ANT02 entry (appended, or the existing ANT02 entry's keys set), and
    what was done. The result is validated."""
    doc = YamlDocument(text, path)
    validate_components(doc.to_plain(), path)
    items = doc.get("components") or []
    found = [i for i, it in enumerate(items) if isinstance(it, dict) and it.get("type") == "ANT02"]
    if len(found) > 1:
        raise InputError("several ANT02 entries: keep one", path=path, key="components")
    if found:
        i = found[0]
        for k, v in entry.items():
            doc.set(("components", i, k), v)
        what = "ANT02 entry updated" if doc.changed else "ANT02 entry already as asked"
    elif items:
        doc.append("components", entry)
        what = "ANT02 entry added"
    else:
        doc.set("components", [entry])
        what = "ANT02 entry added"
    validate_components(YamlDocument(doc.text, path).to_plain(), path)
    return doc.text, what
