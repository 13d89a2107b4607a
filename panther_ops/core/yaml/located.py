"""Read small YAML files (inventories, hosts files) keeping line numbers for errors.

PyYAML's composer gives every node its position; mappings become :class:`LineDict`, which
remembers the line of each key, so an error can say ``fleet.yaml:14 [robots.r01.port]``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from panther_ops.errors import InputError


class LineDict(dict[str, Any]):
    """A mapping that knows the 1-based line of itself and of each of its keys."""

    line: int = 0
    key_lines: dict[str, int]

    def line_of(self, key: str) -> int:
        return self.key_lines.get(key, self.line)


class LineList(list[Any]):
    line: int = 0
    item_lines: list[int]


def _build(node: Any, path: str, scalars: Any = None) -> Any:
    import yaml

    if scalars is None:
        scalars = yaml.SafeLoader("")
    if isinstance(node, yaml.MappingNode):
        out = LineDict()
        out.line = node.start_mark.line + 1
        out.key_lines = {}
        for knode, vnode in node.value:
            if knode.tag == "tag:yaml.org,2002:merge":
                merged = _build(vnode, path, scalars)
                for m in merged if isinstance(merged, list) else [merged]:
                    for k, v in m.items():
                        out.setdefault(k, v)
                        out.key_lines.setdefault(k, m.line_of(k))
                continue
            key = _build(knode, path, scalars)
            if not isinstance(key, (str, int, float, bool)):
                raise InputError("mapping keys must be plain scalars", path=path, line=knode.start_mark.line + 1)
            key = str(key)
            if key in out:
                raise InputError(f"duplicate key {key!r}", path=path, line=knode.start_mark.line + 1, key=key)
            out[key] = _build(vnode, path, scalars)
            out.key_lines[key] = knode.start_mark.line + 1
        return out
    if isinstance(node, yaml.SequenceNode):
        seq = LineList(_build(v, path, scalars) for v in node.value)
        seq.line = node.start_mark.line + 1
        seq.item_lines = [v.start_mark.line + 1 for v in node.value]
        return seq
    return scalars.construct_object(node, deep=True)


def load_yaml(text: str, path: str) -> Any:
    """Parse YAML text; syntax errors become :class:`InputError` naming file and line."""
    import yaml

    try:
        node = yaml.compose(text, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))  # libyaml where built
    except yaml.MarkedYAMLError as exc:
        line = exc.problem_mark.line + 1 if exc.problem_mark else None
        raise InputError(f"invalid YAML: {exc.problem}", path=path, line=line) from None
    except yaml.YAMLError as exc:
        raise InputError(f"invalid YAML: {exc}", path=path) from None
    if node is None:
        return None
    try:
        return _build(node, path)
    except yaml.constructor.ConstructorError as exc:
        line = exc.problem_mark.line + 1 if exc.problem_mark else None
        raise InputError(f"invalid value: {exc.problem}", path=path, line=line) from None


def load_yaml_file(path: Path) -> Any:
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputError("file not found", path=str(path)) from None
    except UnicodeDecodeError:
        raise InputError("not a UTF-8 text file", path=str(path)) from None
    return load_yaml(text, str(path))
