"""A YAML syntax error caused by a tab, named as one: both parsers only say "found character
that cannot start any token" (or a mapping that is not allowed here), never that it is a tab."""

from __future__ import annotations

from typing import Any


def tab_problem(text: str, mark: Any) -> str | None:
    """``tab character at line L col C; YAML indents with spaces`` when the line a parser
    stopped at (``mark``: its 0-based ``line``/``column``) holds a tab at or before the place it
    stopped, else None (the parser's own words stand)."""
    if mark is None:
        return None
    lines = text.splitlines()
    if not 0 <= mark.line < len(lines):
        return None
    line = lines[mark.line]
    col = line.find("\t")
    if col < 0 or col > max(mark.column, len(line) - len(line.lstrip(" \t"))):
        return None
    return f"tab character at line {mark.line + 1} col {col + 1}; YAML indents with spaces"
