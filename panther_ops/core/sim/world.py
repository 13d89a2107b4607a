"""A world SDF's ``<spherical_coordinates>`` (the NavSat origin; manual "Use of GPS in
Simulation"): read, and set latitude / longitude / elevation / heading with the file's own
formatting kept (only the element texts change; a missing element or block is inserted at
the indentation of its neighbours). ``surface_model`` must be EARTH_WGS84.

The file must stay well-formed XML (checked before and after every edit).
"""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from typing import Any

from panther_ops.errors import InputError, UsageError

FIELDS = {"latitude": "latitude_deg", "longitude": "longitude_deg", "elevation": "elevation", "heading": "heading_deg"}
_LIMITS = {"latitude": (-90.0, 90.0), "longitude": (-180.0, 180.0), "heading": (-360.0, 360.0),
           "elevation": (-12000.0, 100000.0)}
_BLOCK = re.compile(r"(?P<indent>[ \t]*)<spherical_coordinates>(?P<body>.*?)</spherical_coordinates>", re.S)
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


def check_values(values: dict[str, float]) -> None:
    for key, value in values.items():
        lo, hi = _LIMITS[key]
        if not math.isfinite(value) or not lo <= value <= hi:
            raise UsageError(f"--{key} {value:g}: {lo:g} to {hi:g}")


def _fmt(value: float) -> str:
    return repr(float(value)).rstrip("0").rstrip(".") if "e" not in repr(float(value)) else f"{value:.9f}"


def set_coordinates(text: str, path: str, values: dict[str, float]) -> str:
    """The file with the given fields set (keys of FIELDS)."""
    check_values(values)
    _parse(text, path)
    m = _BLOCK.search(text)
    if m is None:
        text = _insert_block(text, path)
        m = _BLOCK.search(text)
        assert m is not None
    body = m.group("body")
    model = re.search(r"<surface_model>\s*([^<]*?)\s*</surface_model>", body)
    if model is not None and model.group(1) != "EARTH_WGS84":
        raise InputError(f"surface_model {model.group(1)!r}: NavSat needs EARTH_WGS84", path=path,
                         key="spherical_coordinates.surface_model")
    for key, value in values.items():
        tag = FIELDS[key]
        field = re.search(rf"(<{tag}>)(\s*)([^<]*?)(\s*)(</{tag}>)", body)
        if field is not None:
            body = body[:field.start(3)] + _fmt(value) + body[field.end(3):]
        else:
            last = re.search(r"\n([ \t]*)<[^/][^>]*>[^\n]*\n[ \t]*$", body)
            indent = last.group(1) if last else m.group("indent") + "  "
            tail = re.search(r"\n[ \t]*$", body)
            cut = tail.start() if tail else len(body)
            body = body[:cut] + f"\n{indent}<{tag}>{_fmt(value)}</{tag}>" + body[cut:]
    out = text[:m.start("body")] + body + text[m.end("body"):]
    _parse(out, path)
    return out


def _insert_block(text: str, path: str) -> str:
    world = re.search(r"^([ \t]*)<world\b[^>]*>[^\n]*\n", text, re.M)
    if world is None:
        raise InputError("cannot place <spherical_coordinates>: no <world ...> line", path=path)
    inner = world.group(1) + "  "
    lines = [f"{inner}<spherical_coordinates>"]
    lines += [f"{inner}  <{k}>{v}</{k}>" for k, v in MANUAL.items()]
    lines.append(f"{inner}</spherical_coordinates>")
    return text[:world.end()] + "\n".join(lines) + "\n" + text[world.end():]
