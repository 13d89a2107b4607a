"""A semantic digest of a file: what the template check needs, not the file.

A YAML file becomes its *leaves*: every key path (``drive_controller.ros__parameters.
linear.x.max_velocity``; list items as ``[i]``) with the type of its value (``int``,
``float``, ``bool``, ``str``, ``null``; an empty mapping or list as ``map{}``/``list[]``)
and a 16-hex-digit sha256 of the typed value. An XML file (a BT project) the same way
(element paths ``root[0]/BehaviorTree[1]``, attributes ``@ID``, text ``#text``; comments and
layout ignored). Anything else is one leaf: the sha256 of its bytes.

Two digests are equal when the files are equal semantically: the same keys, the same
values of the same types (``2`` and ``2.0`` differ: ROS refuses an integer for a double
parameter). `diff` names each key path that differs and how, without either value: the
digests of upstream files are what the project keeps (tests/golden/upstream), so the
values themselves are not stored.
"""

from __future__ import annotations

import hashlib
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from typing import Any

Leaves = dict[str, tuple[str, str]]


def _hash(kind: str, canon: str) -> str:
    return hashlib.sha256(f"{kind}\0{canon}".encode()).hexdigest()[:16]


def _key(key: Any) -> str:
    if isinstance(key, str) and key and not any(c in key for c in ".[]\"") and key.strip() == key:
        return key
    return f"[{key!r}]"


def _join(prefix: str, key: Any) -> str:
    part = _key(key)
    if part.startswith("["):
        return prefix + part
    return f"{prefix}.{part}" if prefix else part


def _yaml_leaves(value: Any, prefix: str, out: Leaves) -> None:
    if isinstance(value, dict):
        if not value:
            out[prefix] = ("map{}", _hash("map", ""))
        for key, item in value.items():
            _yaml_leaves(item, _join(prefix, key), out)
        return
    if isinstance(value, list):
        if not value:
            out[prefix] = ("list[]", _hash("list", ""))
        for i, item in enumerate(value):
            _yaml_leaves(item, f"{prefix}[{i}]", out)
        return
    if isinstance(value, bool):
        out[prefix] = ("bool", _hash("bool", "true" if value else "false"))
    elif isinstance(value, int):
        out[prefix] = ("int", _hash("int", str(value)))
    elif isinstance(value, float):
        out[prefix] = ("float", _hash("float", repr(value)))
    elif value is None:
        out[prefix] = ("null", _hash("null", ""))
    else:
        out[prefix] = ("str", _hash("str", str(value)))


def _xml_leaves(element: ET.Element, prefix: str, out: Leaves) -> None:
    for name, value in sorted(element.attrib.items()):
        out[f"{prefix}@{name}"] = ("str", _hash("str", value))
    text = (element.text or "").strip()
    if text:
        out[f"{prefix}#text"] = ("str", _hash("str", text))
    counts: dict[str, int] = {}
    for child in element:
        if not isinstance(child.tag, str):  # a comment or processing instruction
            continue
        index = counts.get(child.tag, 0)
        counts[child.tag] = index + 1
        _xml_leaves(child, f"{prefix}/{child.tag}[{index}]", out)


_ORDERED = frozenset({"command", "entrypoint"})


def _compose_normal(value: Any, key: Any = None) -> Any:
    """A compose document as docker compose reads it: lists of strings (volumes, environment,
    devices...) are sets (except ``command``/``entrypoint``), and runs of white space in a
    string are one space (a folded ``command: >`` block equals the same command on one line)."""
    if isinstance(value, dict):
        return {k: _compose_normal(v, k) for k, v in value.items()}
    if isinstance(value, list):
        items = [_compose_normal(v) for v in value]
        if key not in _ORDERED and all(isinstance(i, str) for i in items):
            return sorted(items)
        return items
    if isinstance(value, str):
        return " ".join(value.split())
    return value


def compose_leaves(data: bytes) -> Leaves:
    """The leaves of a compose file, normalised (`_compose_normal`); a file that does not parse: its bytes."""
    from ruamel.yaml import YAML
    from ruamel.yaml.error import YAMLError

    out: Leaves = {}
    try:
        _yaml_leaves(_compose_normal(YAML(typ="safe", pure=True).load(data.decode())), "", out)
    except (YAMLError, UnicodeDecodeError, RecursionError):
        return {"": ("bytes", hashlib.sha256(data).hexdigest()[:16])}
    return out


def file_format(name: str) -> str:
    """``yaml``, ``xml`` (also ``.btproj``) or ``bytes``, from the file name."""
    if name.endswith((".yaml", ".yml")):
        return "yaml"
    if name.endswith((".xml", ".btproj")):
        return "xml"
    return "bytes"


def leaves(name: str, data: bytes) -> tuple[str, Leaves]:
    """The format and leaves of a file (a file that does not parse as its format is ``bytes``)."""
    fmt = file_format(name)
    out: Leaves = {}
    if fmt == "yaml":
        from ruamel.yaml import YAML
        from ruamel.yaml.error import YAMLError

        try:
            _yaml_leaves(YAML(typ="safe", pure=True).load(data.decode()), "", out)
            return fmt, out
        except (YAMLError, UnicodeDecodeError, RecursionError):
            out.clear()
    elif fmt == "xml":
        try:
            root = ET.fromstring(data)  # noqa: S314 - upstream's or the project's own file; no DTD used
            _xml_leaves(root, f"{root.tag}[0]", out)
            return fmt, out
        except ET.ParseError:
            out.clear()
    return "bytes", {"": ("bytes", hashlib.sha256(data).hexdigest()[:16])}


def sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


@dataclass(frozen=True)
class Difference:
    """One key path where a file differs from upstream's."""

    path: str
    what: str
    """``missing`` (upstream has it, the file not), ``extra`` (only the file), ``type``
    (``int`` where upstream has ``float``...), ``value``."""
    detail: str = ""

    def line(self) -> str:
        return f"{self.path or '(whole file)'}: {self.what}" + (f" ({self.detail})" if self.detail else "")


def diff(upstream: Leaves, ours: Leaves) -> list[Difference]:
    """Where ``ours`` differs from ``upstream`` (in upstream's key order, then our extra keys)."""
    out: list[Difference] = []
    for path, (kind, digest) in upstream.items():
        if path not in ours:
            out.append(Difference(path, "missing", f"upstream {kind}"))
            continue
        our_kind, our_digest = ours[path]
        if our_kind != kind:
            out.append(Difference(path, "type", f"upstream {kind}, ours {our_kind}"))
        elif our_digest != digest:
            out.append(Difference(path, "value", kind))
    out.extend(Difference(path, "extra", f"ours {kind}") for path, (kind, _) in ours.items() if path not in upstream)
    return out
