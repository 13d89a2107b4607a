"""A world SDF's ``<spherical_coordinates>`` (the NavSat origin; manual "Use of GPS in
Simulation"): read, and set latitude / longitude / elevation / heading with the file's own
formatting kept (only the element texts change; a missing element or block is inserted at
the indentation of its neighbours; a block or element inside an XML comment is not the one
Gazebo reads, and is left alone).

The file must be well-formed XML before the edit; after it, the whole file must pass the world
file kind's validator (`core/kinds/world.py`: surface_model EARTH_WGS84, every coordinate in
range, including the ones this edit did not change), and must read back as asked.
"""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from typing import Any

from panther_ops.core.kinds import FileKind, check_file
from panther_ops.core.kinds.world import FIELDS as ELEMENTS
from panther_ops.errors import InputError, UsageError

FIELDS = {option: tag for tag, (option, *_rest) in ELEMENTS.items()}
"""`sim world set` option name -> the element it sets."""
_LIMITS = {option: (low, high) for (option, low, high, _unit) in ELEMENTS.values()}
_BLOCK = re.compile(r"(?P<indent>[ \t]*)<spherical_coordinates>(?P<body>.*?)</spherical_coordinates>", re.S)
_COMMENT = re.compile(r"<!--.*?-->", re.S)
MANUAL = {"surface_model": "EARTH_WGS84", "world_frame_orientation": "ENU", "latitude_deg": "53.1978",
          "longitude_deg": "18.3732", "elevation": "0", "heading_deg": "0"}


def _parse(text: str, path: str) -> ET.Element:
    try:
        root = ET.fromstring(text)  # noqa: S314 - the operator's own file
    except ET.ParseError as exc:
        raise InputError(f"not well-formed XML: {exc}", path=path) from None
    if root.find(".//world") is None and root.tag != "world":
        raise InputError("no <world> element", path=path)
    return root


def read_coordinates(text: str, path: str) -> dict[str, Any]:
    root = _parse(text, path)
    block = root.find(".//spherical_coordinates")
    if block is None:
        return {"present": False}
    out: dict[str, Any] = {"present": True}
    for child in block:
        out[child.tag] = (child.text or "").strip()
    out["surface_model_ok"] = out.get("surface_model", "EARTH_WGS84") == "EARTH_WGS84"
    return out


def problems(text: str, path: str) -> list[str]:
    """What the world file kind's validator refuses in ``text`` (empty: nothing), for `show`."""
    from panther_ops.core.kinds import FileKindError

    try:
        check_file(FileKind.WORLD, path, text.encode())
    except FileKindError as exc:
        return exc.errors
    return []


def check_values(values: dict[str, float]) -> None:
    for key, value in values.items():
        lo, hi = _LIMITS[key]
        if not math.isfinite(value) or not lo <= value <= hi:
            raise UsageError(f"--{key} {value:g}: {lo:g} to {hi:g}")


def _fmt(value: float) -> str:
    return repr(float(value)).rstrip("0").rstrip(".") if "e" not in repr(float(value)) else f"{value:.9f}"


def _masked(text: str) -> str:
    """``text`` with its XML comments blanked (same length: positions stay those of ``text``)."""
    return _COMMENT.sub(lambda m: re.sub(r"[^\n]", " ", m.group()), text)


def set_coordinates(text: str, path: str, values: dict[str, float]) -> str:
    """The file with the given fields set (keys of FIELDS). Raises UsageError for a value out
    of range, InputError / FileKindError (exit 2) for a file that is not, or would not be,
    a valid world file."""
    check_values(values)
    _parse(text, path)
    m = _BLOCK.search(_masked(text))
    if m is None:
        text = _insert_block(text, path)
        m = _BLOCK.search(_masked(text))
        assert m is not None
    body, shown = text[m.start("body"):m.end("body")], m.group("body")
    for key, value in values.items():
        tag = FIELDS[key]
        field = re.search(rf"(<{tag}>)(\s*)([^<]*?)(\s*)(</{tag}>)", shown)
        if field is not None:
            new = _fmt(value)
            body = body[:field.start(3)] + new + body[field.end(3):]
            shown = shown[:field.start(3)] + new + shown[field.end(3):]
        else:
            last = re.search(r"\n([ \t]*)<[^/][^>]*>[^\n]*\n[ \t]*$", shown)
            indent = last.group(1) if last else m.group("indent") + "  "
            tail = re.search(r"\n[ \t]*$", shown)
            cut = tail.start() if tail else len(shown)
            added = f"\n{indent}<{tag}>{_fmt(value)}</{tag}>"
            body = body[:cut] + added + body[cut:]
            shown = shown[:cut] + added + shown[cut:]
    out = text[:m.start("body")] + body + text[m.end("body"):]
    _parse(out, path)
    check_file(FileKind.WORLD, path, out.encode())  # the whole file, the values not changed here included
    got = read_coordinates(out, path)
    wrong = [k for k, v in values.items() if got.get(FIELDS[k]) != _fmt(v)]
    if wrong:
        raise InputError(f"could not set {', '.join(FIELDS[k] for k in wrong)}: the file's <spherical_coordinates> "
                         "is not where panther-ops can edit it", path=path, key="spherical_coordinates")
    return out


def _insert_block(text: str, path: str) -> str:
    world = re.search(r"^([ \t]*)<world\b[^>]*>[^\n]*\n", _masked(text), re.M)
    if world is None:
        raise InputError("cannot place <spherical_coordinates>: no <world ...> line", path=path)
    inner = world.group(1) + "  "
    lines = [f"{inner}<spherical_coordinates>"]
    lines += [f"{inner}  <{k}>{v}</{k}>" for k, v in MANUAL.items()]
    lines.append(f"{inner}</spherical_coordinates>")
    return text[:world.end()] + "\n".join(lines) + "\n" + text[world.end():]
