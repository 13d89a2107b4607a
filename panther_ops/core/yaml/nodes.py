"""Node positions of a YAML document: the read side of `YamlDocument`.

`YamlNodes` parses the text with ruamel.yaml's composer (YAML 1.2) and answers where each
node is written: character spans of values (without anchors and tags), the alias slots,
the ``<<`` merge sources, block-sequence dash columns, the file's indentation, and plain
Python views of the tree (merges resolved, or aliases kept as `AliasRef`). It never
changes the text; `panther_ops.core.yaml.document.YamlDocument` does.

Size (~500 lines): one class (`YamlNodes`) indexing one parsed text; its parts (spans,
merges, aliases, plain views) read the same index and would not stand alone.
"""

from __future__ import annotations

import builtins
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import date
from typing import Any, cast

from ruamel.yaml.error import MarkedYAMLError, YAMLError
from ruamel.yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode

from panther_ops.core.yaml.paths import DocumentError, PathError, PathPart, as_index, format_path
from panther_ops.core.yaml.render import (
    Indentation,
)
from panther_ops.core.yaml.tabs import tab_problem
from panther_ops.core.yaml.values import AliasRef, construct_scalar, plain_value, py_set, thread_parser

_MERGE_TAG = "tag:yaml.org,2002:merge"


_IdSet = set[int]  # `set` is a method name inside YamlDocument


MISSING: Any = object()


@dataclass(frozen=True)
class NodeInfo:
    """Where and how a value is written.

    Attributes:
        kind: ``scalar``, ``mapping``, ``sequence`` or ``alias``.
        style: scalars: None (plain), ``'``, ``"``, ``|``, ``>``; collections: ``flow`` or
            ``block``.
        start, end: character span of the value text (scalars: without anchor/tag; block
            scalars: the header through the last content character).
        line: 1-based line of the value.
        column: 0-based column.
        anchor: anchor defined on the value, if any.
        merged_from: the value is not in the mapping itself but inherited through ``<<``
            from this anchor.
    """

    kind: str
    style: str | None
    start: int
    end: int
    line: int
    column: int
    anchor: str | None
    merged_from: str | None = None
    raw: str = ""


MAX_EXPANDED_NODES = 100_000
"""Most nodes a document may hold once its aliases are expanded (an alias bomb is refused)."""


def _check_aliases(root: Node, path: str | None) -> None:
    """Refuse a recursive alias (a node inside itself) and a document whose aliases expand to
    more than MAX_EXPANDED_NODES nodes, before anything walks or converts it."""
    sizes: dict[int, int] = {}
    open_nodes: builtins.set[int] = builtins.set()

    def size(node: Node) -> int:
        if id(node) in sizes:
            return sizes[id(node)]
        if id(node) in open_nodes:
            raise DocumentError("recursive YAML alias (a node that contains itself)", path=path,
                                line=node.start_mark.line + 1 if node.start_mark else None)
        open_nodes.add(id(node))
        children: list[Node] = []
        if isinstance(node, MappingNode):
            children = [n for pair in node.value for n in pair]
        elif isinstance(node, SequenceNode):
            children = list(node.value)
        total = 1 + sum(size(c) for c in children)
        open_nodes.discard(id(node))
        if total > MAX_EXPANDED_NODES:
            raise DocumentError(f"the document expands to more than {MAX_EXPANDED_NODES} nodes (aliases expanded)",
                                path=path, line=node.start_mark.line + 1 if node.start_mark else None)
        sizes[id(node)] = total
        return total

    size(root)


def is_flow(node: Node) -> bool:
    return bool(getattr(node, "flow_style", False))


class YamlNodes:
    """Parsed view of a YAML text (positions, merges, aliases). Read-only."""

    path: str | None
    _text: str
    _root: Node | None
    _alias_slots: builtins.set[tuple[int, int]]
    _anchors: dict[str, Node]
    _indent: Indentation
    _original_scalars: dict[tuple[PathPart, ...], tuple[Any, str, str | None]]

    def anchor_path(self, anchor: str) -> tuple[PathPart, ...] | None:
        """Path of the value that defines ``&anchor`` (None when not defined)."""

        def walk(node: Node, here: tuple[PathPart, ...], seen: _IdSet) -> tuple[PathPart, ...] | None:
            if id(node) in seen:
                return None
            seen.add(id(node))
            if node.anchor == anchor:
                return here
            if isinstance(node, MappingNode):
                for k, v in node.value:
                    if isinstance(k, ScalarNode) and k.tag != _MERGE_TAG:
                        hit = walk(v, (*here, k.value), seen)
                        if hit is not None:
                            return hit
            elif isinstance(node, SequenceNode):
                for i, item in enumerate(node.value):
                    hit = walk(item, (*here, i), seen)
                    if hit is not None:
                        return hit
            return None

        return None if self._root is None else walk(self._root, (), builtins.set())

    # ----------------------------------------------------------- parse & index

    def _compose(self, text: str) -> Node | None:
        try:
            root = cast("Node | None", thread_parser().compose(text))
            if root is not None:
                _check_aliases(root, self.path)
            return root
        except RecursionError:
            raise DocumentError("invalid YAML: nested too deeply", path=self.path) from None
        except MarkedYAMLError as exc:
            mark = exc.problem_mark or exc.context_mark
            line = mark.line + 1 if mark is not None else None
            problem = tab_problem(text, mark) or exc.problem or exc.context or "invalid YAML"
            raise DocumentError(f"invalid YAML: {problem}", path=self.path, line=line) from exc
        except YAMLError as exc:
            raise DocumentError(f"invalid YAML: {exc}", path=self.path) from exc

    def _index(self) -> None:
        """Record alias slots and anchors; detect indentation; refuse duplicate keys."""
        self._alias_slots: builtins.set[tuple[int, int]] = builtins.set()
        self._anchors: dict[str, Node] = {}
        seen: _IdSet = builtins.set()
        map_steps: dict[int, int] = {}
        seq_offsets: dict[int, int] = {}

        def walk(node: Node) -> None:
            if id(node) in seen:
                return
            seen.add(id(node))
            if node.anchor:
                self._anchors[node.anchor] = node
            if isinstance(node, MappingNode):
                self._check_duplicates(node)
                for i, (k, v) in enumerate(node.value):
                    if id(v) in seen:
                        self._alias_slots.add((id(node), i))
                        continue
                    if not is_flow(node):
                        self._sample_indent(k, v, map_steps, seq_offsets)
                    walk(v)
            elif isinstance(node, SequenceNode):
                for i, item in enumerate(node.value):
                    if id(item) in seen:
                        self._alias_slots.add((id(node), i))
                        continue
                    walk(item)

        if self._root is not None:
            walk(self._root)
        mapping = max(map_steps, key=lambda s: (map_steps[s], -s)) if map_steps else 2
        offset = max(seq_offsets, key=lambda s: (seq_offsets[s], s)) if seq_offsets else 2
        self._indent = Indentation(mapping=mapping, offset=offset)

    def _check_duplicates(self, node: MappingNode) -> None:
        keys: dict[str, int] = {}
        for k, _v in node.value:
            if isinstance(k, ScalarNode) and k.tag != _MERGE_TAG:
                if k.value in keys:
                    raise DocumentError(
                        f"duplicate key {k.value!r} (first at line {keys[k.value]})",
                        path=self.path,
                        line=k.start_mark.line + 1,
                        key=k.value,
                    )
                keys[k.value] = k.start_mark.line + 1

    def _sample_indent(self, key: Node, value: Node, map_steps: dict[int, int], seq_offsets: dict[int, int]) -> None:
        """Count how a block collection under ``key`` is indented (for `Indentation`)."""
        if getattr(value, "flow_style", True) or not value.value:
            return
        col = key.start_mark.column
        if isinstance(value, MappingNode):
            step = value.value[0][0].start_mark.column - col
            if step > 0:
                map_steps[step] = map_steps.get(step, 0) + 1
        elif isinstance(value, SequenceNode):
            dash = self._dash_col(value.value[0])
            if dash is not None and dash >= col:
                seq_offsets[dash - col] = seq_offsets.get(dash - col, 0) + 1

    def _scalar_texts(self) -> dict[tuple[PathPart, ...], tuple[Any, str, str | None]]:
        """Own one-line scalars of the loaded text: path -> (value, text, style).

        Writing back a value a scalar had when loaded reuses its original text, so a change
        reverted is byte-identical again (``1.8e-3`` does not come back as ``0.0018``).
        """
        out: dict[tuple[PathPart, ...], tuple[Any, str, str | None]] = {}

        def walk(node: Node, path: tuple[PathPart, ...]) -> None:
            if isinstance(node, MappingNode):
                for i, (k, v) in enumerate(node.value):
                    if (id(node), i) not in self._alias_slots and isinstance(k, ScalarNode) and k.tag != _MERGE_TAG:
                        walk(v, (*path, k.value))
            elif isinstance(node, SequenceNode):
                for i, item in enumerate(node.value):
                    if (id(node), i) not in self._alias_slots:
                        walk(item, (*path, i))
            elif isinstance(node, ScalarNode) and node.style not in ("|", ">"):
                start, end = self._scalar_span(node)
                raw = self._text[start:end]
                if "\n" not in raw and start != end:
                    out[path] = (construct_scalar(node), raw, node.style)

        if self._root is not None:
            walk(self._root, ())
        return out

    def _dash_col(self, item: Node) -> int | None:
        pos = self._dash_pos(item.start_mark.index)
        if pos is None:
            return None
        return pos - (self._text.rfind("\n", 0, pos) + 1)

    def _dash_pos(self, item_start: int) -> int | None:
        """Position of the ``-`` introducing a block sequence item starting at ``item_start``."""
        i = item_start - 1
        text = self._text
        while i >= 0 and text[i] in " \t":
            i -= 1
        if i >= 0 and text[i] == "-":
            return i
        # the item may start on a later line ("-\n  key: v"); search backwards for the dash
        j = i
        while j >= 0 and text[j] in " \t\r\n":
            j -= 1
        return j if j >= 0 and text[j] == "-" else None

    # ------------------------------------------------------------- navigation

    def _root_found(self) -> tuple[Node, str | None, tuple[int, int]] | None:
        if self._root is None:
            return None
        return self._root, None, (self._root.start_mark.index, self._content_end(self._root))

    def _slot(self, node: Node, part: PathPart) -> int | None:
        """Index of the own entry/item for ``part`` in a collection node."""
        if isinstance(node, MappingNode):
            want = str(part)
            for i, (k, _v) in enumerate(node.value):
                if isinstance(k, ScalarNode) and k.tag != _MERGE_TAG and k.value == want:
                    return i
            return None
        if isinstance(node, SequenceNode):
            idx = as_index(part)
            if idx is None:
                return None
            if idx < 0:
                idx += len(node.value)
            return idx if 0 <= idx < len(node.value) else None
        return None

    def _merge_sources(self, node: MappingNode) -> list[MappingNode]:
        sources: list[MappingNode] = []
        for k, v in node.value:
            if isinstance(k, ScalarNode) and k.tag == _MERGE_TAG:
                if isinstance(v, MappingNode):
                    sources.append(v)
                elif isinstance(v, SequenceNode):
                    sources.extend(m for m in v.value if isinstance(m, MappingNode))
        return sources

    def _merged_lookup(self, node: MappingNode, part: PathPart) -> tuple[Node, str] | None:
        for source in self._merge_sources(node):
            slot = self._slot(source, part)
            if slot is not None:
                return source.value[slot][1], source.anchor or "?"
            deeper = self._merged_lookup(source, part)
            if deeper is not None:
                return deeper
        return None

    def _find(self, parts: Sequence[PathPart]) -> tuple[Node, str | None, tuple[int, int]] | None:
        """Node at ``parts``, the anchor it is inherited from (if any), and its text span."""
        found = self._root_found()
        if found is None:
            return None
        node, merged_from, span = found
        for part in parts:
            slot = self._slot(node, part)
            if slot is not None:
                if merged_from is None:
                    span = self._slot_span(node, slot)
                node = node.value[slot][1] if isinstance(node, MappingNode) else node.value[slot]
                if merged_from is not None:
                    span = (node.start_mark.index, self._content_end(node))
                continue
            if isinstance(node, MappingNode):
                inherited = self._merged_lookup(node, part)
                if inherited is not None:
                    node, anchor = inherited
                    merged_from = merged_from or anchor
                    span = (node.start_mark.index, self._content_end(node))
                    continue
            return None
        return node, merged_from, span

    def _is_alias_path(self, parts: Sequence[PathPart]) -> bool:
        """Whether some slot on the path is an alias (``*anchor``) occurrence."""
        node = self._root
        for part in parts:
            if node is None:
                return False
            slot = self._slot(node, part)
            if slot is None:
                return False
            if (id(node), slot) in self._alias_slots:
                return True
            node = node.value[slot][1] if isinstance(node, MappingNode) else node.value[slot]
        return False

    def _path_error(self, parts: Sequence[PathPart], what: str) -> PathError:
        line = None
        for n in range(len(parts) - 1, -1, -1):
            found = self._find(parts[:n])
            if found is not None:
                line = self._text.count("\n", 0, found[2][0]) + 1 if n else None
                break
        return PathError(f"{format_path(parts)}: {what}", path=self.path, line=line, key=format_path(parts))

    # ------------------------------------------------------------ plain views

    def _resolved(self, node: Node) -> Any:
        if isinstance(node, ScalarNode):
            return construct_scalar(node)
        if isinstance(node, SequenceNode):
            return [self._resolved(n) for n in node.value]
        out: dict[Any, Any] = {}
        for source in reversed(self._merge_sources(cast("MappingNode", node))):
            out.update(self._resolved(source))
        for k, v in node.value:
            if isinstance(k, ScalarNode) and k.tag == _MERGE_TAG:
                continue
            out[self._key(k)] = self._resolved(v)
        # own keys first, in file order, then inherited ones
        own = [self._key(k) for k, _ in node.value if not (isinstance(k, ScalarNode) and k.tag == _MERGE_TAG)]
        return {**{k: out[k] for k in own}, **{k: v for k, v in out.items() if k not in own}}

    def _key(self, node: Node) -> Any:
        if isinstance(node, ScalarNode):
            return node.value
        return repr(self._resolved(node))

    def _unresolved(self, node: Node | None, seen: _IdSet | None = None) -> Any:
        """Plain view with aliases as `AliasRef` (``<<`` kept as a key)."""
        if node is None:
            return None
        seen = builtins.set() if seen is None else seen
        if id(node) in seen:
            return AliasRef(node.anchor or "?")
        seen.add(id(node))
        if isinstance(node, ScalarNode):
            value = construct_scalar(node)
            return value.isoformat() if isinstance(value, date) else value
        if isinstance(node, SequenceNode):
            return [self._unresolved(n, seen) for n in node.value]
        out: dict[Any, Any] = {}
        for k, v in node.value:
            key = "<<" if isinstance(k, ScalarNode) and k.tag == _MERGE_TAG else self._key(k)
            out[key] = self._unresolved(v, seen)
        return out

    def _unresolved_with(self, parts: Sequence[PathPart], value: Any) -> Any:
        tree = self._unresolved(self._root)
        if tree is None:
            tree = {}
        py_set(tree, parts, plain_value(value))
        return tree

    # ----------------------------------------------------------- text geometry

    def _eol(self, pos: int) -> int:
        """Index just past the newline ending the line that contains ``pos - 1``."""
        j = self._text.find("\n", max(pos, 0))
        return len(self._text) if j < 0 else j + 1

    def _bol(self, pos: int) -> int:
        return self._text.rfind("\n", 0, pos) + 1

    def _colon_after(self, key: Node) -> int:
        """Index just past the ``:`` that follows a mapping key."""
        pos = key.end_mark.index
        j = self._text.find(":", pos)
        return j + 1 if j >= 0 else pos

    def _scalar_span(self, node: ScalarNode) -> tuple[int, int]:
        start, end = node.start_mark.index, node.end_mark.index
        text = self._text
        # skip an anchor (&a) and/or a tag (!!str) written before the scalar
        while start < end and text[start] in "&!":
            while start < end and text[start] not in " \t\r\n":
                start += 1
            while start < end and text[start] in " \t\r\n":
                start += 1
        if node.style in ("|", ">"):
            while end > start and text[end - 1] in " \t\r\n":
                end -= 1
        return start, end

    def _content_end(self, node: Node) -> int:
        """End (exclusive) of the last character that belongs to ``node``'s content."""
        if isinstance(node, ScalarNode):
            return self._scalar_span(node)[1]
        if is_flow(node) or not node.value:
            return cast("int", node.end_mark.index)
        last = len(node.value) - 1
        return self._slot_span(node, last)[1]

    def _slot_span(self, node: Node, slot: int) -> tuple[int, int]:
        """Text span of the value in a collection slot (alias token, empty value, ...)."""
        if isinstance(node, MappingNode):
            key, value = node.value[slot]
            after = self._colon_after(key)
        else:
            value = node.value[slot]
            after = self._slot_span(node, slot - 1)[1] if slot else node.start_mark.index + int(is_flow(node))
        if (id(node), slot) in self._alias_slots:
            token = "*" + (value.anchor or "")
            start = self._find_token(token, after)
            return start, start + len(token)
        if isinstance(value, ScalarNode) and value.tag == "tag:yaml.org,2002:null" and value.value == "":
            if isinstance(node, SequenceNode) and not is_flow(node):
                dash = self._find_token("-", after if slot else node.start_mark.index)
                return dash + 1, dash + 1
            return after, after
        if isinstance(value, ScalarNode):
            return self._scalar_span(value)
        return value.start_mark.index, self._content_end(value)

    def _find_token(self, token: str, pos: int) -> int:
        """First occurrence of ``token`` at or after ``pos`` outside comments."""
        text = self._text
        i = pos
        while i < len(text):
            if text.startswith(token, i):
                return i
            if text[i] == "#" and (i == 0 or text[i - 1] in " \t\n"):
                nl = text.find("\n", i)
                i = len(text) if nl < 0 else nl + 1
                continue
            i += 1
        raise DocumentError(f"internal: {token!r} not found after offset {pos}", path=self.path)

    def _in_flow(self, parts: Sequence[PathPart]) -> bool:
        node = self._root
        for part in parts:
            if node is None or isinstance(node, ScalarNode):
                return False
            if is_flow(node):
                return True
            slot = self._slot(node, part)
            if slot is None:
                return False
            node = node.value[slot][1] if isinstance(node, MappingNode) else node.value[slot]
        return False

    def _blank_separated(self, node: Node) -> bool:
        """Whether the last two entries of a block collection are separated by a blank line."""
        if len(node.value) < 2:
            return False
        prev_end = self._slot_span(node, len(node.value) - 2)[1]
        last_start = self._entry_start(node, len(node.value) - 1)
        between = self._text[self._eol(prev_end) : self._bol(last_start)]
        return any(not line.strip() for line in between.split("\n")[:-1]) if between else False

    def _entry_start(self, node: Node, slot: int) -> int:
        if isinstance(node, MappingNode):
            return cast("int", node.value[slot][0].start_mark.index)
        start = self._slot_span(node, slot)[0]
        dash = self._dash_pos(start)
        return dash if dash is not None else start
