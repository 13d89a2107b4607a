"""What the validators share: reading the content as text and as plain YAML."""

from __future__ import annotations

from typing import Any

from panther_ops.core.kinds.registry import FileKindError


def text_of(source: str, data: bytes, what: str) -> str:
    """The content as UTF-8 text (a binary file is refused)."""
    try:
        text = data.decode()
    except UnicodeDecodeError:
        raise FileKindError(source, what, ["not a UTF-8 text file"]) from None
    if "\0" in text:
        raise FileKindError(source, what, ["not a text file (holds a NUL byte)"])
    return text


def load_yaml(source: str, data: bytes, what: str) -> Any:
    """The content as plain YAML values (ruamel, safe: no tags, no code)."""
    from ruamel.yaml import YAML
    from ruamel.yaml.error import YAMLError

    text = text_of(source, data, what)
    try:
        return YAML(typ="safe", pure=True).load(text)
    except YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        at = f" (line {mark.line + 1})" if mark is not None else ""
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise FileKindError(source, what, [f"not valid YAML{at}: {problem}"]) from None
    except RecursionError:
        raise FileKindError(source, what, ["not valid YAML: an alias refers to itself"]) from None


def load_mapping(source: str, data: bytes, what: str) -> dict[str, Any]:
    doc = load_yaml(source, data, what)
    if not isinstance(doc, dict):
        raise FileKindError(source, what, [f"must be a YAML mapping, not {type(doc).__name__}"])
    return doc


def is_float(value: Any) -> bool:
    return isinstance(value, float)


def is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)
