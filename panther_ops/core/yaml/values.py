"""Plain Python values of a document: typed comparison, what a rendered value reads back as,
and edits of a plain tree by path (what every text edit is checked against)."""

from __future__ import annotations

import math
import threading
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from datetime import date
from typing import Any, cast

from ruamel.yaml import YAML
from ruamel.yaml.nodes import ScalarNode

from panther_ops.core.yaml.paths import PathError, PathPart, as_index
from panther_ops.core.yaml.render import (
    Alias,
    Block,
    Flow,
    Quoted,
    block_scalar_lines,
    is_collection,
)

# Only node positions and styles are needed (the text itself is kept), so the plain
# composer is enough: same YAML 1.2 resolution as round-trip mode, without comment tokens.
_local = threading.local()


def thread_parser() -> YAML:
    """A YAML instance of this thread: ruamel's are not safe to share between threads."""
    y = getattr(_local, "yaml", None)
    if y is None:
        y = _local.yaml = YAML(typ="safe", pure=True)
    return y


@dataclass(frozen=True)
class AliasRef:
    """An alias (``*anchor``) in the unresolved view of a document."""

    anchor: str


def same_value(a: Any, b: Any) -> bool:
    """Equality that tells bool from int and int from float (types matter to ROS params)."""
    if isinstance(a, bool) or isinstance(b, bool):
        return type(a) is type(b) and a == b
    if isinstance(a, float) and isinstance(b, float):
        return a == b or (math.isnan(a) and math.isnan(b))
    if isinstance(a, int | float) and isinstance(b, int | float):
        return type(a) is type(b) and a == b
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(same_value(a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(same_value(x, y) for x, y in zip(a, b, strict=True))
    return type(a) is type(b) and bool(a == b)


def plain_value(value: Any) -> Any:
    """A Python value as it reads back from YAML (tuples -> lists, markers -> content)."""
    if isinstance(value, Quoted):
        return value.text
    if isinstance(value, Block):
        return _block_value(value)
    if isinstance(value, Flow):
        return plain_value(value.value)
    if isinstance(value, Alias):
        return AliasRef(value.anchor)
    if isinstance(value, Mapping):
        return {k: plain_value(v) for k, v in value.items()}
    if is_collection(value):
        return [plain_value(v) for v in value]
    return value


def _block_value(value: Block) -> str:
    """The string a rendered block scalar reads back as (folding applied)."""
    header, lines = block_scalar_lines(value, 2)
    node = thread_parser().compose("k: " + header + "\n" + "\n".join(lines) + "\n")
    return cast("str", construct_scalar(node.value[0][1]))


def construct_scalar(node: ScalarNode) -> Any:
    tag = node.tag
    value = node.value.replace("\a", "") if node.style == ">" else node.value
    if tag == "tag:yaml.org,2002:null":
        return None
    if tag == "tag:yaml.org,2002:bool":
        return value.lower() == "true"
    if tag == "tag:yaml.org,2002:int":
        text = value.replace("_", "")
        try:
            return int(text, 0)
        except ValueError:
            return int(text, 10)
    if tag == "tag:yaml.org,2002:float":
        text = value.replace("_", "").lower()
        if text.endswith(".nan"):
            return math.nan
        if text.endswith(".inf"):
            return -math.inf if text.startswith("-") else math.inf
        return float(text)
    return value


def nest(rest: Sequence[PathPart], value: Any) -> Any:
    out = value
    for part in reversed(rest):
        if isinstance(part, int):
            raise PathError(f"cannot create a sequence index [{part}]; set the list instead")
        out = {part: out}
    return out


def py_set(tree: Any, parts: Sequence[PathPart], value: Any, *, allow_create: bool = True) -> None:
    node = tree
    for i, part in enumerate(parts):
        last = i == len(parts) - 1
        if isinstance(node, list):
            idx = as_index(part)
            if idx is None:
                raise TypeError(f"{part!r} is not an index")
            if idx == len(node) and last:
                node.append(plain_value(value))
                return
            if last:
                node[idx] = plain_value(value)
                return
            node = node[idx]
        elif isinstance(node, dict):
            key = _dict_key(node, part)
            if last:
                node[key] = plain_value(value)
                return
            if key not in node:
                if not allow_create:
                    raise KeyError(part)
                node[key] = {}
            node = node[key]
        else:
            raise TypeError("goes through a scalar")


def _dict_key(node: dict[Any, Any], part: PathPart) -> Any:
    if part in node:
        return part
    for k in node:
        if str(k) == str(part):
            return k
    return str(part) if isinstance(part, int) else part


def py_delete(tree: Any, part: PathPart) -> None:
    if isinstance(tree, list):
        idx = as_index(part)
        if idx is None:
            raise PathError(f"{part!r} is not an index")
        del tree[idx]
    elif isinstance(tree, dict):
        del tree[_dict_key(tree, part)]


def py_delete_path(tree: Any, parts: Sequence[PathPart]) -> None:
    node = tree
    for part in parts[:-1]:
        node = node[as_index(part) or 0] if isinstance(node, list) else node[_dict_key(node, part)]
    py_delete(node, parts[-1])


def normalise(value: Any) -> Any:
    """Make `same_value` comparisons insensitive to key order and date objects."""
    if isinstance(value, dict):
        return {str(k): normalise(v) for k, v in value.items()}
    if isinstance(value, list):
        return [normalise(v) for v in value]
    if isinstance(value, date):
        return value.isoformat()
    return value
