"""The files a BT project pulled from a robot includes (`config pull bt-lights|bt-safety`).

A ``.btproj`` names its trees by ``<include path="..."/>``, relative to the including file
(BehaviorTree.CPP@4.x: src/xml_parsing.cpp, ``loadDocImpl``; ``ros_pkg`` includes are resolved
in a ROS package on the robot and are not copied). The pulled project is only usable (``bt
validate``, ``config push``) with those files beside it, at the same relative paths, from the
same source as the project: each is read through ``read`` (a relative name -> its content, None
when it is not there). An include that leaves the project's directory is not fetched: `config
push` refuses such a project too (`core.kinds.bt.project_files`).
"""

from __future__ import annotations

import posixpath
import xml.etree.ElementTree as ET
from collections.abc import Callable
from dataclasses import dataclass, field


@dataclass
class Includes:
    """What a pulled project includes."""

    files: dict[str, bytes] = field(default_factory=dict)
    """relative name (posix, inside the project's directory) -> content, in include order"""
    missing: list[str] = field(default_factory=list)
    """included but not found at the source"""
    refused: list[str] = field(default_factory=list)
    """include paths that leave the project's directory (or are not a path), not fetched"""


def include_name(including: str, rel: str) -> str | None:
    """``rel`` (from the file named ``including``) as a name inside the project's directory;
    None when it leaves it (absolute, ``~``, ``..`` out of it, control characters, empty)."""
    if not rel or rel.startswith(("/", "~")) or any(ord(c) < 32 for c in rel):
        return None
    name = posixpath.normpath(posixpath.join(posixpath.dirname(including), rel))
    if name in (".", "..") or name.startswith("../"):
        return None
    return name


def _includes_of(data: bytes) -> list[str]:
    """The ``path`` of each file include (not ``ros_pkg``) of one XML file; none when it is not
    XML without a DTD (a robot's file: no entity is expanded)."""
    if b"<!DOCTYPE" in data or b"<!ENTITY" in data:
        return []
    try:
        root = ET.fromstring(data)  # noqa: S314 - no DTD or entity (refused above)
    except ET.ParseError:
        return []
    return [inc.get("path") or "" for inc in root.iter("include") if not inc.get("ros_pkg")]


def pulled_includes(project: bytes, read: Callable[[str], bytes | None]) -> Includes:
    """Every file ``project`` includes, directly or through an included file, read by ``read``."""
    out = Includes()
    todo = [("", project)]
    while todo:
        including, data = todo.pop(0)
        for rel in _includes_of(data):
            name = include_name(including, rel)
            if name is None:
                out.refused.append(rel)
                continue
            if name in out.files or name in out.missing:
                continue
            got = read(name)
            if got is None:
                out.missing.append(name)
                continue
            out.files[name] = got
            todo.append((name, got))
    return out
