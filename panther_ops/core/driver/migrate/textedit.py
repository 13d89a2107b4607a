"""Small in-place edits the translators make on a `YamlDocument` (every other byte kept).

The document editor sets, deletes and appends; a translation also needs a value written as
upstream writes it (``.NAN``, ``-2.7`` from ``2.7``), a key inserted right after another one
(``min_velocity`` after ``max_velocity``, as husarion_ugv 2.3 orders them), a key renamed in
place (``device_namespace`` -> ``name``) and upstream's own explanatory comment lines dropped
where they describe a 2.2 rule that no longer holds. Each edit goes through
`YamlDocument.replace_span`, which re-parses and refuses an edit that changes anything else.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from typing import Any

from panther_ops.core.yaml.document import PathPart, YamlDocument
from panther_ops.core.yaml.paths import DocumentError

Path = tuple[PathPart, ...]

_UNIT = re.compile(r"[ \t]+(#[ \t]*(?:m|rad)/s(?:\^[23])?)[ \t]*$")
"""A unit comment at the end of a line (``# m/s``, ``# rad/s^2``), as upstream's limits carry."""


def line_bounds(doc: YamlDocument, index: int) -> tuple[int, int]:
    """(start, end) of the line holding character ``index`` (end: before its newline)."""
    text = doc.text
    start = text.rfind("\n", 0, index) + 1
    end = text.find("\n", index)
    return start, len(text) if end < 0 else end


def raw(doc: YamlDocument, path: Path) -> str:
    """The value at ``path`` as written (a scalar's text)."""
    return doc.info(path).raw


def trailing_comment(doc: YamlDocument, path: Path) -> str:
    """The unit comment at the end of the value's line (``# m/s``), or "" (an operator's own
    comment stays on its own line, not copied)."""
    info = doc.info(path)
    _start, end = line_bounds(doc, info.end)
    m = _UNIT.search(doc.text[info.end:end])
    return m.group(1) if m else ""


def scalar(text: str) -> Any:
    """What a plain scalar written as ``text`` reads back as (``.NAN`` -> nan, ``-2.7`` -> -2.7)."""
    from ruamel.yaml import YAML

    return YAML(typ="safe", pure=True).load(f"- {text}" if text else "- ")[0]


def set_raw(doc: YamlDocument, path: Path, text: str) -> bool:
    """Write the scalar at ``path`` as ``text`` (its comment and everything else kept)."""
    info = doc.info(path)
    return doc.replace_span(info.start, info.end, text, path=path, expected=scalar(text))


def insert_after(doc: YamlDocument, after: Path, key: str, text: str, comment: str = "") -> None:
    """A new ``key: text`` line right after the entry at ``after`` (a scalar), at its column."""
    info = doc.info(after)
    start, end = line_bounds(doc, info.end)
    line = doc.text[start:end]
    col = len(line) - len(line.lstrip(" "))
    new = "\n" + " " * col + f"{key}: {text}" + (f" {comment}" if comment else "")
    parent = doc.get(after[:-1])
    doc.replace_span(end, end, new, path=after[:-1], expected={**parent, key: scalar(text)})


def insert_before(doc: YamlDocument, at: Path, key: str, text: str) -> None:
    """A new ``key: text`` line right before the entry at ``at`` (a scalar), at its column."""
    info = doc.info(at)
    start = doc.text.rfind("\n", 0, info.start) + 1
    line = doc.text[start:info.start]
    col = len(line) - len(line.lstrip(" "))
    parent = doc.get(at[:-1])
    doc.replace_span(start, start, " " * col + f"{key}: {text}\n", path=at[:-1], expected={**parent, key: scalar(text)})


def rename_key(doc: YamlDocument, path: Path, new: str) -> None:
    """Rename the mapping key at ``path`` (the last part) to ``new`` on its own line."""
    info = doc.info(path)
    start, _end = line_bounds(doc, info.start)
    head = doc.text[start:info.start]
    old = str(path[-1])
    m = re.search(rf"(?<![\w-]){re.escape(old)}(?=\s*:)", head)
    if m is None:
        raise DocumentError(f"cannot rename {old}: its key is not written plainly on the value's line",
                            path=doc.path, line=info.line)
    doc.replace_span(start + m.start(), start + m.end(), new, path=path[:-1])


def drop_comment_lines(text: str, comments: Iterable[str]) -> tuple[str, int]:
    """``text`` without the whole-line comments equal (stripped) to one of ``comments``;
    returns the text and how many lines went. Comments carry no value: nothing else changes."""
    wanted = set(comments)
    kept: list[str] = []
    dropped = 0
    for line in text.splitlines(keepends=True):
        if line.strip() in wanted:
            dropped += 1
            continue
        kept.append(line)
    return "".join(kept), dropped


def negated(number: str) -> str:
    """``2.7`` -> ``-2.7``, ``-2.7`` -> ``2.7``: the operator's own digits, sign flipped."""
    text = number.strip()
    if text.startswith("-"):
        return text[1:]
    return "-" + text.lstrip("+")
