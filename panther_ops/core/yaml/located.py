"""Read small YAML files (inventories, hosts files) keeping line numbers for errors.

PyYAML's composer gives every node its position; mappings become :class:`LineDict`, which
remembers the line of each key, so an error can say ``fleet.yaml:14 [robots.r01.port]``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from panther_ops.core.yaml.tabs import tab_problem
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


MAX_NODES = 100_000
"""Most nodes a document may expand to, aliases expanded (an alias bomb is refused)."""


class _Budget:
    """Nodes left to build and the nodes being built (an alias to one of them is recursive)."""

    def __init__(self, path: str, limit: int) -> None:
        self.path = path
        self.left = limit
        self.open: set[int] = set()

    def enter(self, node: Any) -> None:
        if id(node) in self.open:
            raise InputError("recursive YAML alias (a node that contains itself)", path=self.path,
                             line=node.start_mark.line + 1, hint="aliases (*name) may only refer to "
                             "a complete node defined earlier, not to one of its own parents")
        self.left -= 1
        if self.left < 0:
            raise InputError(f"the document expands to more than {MAX_NODES} nodes (aliases expanded)",
                             path=self.path, line=node.start_mark.line + 1,
                             hint="an alias bomb? write the values out, or use fewer nested aliases")


def _build(node: Any, path: str, scalars: Any = None, budget: _Budget | None = None) -> Any:
    import yaml

    if scalars is None:
        scalars = yaml.SafeLoader("")
    if budget is None:
        budget = _Budget(path, MAX_NODES)
    budget.enter(node)
    if isinstance(node, (yaml.MappingNode, yaml.SequenceNode)):
        budget.open.add(id(node))
        try:
            return _build_collection(node, path, scalars, budget)
        finally:
            budget.open.discard(id(node))
    return scalars.construct_object(node, deep=True)


def _build_collection(node: Any, path: str, scalars: Any, budget: _Budget) -> Any:
    import yaml

    if isinstance(node, yaml.MappingNode):
        out = LineDict()
        out.line = node.start_mark.line + 1
        out.key_lines = {}
        for knode, vnode in node.value:
            if knode.tag == "tag:yaml.org,2002:merge":
                merged = _build(vnode, path, scalars, budget)
                sources = merged if isinstance(merged, list) else [merged]
                if not all(isinstance(m, LineDict) for m in sources):
                    raise InputError("a merge key (<<) takes a mapping or a list of mappings", path=path,
                                     line=knode.start_mark.line + 1)
                for m in sources:
                    for k, v in m.items():
                        out.setdefault(k, v)
                        out.key_lines.setdefault(k, m.line_of(k))
                continue
            key = _build(knode, path, scalars, budget)
            if not isinstance(key, (str, int, float, bool)):
                raise InputError("mapping keys must be plain scalars", path=path, line=knode.start_mark.line + 1)
            key = str(key)
            if key in out:
                raise InputError(f"duplicate key {key!r}", path=path, line=knode.start_mark.line + 1, key=key)
            out[key] = _build(vnode, path, scalars, budget)
            out.key_lines[key] = knode.start_mark.line + 1
        return out
    seq = LineList(_build(v, path, scalars, budget) for v in node.value)
    seq.line = node.start_mark.line + 1
    seq.item_lines = [v.start_mark.line + 1 for v in node.value]
    return seq


def as_located(value: Any, line: int = 0) -> Any:
    """Plain data (a document built in memory, e.g. from an Ansible inventory) as the located
    form :func:`load_yaml` gives, every line ``line`` (no file line to name)."""
    if isinstance(value, dict):
        out = LineDict((str(k), as_located(v, line)) for k, v in value.items())
        out.line, out.key_lines = line, {}
        return out
    if isinstance(value, list):
        seq = LineList(as_located(v, line) for v in value)
        seq.line, seq.item_lines = line, [line] * len(value)
        return seq
    return value


def load_yaml(text: str, path: str) -> Any:
    """Parse YAML text; syntax errors become :class:`InputError` naming file and line."""
    import yaml

    try:
        node = yaml.compose(text, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))  # libyaml where built
    except yaml.MarkedYAMLError as exc:
        line = exc.problem_mark.line + 1 if exc.problem_mark else None
        # the libyaml of PyYAML >= 6.0.4 stops at its own depth limit: the same refusal
        # as the RecursionError below, in the same words
        problem = "nested too deeply" if "nesting depth" in (exc.problem or "") else exc.problem
        problem = tab_problem(text, exc.problem_mark) or problem
        raise InputError(f"invalid YAML: {problem}", path=path, line=line) from None
    except yaml.YAMLError as exc:
        raise InputError(f"invalid YAML: {exc}", path=path) from None
    except RecursionError:
        raise InputError("invalid YAML: nested too deeply", path=path) from None
    if node is None:
        return None
    try:
        return _build(node, path)
    except yaml.constructor.ConstructorError as exc:
        line = exc.problem_mark.line + 1 if exc.problem_mark else None
        raise InputError(f"invalid value: {exc.problem}", path=path, line=line) from None
    except RecursionError:
        raise InputError("invalid YAML: nested too deeply", path=path) from None


def load_yaml_file(path: Path) -> Any:
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputError("file not found", path=str(path)) from None
    except UnicodeDecodeError:
        raise InputError("not a UTF-8 text file", path=str(path)) from None
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror or exc}", path=str(path)) from None
    return load_yaml(text, str(path))
