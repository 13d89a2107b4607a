"""A Gazebo world SDF (simulation only; written by `sim world set`): well-formed XML with a
``<world>``, and its ``<spherical_coordinates>``, the NavSat origin (manual "Use of GPS in
Simulation"): ``surface_model`` EARTH_WGS84, ``latitude_deg`` -90..90, ``longitude_deg``
-180..180, ``elevation`` [m], ``heading_deg`` -360..360, each a decimal number in ASCII digits
(Gazebo reads them as doubles: ``53°11'52"N`` or ``５３.２`` is no latitude to it), each
element once.

The whole file is checked, the values an edit leaves as they were included: a latitude of
200 already in the file refuses the write that changes only the longitude, naming the key
and the fix.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from pathlib import Path

from panther_ops.core.kinds.common import text_of
from panther_ops.core.kinds.registry import FileKindError, Target

WHAT = "world file"
BLOCK = "spherical_coordinates"
SURFACE_MODEL = "EARTH_WGS84"
FIELDS: dict[str, tuple[str, float, float, str]] = {
    "latitude_deg": ("latitude", -90.0, 90.0, "decimal degrees"),
    "longitude_deg": ("longitude", -180.0, 180.0, "decimal degrees"),
    "elevation": ("elevation", -12000.0, 100000.0, "metres"),
    "heading_deg": ("heading", -360.0, 360.0, "degrees"),
}
"""Element -> (the `sim world set` option that sets it, lowest, highest, unit)."""

_DMS = re.compile(
    r"""\s*(?P<d>[0-9]+(?:\.[0-9]+)?)\s*(?:°|º|deg|d)\s*
        (?:(?P<m>[0-9]+(?:\.[0-9]+)?)\s*(?:'|′|m)\s*)?
        (?:(?P<s>[0-9]+(?:\.[0-9]+)?)\s*(?:"|″|''|s)\s*)?
        (?P<h>[NSEW])?\s*""", re.ASCII | re.VERBOSE | re.IGNORECASE)


def dms_degrees(text: str) -> float | None:
    """``53°11'52"N`` (degrees, minutes, seconds and a hemisphere) as decimal degrees; None
    when ``text`` is not written that way."""
    m = _DMS.fullmatch(text)
    if m is None:
        return None
    value = float(m["d"]) + float(m["m"] or 0) / 60 + float(m["s"] or 0) / 3600
    return -value if (m["h"] or "").upper() in ("S", "W") else value


def check_world(source: str, data: bytes, local: Path | None, target: Target, force: bool) -> list[str]:
    """The world file kind's validator: FileKindError naming every bad key and its fix."""
    text = text_of(source, data, WHAT)
    if "<!ENTITY" in text:
        raise FileKindError(source, WHAT, ["holds an <!ENTITY> declaration (Gazebo's SDF reader takes none)"])
    try:
        root = ET.fromstring(text)  # noqa: S314 - no entities (refused above): nothing to expand
    except ET.ParseError as exc:
        raise FileKindError(source, WHAT, [f"not well-formed XML: {exc}"]) from None
    worlds = [root] if root.tag == "world" else root.findall(".//world")
    if not worlds:
        raise FileKindError(source, WHAT, ["no <world> element"])
    errors: list[str] = []
    for world in worlds:
        blocks = world.findall(BLOCK)
        if len(blocks) > 1:
            errors.append(f"{BLOCK}: {len(blocks)} blocks in <world name={world.get('name', '')!r}>; Gazebo reads "
                          "one: keep one")
        for block in blocks[:1]:
            errors += _check_block(source, block)
    if errors:
        raise FileKindError(source, WHAT, errors)
    return []


def _check_block(source: str, block: ET.Element) -> list[str]:
    errors: list[str] = []
    seen: set[str] = set()
    for child in block:
        if child.tag in seen and child.tag in (*FIELDS, "surface_model"):
            errors.append(f"{BLOCK}.{child.tag}: given twice; keep one")
        seen.add(child.tag)
    model = block.find("surface_model")
    if model is not None and (model.text or "").strip() != SURFACE_MODEL:
        errors.append(f"{BLOCK}.surface_model={(model.text or '').strip()!r}: NavSat needs {SURFACE_MODEL}; "
                      f"fix: <surface_model>{SURFACE_MODEL}</surface_model>")
    for tag, (option, low, high, unit) in FIELDS.items():
        element = block.find(tag)
        if element is not None:
            problem = _field_problem(source, tag, (element.text or "").strip(), option, low, high, unit)
            if problem:
                errors.append(problem)
    return errors


def _field_problem(source: str, tag: str, text: str, option: str, low: float, high: float, unit: str) -> str | None:
    from panther_ops.core.parse.numbers import NumberError, decimal

    try:
        decimal(text, low, high)
        return None
    except NumberError as exc:
        why = str(exc)
    fix = f"panther-ops sim world set {source} --{option} VALUE"
    if unit == "decimal degrees":
        converted = dms_degrees(text)
        if converted is not None and low <= converted <= high:
            return (f"{BLOCK}.{tag}={text!r} is degrees, minutes and seconds: Gazebo reads {unit}; "
                    f"fix: panther-ops sim world set {source} --{option} {converted:.6f}")
    return f"{BLOCK}.{tag}={text!r} is not {why} ({unit}); fix: {fix}"
