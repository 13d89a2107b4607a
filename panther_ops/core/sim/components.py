"""components.yaml (panther_description / husarion_ugv_description): the validator of the
file kind, and the manual's ANT02 entry ("Use of GPS in Simulation").

Schema (panther-stack.md 1.7): ``components:`` a list of mappings with ``type``, and
``parent_link``, ``xyz`` ("x y z"), ``rpy`` ("r p y"), ``device_namespace``, optional ``name``.
"""

from __future__ import annotations

import re
from typing import Any

from panther_ops.core.yaml.document import YamlDocument
from panther_ops.errors import InputError, UsageError

KEYS = ("type", "parent_link", "xyz", "rpy", "device_namespace", "name")
ANT02 = {"type": "ANT02", "parent_link": "cover_link", "xyz": "0.185 -0.12 0.0", "rpy": "0.0 0.0 3.14",
         "device_namespace": "gps"}
"""The manual's entry."""
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_TYPE = re.compile(r"^[A-Z]{3}[0-9]{2}$")


def check_triple(value: Any, what: str) -> str:
    """``"x y z"``: three numbers in ASCII digits separated by spaces (the file kind's
    `triple`), normalised; UsageError otherwise."""
    from panther_ops.core.kinds.simple import triple

    text = triple(str(value))
    if text is None:
        raise UsageError(f"{what} {value!r}: three numbers separated by spaces, e.g. \"0.185 -0.12 0.0\"")
    return text


def validate_components(text: str, path: str) -> None:
    """`FileKindError` (exit 2, naming the entry and key) unless ``text`` is a valid components
    file: the file kind's one validator (`core/kinds`, also `config push --as components`)."""
    from panther_ops.core.kinds import FileKind, check_file

    check_file(FileKind.COMPONENTS, path, text.encode())


def add_ant02(text: str, path: str, entry: dict[str, str]) -> tuple[str, str]:
    """The file with the ANT02 entry (appended, or the existing ANT02 entry's keys set), and
    what was done. The result is validated."""
    doc = YamlDocument(text, path)
    validate_components(text, path)
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
    validate_components(doc.text, path)
    return doc.text, what
