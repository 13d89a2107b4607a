"""Render Python values as YAML text for surgical insertion into an existing document.

`YamlDocument` never re-emits a whole file: it splices small rendered fragments into the
original text. This module produces those fragments: scalars (keeping the quoting style of
the value they replace), block mappings and sequences at a given column with the
indentation detected from the file, and flow collections for flow contexts.

Markers let a caller choose a style for a new value: `Block` scalars (``|`` or ``>``),
`Quoted` scalars, `Flow` collections and `Alias` (``*anchor``, e.g. the value of ``<<``).
"""

from __future__ import annotations

import json
import math
import re
import threading
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

from ruamel.yaml import YAML
from ruamel.yaml.error import YAMLError


@dataclass(frozen=True)
class Indentation:
    """How a file indents block collections.

    Attributes:
        mapping: spaces from a key to the keys of its nested mapping (compose files: 2).
        offset: spaces from a key to the ``-`` of its block sequence items (2 when the
            dashes are indented under their key, 0 when they sit at the key's column).
    """

    mapping: int = 2
    offset: int = 2


@dataclass(frozen=True)
class Block:
    """A string to write as a block scalar: ``style`` ``|`` (literal: one output line per line of
    text) or ``>`` (folded: its lines are folded into one when read)."""

    text: str
    style: str = "|"

    def __post_init__(self) -> None:
        if self.style not in ("|", ">"):
            raise ValueError(f"a block scalar's style is '|' or '>', not {self.style!r}")


@dataclass(frozen=True)
class Quoted:
    """A string to write quoted: ``quote`` is ``'`` or ``"``."""

    text: str
    quote: str = "'"


@dataclass(frozen=True)
class Flow:
    """A list or mapping to write in flow style (``[a, b]`` / ``{k: v}``)."""

    value: Sequence[Any] | Mapping[Any, Any]


@dataclass(frozen=True)
class Alias:
    """A reference to an anchor, written ``*anchor`` (use as the value of ``<<``)."""

    anchor: str


Marker = Block | Quoted | Flow | Alias

# YAML 1.1 readers (PyYAML, some tools) take these plain scalars as bool/null/number/sexagesimal.
_YAML11_SPECIAL = re.compile(
    r"""^(?:y|Y|yes|Yes|YES|n|N|no|No|NO|on|On|ON|off|Off|OFF|~
    |[-+]?0[0-7_]+|[-+]?0b[01_]+|[-+]?0x[0-9a-fA-F_]+
    |[-+]?[0-9][0-9_]*(?::[0-5]?[0-9])+(?:\.[0-9_]*)?
    |[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN)
    |[-+]?(?:[0-9][0-9_]*)?\.[0-9_]*(?:[eE][-+]?[0-9]+)?)$""",
    re.VERBOSE,
)
_CONTROL = re.compile(r"[\x00-\x08\x0a-\x1f\x7f\x85\u2028\u2029]")
_local = threading.local()


def _parser() -> YAML:
    """A YAML instance of this thread: ruamel's are not safe to share between threads."""
    y = getattr(_local, "yaml", None)
    if y is None:
        y = _local.yaml = YAML(typ="rt")
    return y


@lru_cache(maxsize=4096)
def plain_ok(text: str, flow: bool = False) -> bool:
    """Whether ``text`` can be written as a plain scalar and read back as that same string.

    Checked with the YAML 1.2 parser in use and, to stay safe for YAML 1.1 readers, against
    the 1.1 booleans (``yes``/``on``...), nulls, octals and sexagesimals.
    """
    if not text or text != text.strip() or _CONTROL.search(text) or "\t" in text:
        return False
    if _YAML11_SPECIAL.match(text):
        return False
    if flow and any(c in text for c in ",[]{}"):
        return False
    probe = f"[{text}]" if flow else f"- {text}"
    try:
        node = _parser().compose(probe)
    except YAMLError:
        return False
    if node is None or len(node.value) != 1:
        return False
    item = node.value[0]
    return bool(
        item.tag == "tag:yaml.org,2002:str" and item.style is None and item.value == text
    )


def format_float(value: float) -> str:
    """A float as YAML that every reader takes as a float (always a ``.``; ``.nan``/``.inf``)."""
    if math.isnan(value):
        return ".nan"
    if math.isinf(value):
        return ".inf" if value > 0 else "-.inf"
    text = repr(value)
    if "e" in text or "E" in text:
        mantissa, _, exponent = text.lower().partition("e")
        if "." not in mantissa:
            mantissa += ".0"
        if exponent[0] not in "+-":
            exponent = "+" + exponent
        return f"{mantissa}e{exponent}"
    if "." not in text:
        text += ".0"
    return text


def quote_single(text: str) -> str:
    return "'" + text.replace("'", "''") + "'"


def quote_double(text: str) -> str:
    return json.dumps(text, ensure_ascii=False)


def render_scalar(value: Any, *, style: str | None = None, raw: str = "", flow: bool = False) -> str:
    """Render a scalar.

    Args:
        value: str, int, float, bool or None (or a `Quoted` / `Alias` marker).
        style: style of the scalar being replaced (None = plain, ``'``, ``"``); a quoted
            original stays quoted with the same quote character.
        raw: original text of the scalar being replaced; keeps the case of booleans
            (``True`` stays capitalised) and ``~``/``null`` spelling.
        flow: the scalar sits inside a flow collection (``[...]`` / ``{...}``).
    """
    if isinstance(value, Alias):
        return "*" + value.anchor
    if isinstance(value, Quoted):
        return quote_double(value.text) if value.quote == '"' else _single_or_double(value.text)
    if value is None:
        return raw if raw in ("~", "null", "Null", "NULL") else "null"
    if isinstance(value, bool):
        word = "true" if value else "false"
        if raw[:1].isupper():
            return word.upper() if raw.isupper() and len(raw) > 1 else word.capitalize()
        return word
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return format_float(value)
    if not isinstance(value, str):
        raise TypeError(f"cannot write a {type(value).__name__} as a YAML scalar")
    if style == '"':
        return quote_double(value)
    if style == "'":
        return _single_or_double(value)
    if plain_ok(value, flow):
        return value
    return _single_or_double(value)


def _single_or_double(text: str) -> str:
    if _CONTROL.search(text) or "\t" in text:
        return quote_double(text)
    return quote_single(text)


def is_collection(value: Any) -> bool:
    """A mapping or a list/tuple (not a string), possibly wrapped in `Flow`."""
    if isinstance(value, Flow):
        return True
    return isinstance(value, Mapping) or (
        isinstance(value, Sequence) and not isinstance(value, str | bytes)
    )


def render_key(key: Any) -> str:
    if key == "<<":
        return "<<"
    if isinstance(key, str):
        return render_scalar(key)
    return render_scalar(key)


def render_flow(value: Any) -> str:
    """A value in flow style on one line."""
    if isinstance(value, Flow):
        value = value.value
    if isinstance(value, Mapping):
        inner = ", ".join(f"{render_key(k)}: {render_flow(v)}" for k, v in value.items())
        return "{" + inner + "}"
    if is_collection(value):
        return "[" + ", ".join(render_flow(v) for v in value) + "]"
    if isinstance(value, Block):
        return render_scalar(value.text, flow=True)
    return render_scalar(value, flow=True)


def render_inline(value: Any, *, style: str | None = None, raw: str = "", flow: bool = False) -> str | None:
    """A one-line rendering of ``value``, or None when it needs block lines."""
    if isinstance(value, Block):
        return None
    if isinstance(value, Flow) or flow:
        return render_flow(value)
    if is_collection(value):
        return "{}" if isinstance(value, Mapping) and not value else (
            "[]" if not isinstance(value, Mapping) and not value else None
        )
    return render_scalar(value, style=style, raw=raw)


def block_scalar_lines(value: Block, col: int) -> tuple[str, list[str]]:
    """Header (``>``, ``>-``, ``|``...) and content lines (at ``col``) of a block scalar."""
    text = value.text
    chomp = "" if text.endswith("\n") else "-"
    body = text[:-1] if text.endswith("\n") else text
    pad = " " * col
    lines = [pad + line if line else "" for line in body.split("\n")]
    return value.style + chomp, lines


def render_value_lines(value: Any, col: int, ind: Indentation) -> list[str]:
    """Block lines of a non-empty mapping or list whose parent key sits at ``col``."""
    if isinstance(value, Mapping):
        lines: list[str] = []
        for k, v in value.items():
            lines.extend(render_entry(k, v, col + ind.mapping, ind))
        return lines
    lines = []
    for item in value:
        lines.extend(render_item(item, col + ind.offset, ind))
    return lines


def render_entry(key: Any, value: Any, col: int, ind: Indentation) -> list[str]:
    """Lines of ``key: value`` with the key at ``col``."""
    head = " " * col + render_key(key) + ":"
    if isinstance(value, Block):
        header, body = block_scalar_lines(value, col + ind.mapping)
        return [f"{head} {header}", *body]
    inline = render_inline(value)
    if inline is not None:
        return [f"{head} {inline}"]
    return [head, *render_value_lines(value, col, ind)]


def render_item(value: Any, dash_col: int, ind: Indentation) -> list[str]:
    """Lines of a block sequence item ``- value`` with the dash at ``dash_col``."""
    prefix = " " * dash_col + "- "
    content_col = dash_col + 2
    if isinstance(value, Block):
        header, body = block_scalar_lines(value, content_col)
        return [prefix + header, *body]
    inline = render_inline(value)
    if inline is not None:
        return [prefix + inline]
    if isinstance(value, Mapping):
        lines: list[str] = []
        for k, v in value.items():
            lines.extend(render_entry(k, v, content_col, ind))
    else:
        lines = []
        for item in value:
            lines.extend(render_item(item, content_col, ind))
    lines[0] = prefix + lines[0][content_col:]
    return lines


def render_document(data: Mapping[str, Any], ind: Indentation | None = None) -> str:
    """A whole YAML document for a mapping (block style), ending with a newline."""
    ind = ind or Indentation()
    lines: list[str] = []
    for k, v in data.items():
        lines.extend(render_entry(k, v, 0, ind))
    return "\n".join(lines) + "\n" if lines else "{}\n"
