"""Paths into a YAML document (``a.b[0].c``, ``a\\.b`` for a literal dot) and the errors that name them."""

from __future__ import annotations

import re
from collections.abc import Sequence

from panther_ops.errors import InputError

PathPart = str | int


PathLike = str | Sequence[PathPart]


class DocumentError(InputError):
    """A YAML document cannot be parsed, or cannot be edited as asked (names file and line)."""


class PathError(DocumentError):
    """A path does not exist in the document, or goes through a scalar."""


def parse_path(path: PathLike) -> tuple[PathPart, ...]:
    """Split a dotted path (``a.b[0].c``, ``a\\.b`` for a literal dot) into parts."""
    if not isinstance(path, str):
        return tuple(path)
    parts: list[PathPart] = []
    buf = ""
    i = 0
    while i < len(path):
        c = path[i]
        if c == "\\" and i + 1 < len(path):
            buf += path[i + 1]
            i += 2
            continue
        if c == ".":
            parts.append(buf)
            buf = ""
        elif c == "[":
            close = path.find("]", i)
            if close < 0:
                raise PathError(f"path {path!r}: unclosed '['")
            if buf:
                parts.append(buf)
                buf = ""
            parts.append(int(path[i + 1 : close]))
            i = close + 1
            if i < len(path) and path[i] == ".":
                i += 1
            continue
        else:
            buf += c
        i += 1
    if buf or (path and path[-1] == "."):
        parts.append(buf)
    return tuple(parts)


def format_path(parts: Sequence[PathPart]) -> str:
    out = ""
    for p in parts:
        if isinstance(p, int):
            out += f"[{p}]"
        else:
            out += ("." if out else "") + p.replace(".", "\\.")
    return out


def path_key(parts: Sequence[PathPart]) -> tuple[PathPart, ...]:
    """Normalise a path for `_original_scalars` (digit strings -> indices)."""
    out: list[PathPart] = []
    for part in parts:
        index = as_index(part) if isinstance(part, str) else None
        out.append(part if index is None else index)
    return tuple(out)


def as_index(part: PathPart) -> int | None:
    if isinstance(part, int):
        return part
    if re.fullmatch(r"-?[0-9]+", part):
        return int(part)
    return None
