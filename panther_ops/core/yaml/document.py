"""Round-trip YAML documents edited in place: every byte not edited stays as it was.

`YamlDocument` parses the text with ruamel.yaml (round-trip composer, YAML 1.2) only to
learn where each node lives (line, column, character span, quoting style, anchors, merge
keys). Edits are then spliced into the original text: replacing a value rewrites exactly
that scalar, adding a key inserts its lines after the last entry of the mapping at the
mapping's own column, deleting removes exactly the lines of the entry. Comments, key order,
quoting, flow/block style, anchors, merge keys (``<<: *common``), blank lines and
indentation of the rest of the file are therefore byte-identical, and nothing is re-wrapped.

After each edit the new text is parsed again and compared with what the edit should have
produced (the whole document, with aliases kept as references); an edit that would change
anything else is refused with `DocumentError` and the text is left untouched.

Merge keys: `get` resolves ``<<`` like YAML does. `set` (and `append`, `delete`) never
write through a merge: editing ``services.panther_ros.environment`` when the service only
inherits ``environment`` from ``<<: *common-config`` creates an explicit ``environment``
key in the service (a copy of the inherited value with the edit applied) and leaves the
anchor as it was; `notes` records it. To change the shared value, edit the anchor's own
path (e.g. ``x-common-config.environment``).

Paths are dotted strings (``services.panther_ros.image``, ``hosts.0.ip``, ``a.list[2]``;
escape a literal dot as ``\\.``) or sequences of keys and indices
(``("/**", "drive_controller", "ros__parameters")``).

Size (~750 lines, over the house's ~400): one class, the editor, whose every method keeps one
invariant (the text and the node positions read from it agree after each splice); its read
side is already apart (`nodes.py`), and so are paths (`paths.py`), plain values (`values.py`)
and rendering (`render.py`). Splitting the edit engine further would spread that invariant.
"""

from __future__ import annotations

import copy
from collections.abc import Callable, Mapping, Sequence
from typing import Any, cast

from ruamel.yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode

from panther_ops.core.yaml.nodes import MISSING, NodeInfo, YamlNodes, is_flow
from panther_ops.core.yaml.paths import (
    DocumentError,
    PathError,
    PathLike,
    PathPart,
    as_index,
    format_path,
    parse_path,
    path_key,
)
from panther_ops.core.yaml.render import (
    Alias,
    Block,
    Flow,
    Indentation,
    Quoted,
    block_scalar_lines,
    is_collection,
    render_entry,
    render_inline,
    render_item,
    render_scalar,
    render_value_lines,
)
from panther_ops.core.yaml.values import (
    AliasRef,
    nest,
    normalise,
    plain_value,
    py_delete,
    py_delete_path,
    py_set,
    same_value,
)

__all__ = [
    "Alias",
    "AliasRef",
    "Block",
    "DocumentError",
    "Flow",
    "Indentation",
    "NodeInfo",
    "PathError",
    "PathLike",
    "PathPart",
    "Quoted",
    "YamlDocument",
    "format_path",
    "parse_path",
]


class YamlDocument(YamlNodes):
    """A YAML document (one per file) that is edited in place. See the module docstring."""

    def __init__(self, text: str, path: str | None = None) -> None:
        self.path = path
        self.original = text
        self.notes: list[str] = []
        self._text = text
        self._root = self._compose(text)
        self._index()
        self._original_scalars = self._scalar_texts()

    @classmethod
    def load(cls, text: str, path: str | None = None) -> YamlDocument:
        return cls(text, path)

    # ----------------------------------------------------------------- reading

    @property
    def text(self) -> str:
        """The current text (the original text plus the edits made so far)."""
        return self._text

    def dump(self) -> str:
        return self._text

    @property
    def changed(self) -> bool:
        return self._text != self.original

    @property
    def indentation(self) -> Indentation:
        return self._indent

    def to_plain(self) -> Any:
        """The whole document as plain Python values, merges and aliases resolved."""
        return None if self._root is None else self._resolved(self._root)

    def get(self, path: PathLike, default: Any = MISSING) -> Any:
        """The value at ``path`` as plain Python (merges resolved).

        Raises:
            PathError: the path does not exist and no ``default`` was given.
        """
        found = self._find(parse_path(path))
        if found is None:
            if default is MISSING:
                raise self._path_error(parse_path(path), "not found")
            return default
        return self._resolved(found[0])

    def exists(self, path: PathLike) -> bool:
        return self._find(parse_path(path)) is not None

    def info(self, path: PathLike) -> NodeInfo:
        """Where and how the value at ``path`` is written (see `NodeInfo`)."""
        parts = parse_path(path)
        found = self._find(parts)
        if found is None:
            raise self._path_error(parts, "not found")
        node, merged_from, span = found
        start, end = span
        if isinstance(node, ScalarNode):
            kind, style = "scalar", node.style
        else:
            kind = "mapping" if isinstance(node, MappingNode) else "sequence"
            style = "flow" if is_flow(node) else "block"
        if self._text[start : start + 1] == "*":
            kind = "alias"
        line = self._text.count("\n", 0, start) + 1
        column = start - (self._text.rfind("\n", 0, start) + 1)
        return NodeInfo(
            kind=kind,
            style=style,
            start=start,
            end=end,
            line=line,
            column=column,
            anchor=node.anchor if kind != "alias" else None,
            merged_from=merged_from,
            raw=self._text[start:end],
        )

    def line_of(self, path: PathLike) -> int | None:
        """1-based line of the value at ``path`` (None if it does not exist)."""
        try:
            return self.info(path).line
        except PathError:
            return None

    def origin(self, path: PathLike) -> str | None:
        """``own``, ``merged:<anchor>``, or None when the path does not exist.

        ``merged`` means some key on the path is inherited through ``<<``.
        """
        found = self._find(parse_path(path))
        if found is None:
            return None
        return "own" if found[1] is None else f"merged:{found[1]}"

    def keys(self, path: PathLike = ()) -> list[Any]:
        """Keys of the mapping at ``path`` (own keys first, then inherited ones)."""
        value = self.get(path) if parse_path(path) else self.to_plain()
        if not isinstance(value, dict):
            raise self._path_error(parse_path(path), "is not a mapping")
        return list(value)

    def anchors(self) -> dict[str, int]:
        """Anchors defined in the document and their 1-based line."""
        return {name: self._text.count("\n", 0, n.start_mark.index) + 1 for name, n in self._anchors.items()}

    # ----------------------------------------------------------------- editing

    def set(self, path: PathLike, value: Any) -> bool:
        """Set the value at ``path``; returns False when it already had that value.

        Missing mapping keys on the way are created (as block mappings at the file's
        indentation); a sequence index equal to the length appends. Setting a key that is
        inherited through ``<<`` creates an explicit override key in that mapping (a copy of
        the inherited value with the change); the anchor is never rewritten.

        Scalars keep their quoting style; the case of booleans (``True``) is kept.

        Raises:
            PathError: an index is out of range or the path goes through a scalar.
            DocumentError: the edit cannot be made without changing other content.
        """
        parts = parse_path(path)
        if not parts:
            raise PathError("cannot replace the whole document", path=self.path)
        found = self._find(parts)
        if found is not None and same_value(self._resolved(found[0]), plain_value(value)):
            return False
        self._edit_set(parts, value)
        return True

    def delete(self, path: PathLike, *, missing_ok: bool = True) -> bool:
        """Remove a mapping key or sequence item; returns False when it did not exist.

        The entry's lines go, with comment lines directly above it at its column and one
        blank separator line when entries are separated by blank lines. Removing the last
        entry of a collection leaves ``{}`` / ``[]``.

        Raises:
            DocumentError: the key is only inherited through ``<<`` (nothing to delete in
                this mapping; override it or edit the anchor).
        """
        parts = parse_path(path)
        if not parts:
            raise PathError("cannot delete the whole document", path=self.path)
        parent_found = self._find(parts[:-1]) if parts[:-1] else self._root_found()
        if parent_found is None:
            if missing_ok:
                return False
            raise self._path_error(parts, "not found")
        parent, merged_from, _span = parent_found
        slot = self._slot(parent, parts[-1])
        if slot is None:
            if isinstance(parent, MappingNode) and self._merged_lookup(parent, parts[-1]):
                _node, anchor = self._merged_lookup(parent, parts[-1]) or (None, None)
                raise DocumentError(
                    f"{format_path(parts)} is inherited from &{anchor} through '<<'; "
                    "it is not written in this mapping",
                    path=self.path,
                    line=self.line_of(parts[:-1]),
                    hint=f"edit the anchor &{anchor} to change it for every service that merges it",
                )
            if missing_ok:
                return False
            raise self._path_error(parts, "not found")
        if merged_from is not None:
            full = copy.deepcopy(self._resolved_at(parts[:-1]))
            py_delete(full, parts[-1])
            self._materialize(parts[:-1], full)
            return True
        self._edit_delete(parts, parent, slot)
        return True

    def append(self, path: PathLike, value: Any) -> bool:
        """Append ``value`` to the sequence at ``path`` (created when missing). Always True."""
        parts = parse_path(path)
        found = self._find(parts)
        if found is None:
            self.set(parts, [value])
            return True
        node, merged_from, _ = found
        if not isinstance(node, SequenceNode):
            raise self._path_error(parts, "is not a sequence")
        if merged_from is not None or self._is_alias_path(parts):
            full = copy.deepcopy(self._resolved(node))
            full.append(plain_value(value))
            self._materialize(parts, full)
            return True
        self._edit_set((*parts, len(node.value)), value)
        return True

    def materialize(self, path: PathLike) -> bool:
        """Make the inherited (``<<``) or aliased value at ``path`` an explicit copy.

        Returns False when the value is already written in place.
        """
        parts = parse_path(path)
        found = self._find(parts)
        if found is None:
            raise self._path_error(parts, "not found")
        if found[1] is None and not self._is_alias_path(parts):
            return False
        self._materialize(parts, copy.deepcopy(self._resolved(found[0])))
        return True

    def replace_span(
        self,
        start: int,
        end: int,
        new_text: str,
        *,
        path: PathLike,
        expected: Any = MISSING,
        check: Callable[[Any], bool] | None = None,
    ) -> bool:
        """Low-level splice of ``text[start:end]`` for an edit inside the value at ``path``.

        The result must parse, and differ from before only in the value at ``path``, which
        must now be ``expected`` (when given) and satisfy ``check`` (when given); otherwise
        `DocumentError` is raised and nothing changes.
        """
        if self._text[start:end] == new_text:
            return False
        parts = parse_path(path)
        new = self._text[:start] + new_text + self._text[end:]
        if expected is MISSING:
            probe = YamlDocument(new, self.path)
            expected = probe.get(parts)
        if check is not None and not check(expected):
            raise DocumentError(
                f"internal: the edit of {format_path(parts)} does not give the intended value",
                path=self.path,
                line=self.line_of(parts),
            )
        self._commit(new, self._unresolved_with(parts, expected), parts)
        return True

    def diff(self, path: str | None = None) -> str:
        """Unified diff from the original text to the current text."""
        from panther_ops.core.yaml.diff import unified_diff

        return unified_diff(self.original, self._text, path or self.path or "document.yaml")

    def _resolved_at(self, parts: Sequence[PathPart]) -> Any:
        return self.get(parts) if parts else self.to_plain()

    # --------------------------------------------------------------- commits

    def _commit(self, new_text: str, expected: Any, parts: Sequence[PathPart]) -> None:
        """Adopt ``new_text`` if it parses to ``expected`` (unresolved view); else refuse."""
        try:
            root = self._compose(new_text)
        except DocumentError as exc:
            raise self._refused(parts, f"would make the file invalid YAML ({exc.message})") from exc
        probe = object.__new__(YamlDocument)
        probe._text = new_text
        probe._root = root
        probe.path = self.path
        try:
            probe._index()
        except DocumentError as exc:
            raise self._refused(parts, f"would make the file invalid ({exc.message})") from exc
        got = probe._unresolved(root)
        if got is None and expected == {}:
            got = {}
        if not same_value(normalise(got), normalise(expected)):
            raise self._refused(parts, "would change more than that value; the file was left as it was")
        self._text = new_text
        self._root = root
        self._alias_slots, self._anchors, self._indent = probe._alias_slots, probe._anchors, probe._indent

    def _refused(self, parts: Sequence[PathPart], what: str) -> DocumentError:
        """The error for an edit at ``parts`` that the commit check turned down."""
        return DocumentError(f"internal: editing {format_path(parts)} {what}",
                             path=self.path, line=self.line_of(parts))

    def _splice(self, start: int, end: int, new: str) -> str:
        return self._text[:start] + new + self._text[end:]

    # ------------------------------------------------------------ set engine

    def _edit_set(self, parts: tuple[PathPart, ...], value: Any) -> None:
        if self._root is None:
            self._create_root(parts, value)
            return
        node: Node = self._root
        for depth, part in enumerate(parts):
            here, rest = parts[: depth + 1], parts[depth + 1 :]
            if isinstance(node, ScalarNode):
                raise self._path_error(here, "goes through a scalar value")
            slot = self._slot(node, part)
            if slot is not None:
                if (id(node), slot) in self._alias_slots:
                    self._materialize_set(here, rest, value)
                    return
                if not rest:
                    self._replace_slot(parts, node, slot, value)
                    return
                node = node.value[slot][1] if isinstance(node, MappingNode) else node.value[slot]
                continue
            if isinstance(node, SequenceNode):
                idx = as_index(part)
                if idx is not None and idx == len(node.value):
                    new_value = nest(rest, value)
                    self._append_item(here[:-1], node, new_value, parts)
                    return
                raise self._path_error(here, f"index out of range (the sequence has {len(node.value)} items)")
            inherited = self._merged_lookup(cast("MappingNode", node), part)
            if inherited is not None:
                self._materialize_set(here, rest, value)
                return
            self._insert_entry(here[:-1], cast("MappingNode", node), part, nest(rest, value), parts)
            return

    def _materialize_set(self, here: Sequence[PathPart], rest: Sequence[PathPart], value: Any) -> None:
        """Write out the value at ``here`` (an alias or a merged key) with ``rest`` set to ``value``."""
        if rest:
            full = copy.deepcopy(self.get(here))
            self._py_set_checked(full, rest, value, here)
        else:
            full = value
        self._materialize(here, full)

    def _py_set_checked(self, tree: Any, rest: Sequence[PathPart], value: Any, here: Sequence[PathPart]) -> None:
        if not rest:
            raise DocumentError(f"{format_path(here)}: nothing to set", path=self.path)
        try:
            py_set(tree, rest, value, allow_create=True)
        except (KeyError, IndexError, TypeError) as exc:
            raise self._path_error((*here, *rest), f"cannot be set ({exc})") from exc

    def _copy_with(self, here: Sequence[PathPart], rest: Sequence[PathPart], value: Any) -> Any:
        """A copy of the value at ``here`` with ``rest`` inside it set to ``value`` (``value`` when no rest)."""
        if not rest:
            return value
        sub = copy.deepcopy(self.get(here))
        py_set(sub, rest, value)
        return sub

    def _materialize(self, parts: Sequence[PathPart], full: Any) -> None:
        """Write ``full`` as an explicit value at ``parts`` (inherited or aliased before)."""
        parts = tuple(parts)
        # walk to the first inherited/aliased step and write the copy there
        node: Node | None = self._root
        for depth, part in enumerate(parts):
            assert node is not None
            slot = self._slot(node, part)
            here = parts[: depth + 1]
            if slot is None:
                anchor = self._merged_lookup(cast("MappingNode", node), part)
                source = anchor[1] if anchor else "?"
                sub = self._copy_with(here, parts[depth + 1 :], full)
                self.notes.append(
                    f"{format_path(here)} was inherited from &{source} through '<<': "
                    f"wrote an explicit override in {format_path(here[:-1]) or 'the document'}; "
                    f"&{source} is unchanged"
                )
                self._insert_entry(here[:-1], cast("MappingNode", node), part, sub, here)
                return
            if (id(node), slot) in self._alias_slots:
                sub = self._copy_with(here, parts[depth + 1 :], full)
                anchor_name = (node.value[slot][1] if isinstance(node, MappingNode) else node.value[slot]).anchor
                self.notes.append(
                    f"{format_path(here)} was an alias of &{anchor_name}: replaced it with an "
                    f"explicit copy; &{anchor_name} is unchanged"
                )
                self._replace_slot(here, node, slot, sub)
                return
            node = node.value[slot][1] if isinstance(node, MappingNode) else node.value[slot]
        raise DocumentError(f"{format_path(parts)}: nothing inherited to override", path=self.path)

    def _replace_slot(self, parts: Sequence[PathPart], node: Node, slot: int, value: Any) -> None:
        """Replace the value in a slot with ``value``, keeping the scalar style where it can."""
        parts = tuple(parts)
        old = node.value[slot][1] if isinstance(node, MappingNode) else node.value[slot]
        start, end = self._slot_span(node, slot)
        flow = bool(is_flow(node))
        expected = self._unresolved_with(parts, value)
        is_alias = (id(node), slot) in self._alias_slots
        old_block = isinstance(old, MappingNode | SequenceNode) and not is_flow(old) and not is_alias
        if isinstance(node, MappingNode):
            head = self._colon_after(node.value[slot][0])
            base_col = node.value[slot][0].start_mark.column
        else:
            dash = self._dash_pos(start) if not flow else None
            head = dash + 1 if dash is not None else start
            base_col = (dash - self._bol(dash)) if dash is not None else 0
        if (
            not is_alias
            and isinstance(old, ScalarNode)
            and old.style in ("|", ">")
            and isinstance(value, str)
        ):
            self._commit(self._splice(start, end, self._block_scalar_text(old, start, end, value)), expected, parts)
            return
        original = self._original_scalars.get(path_key(parts))
        if (
            original is not None
            and isinstance(old, ScalarNode)
            and not is_alias
            and not is_collection(value)
            and not isinstance(value, Block | Quoted | Alias)
            and same_value(original[0], value)
            and (original[2] is None or original[2] == old.style)
        ):
            self._commit(self._splice(start, end, original[1]), expected, parts)
            return
        if flow and isinstance(old, ScalarNode) and not is_alias and not is_collection(value):
            style = old.style if old.style in ("'", '"') else None
            inline: str | None = render_scalar(
                value.text if isinstance(value, Block) else value,
                style=style,
                raw=self._text[start:end],
                flow=True,
            )
        elif flow:
            inline = render_inline(value, flow=True)
        elif isinstance(old, ScalarNode) and not is_alias and not is_collection(value):
            style = old.style if old.style in ("'", '"') else None
            inline = render_scalar(value, style=style, raw=self._text[start:end]) if not isinstance(
                value, Block
            ) else None
        elif isinstance(old, MappingNode | SequenceNode) and is_flow(old) and is_alias:
            inline = render_inline(value, flow=True)  # a copy in the style of the anchored value
        elif isinstance(old, MappingNode | SequenceNode) and is_flow(old) and not is_alias:
            # an empty [] / {} has no style to keep: nested content goes in block style
            nested = isinstance(value, Mapping) or (
                is_collection(value) and not isinstance(value, Flow) and any(is_collection(v) for v in value)
            )
            inline = render_inline(value) if not old.value and nested else render_inline(value, flow=True)
        else:
            inline = render_inline(value)
        if inline is not None:
            if start == end or old_block:
                self._commit(self._splice(head, end, " " + inline), expected, parts)
            else:
                self._commit(self._splice(start, end, inline), expected, parts)
            return
        # block rendering after the key's colon (or the item's dash)
        if isinstance(value, Block):
            header, lines = block_scalar_lines(value, base_col + max(self._indent.mapping, 2))
            self._commit(self._splice(head, end, " " + header + "\n" + "\n".join(lines)), expected, parts)
            return
        if isinstance(node, MappingNode):
            col = self._existing_child_col(old, base_col) if old_block else base_col
            lines = render_value_lines(value, col, self._indent)
            self._commit(self._splice(head, end, "\n" + "\n".join(lines)), expected, parts)
            return
        lines = render_item(value, base_col, self._indent)
        new = " " + lines[0][base_col + 2 :] + "".join("\n" + line for line in lines[1:])
        self._commit(self._splice(head, end, new), expected, parts)

    def _block_scalar_text(self, old: ScalarNode, start: int, end: int, value: str) -> str:
        """New text of a ``|``/``>`` scalar holding ``value``: same indicator and indentation."""
        text = self._text
        nl = text.find("\n", start)
        header = text[start:nl] if 0 <= nl < end else text[start:end]
        body = text[nl + 1 : end] if 0 <= nl < end else ""
        first = next((line for line in body.split("\n") if line.strip()), "")
        col = len(first) - len(first.lstrip(" ")) if first else self._bol(start) + 2 - self._bol(start)
        one_line = "\n" not in value.rstrip("\n")
        marker = Block(value, ">" if old.style == ">" and one_line else "|")
        new_header, lines = block_scalar_lines(marker, col)
        token = header.split("#", 1)[0].strip()
        keep = (
            token[:1] == new_header[:1]
            and ("-" in token) == ("-" in new_header)
            and "+" not in token
            and not any(c.isdigit() for c in token)
        )
        return (header if keep else new_header) + "\n" + "\n".join(lines)

    def _existing_child_col(self, old: Node, key_col: int) -> int:
        """Column to use as the 'key column' when re-rendering a block value in place."""
        if isinstance(old, MappingNode) and old.value and not is_flow(old):
            return cast("int", old.value[0][0].start_mark.column) - self._indent.mapping
        if isinstance(old, SequenceNode) and old.value and not is_flow(old):
            dash = self._dash_col(old.value[0])
            if dash is not None:
                return dash - self._indent.offset
        return key_col

    def _child_col(self, parts: Sequence[PathPart]) -> int:
        info = self.info(parts)
        return info.column + self._indent.mapping

    def _insert_entry(
        self,
        parent_parts: Sequence[PathPart],
        node: MappingNode,
        key: PathPart,
        value: Any,
        full_parts: Sequence[PathPart],
    ) -> None:
        key_parts = (*tuple(parent_parts), key)
        expected = self._unresolved_with(key_parts, value)
        if is_flow(node):
            entry = f"{render_scalar(str(key), flow=True)}: {render_inline(value, flow=True)}"
            if node.value:
                at = self._slot_span(node, len(node.value) - 1)[1]
                self._commit(self._splice(at, at, ", " + entry), expected, full_parts)
            else:
                close = node.end_mark.index - 1
                self._commit(self._splice(close, close, entry), expected, full_parts)
            return
        if not node.value:
            raise DocumentError(f"{format_path(parent_parts)}: empty block mapping", path=self.path)
        col = node.value[0][0].start_mark.column
        lines = render_entry(str(key) if isinstance(key, int) else key, value, col, self._indent)
        last_end = self._slot_span(node, len(node.value) - 1)[1]
        at = self._eol(last_end)
        prefix = ""
        if at == len(self._text) and not self._text.endswith("\n"):
            prefix = "\n"
        if self._blank_separated(node):
            prefix += "\n"
        self._commit(self._splice(at, at, prefix + "\n".join(lines) + "\n"), expected, full_parts)

    def _append_item(
        self, seq_parts: Sequence[PathPart], node: SequenceNode, value: Any, full_parts: Sequence[PathPart]
    ) -> None:
        expected = self._unresolved_with((*tuple(seq_parts), len(node.value)), value)
        text = self._text
        if is_flow(node) and not node.value and is_collection(value) and not isinstance(value, Flow) and seq_parts:
            parent_found = self._find(tuple(seq_parts)[:-1]) if len(seq_parts) > 1 else self._root_found()
            if parent_found is not None and not is_flow(parent_found[0]):
                slot = self._slot(parent_found[0], tuple(seq_parts)[-1])
                if slot is not None:
                    self._replace_slot(tuple(seq_parts), parent_found[0], slot, [value])
                    return
        if is_flow(node):
            rendered = render_inline(value, flow=True) or ""
            if not node.value:
                close = node.end_mark.index - 1
                self._commit(self._splice(close, close, rendered), expected, full_parts)
                return
            last_end = self._slot_span(node, len(node.value) - 1)[1]
            n = len(node.value)
            prev_end = self._slot_span(node, n - 2)[1] if n >= 2 else node.start_mark.index
            last_start = self._slot_span(node, len(node.value) - 1)[0]
            if "\n" in text[prev_end:last_start]:
                line_start = self._bol(last_start)
                indent = text[line_start:last_start]
                sep = ",\n" + (indent if not indent.strip() else " " * (last_start - line_start))
            else:
                sep = ", "
            self._commit(self._splice(last_end, last_end, sep + rendered), expected, full_parts)
            return
        dash_col = self._dash_col(node.value[0]) or 0
        lines = render_item(value, dash_col, self._indent)
        last_end = self._slot_span(node, len(node.value) - 1)[1]
        at = self._eol(last_end)
        prefix = "\n" if at == len(text) and not text.endswith("\n") else ""
        if self._blank_separated(node):
            prefix += "\n"
        self._commit(self._splice(at, at, prefix + "\n".join(lines) + "\n"), expected, full_parts)

    def _create_root(self, parts: tuple[PathPart, ...], value: Any) -> None:
        if isinstance(parts[0], int):
            raise PathError("an empty document can only get mapping keys", path=self.path)
        tree = nest(parts[1:], value)
        lines = render_entry(parts[0], tree, 0, self._indent)
        text = self._text
        if text and not text.endswith("\n"):
            text += "\n"
        expected = {parts[0]: plain_value(tree)}
        self._commit(text + "\n".join(lines) + "\n", expected, parts)

    # --------------------------------------------------------- delete engine

    def _edit_delete(self, parts: tuple[PathPart, ...], parent: Node, slot: int) -> None:
        text = self._text
        tree = self._unresolved(self._root)
        py_delete_path(tree, parts)
        if is_flow(parent):
            start = self._entry_start(parent, slot)
            end = self._slot_span(parent, slot)[1]
            if slot + 1 < len(parent.value):
                end = self._entry_start(parent, slot + 1)
            elif slot > 0:
                start = self._slot_span(parent, slot - 1)[1]
            self._commit(self._splice(start, end, ""), tree, parts)
            return
        own = [i for i, (k, _) in enumerate(parent.value)] if isinstance(parent, MappingNode) else list(
            range(len(parent.value))
        )
        if len(own) == 1 and parent is not self._root:
            # last entry: leave an empty flow collection after the parent key / dash
            empty = "{}" if isinstance(parent, MappingNode) else "[]"
            grand_parts = parts[:-2]
            grand_found = self._find(grand_parts) if grand_parts else self._root_found()
            assert grand_found is not None
            grand = grand_found[0]
            gslot = self._slot(grand, parts[-2])
            assert gslot is not None
            if isinstance(grand, MappingNode):
                start = self._colon_after(grand.value[gslot][0])
                lead = " "
            else:
                start = self._slot_span(grand, gslot)[0]
                lead = ""
            end = self._content_end(parent)
            self._commit(self._splice(start, end, lead + empty), tree, parts)
            return
        entry_start = self._entry_start(parent, slot)
        line_start = self._bol(entry_start)
        end = self._eol(self._slot_span(parent, slot)[1])
        if text[line_start:entry_start].strip():
            # first key of a compact "- key: v" item: pull the next key up onto the dash line
            if isinstance(parent, MappingNode) and slot + 1 < len(parent.value):
                nxt = parent.value[slot + 1][0].start_mark.index
                self._commit(self._splice(entry_start, nxt, ""), tree, parts)
                return
            raise DocumentError(
                f"{format_path(parts)}: cannot remove an entry written on its parent's line",
                path=self.path,
                line=self.line_of(parts),
            )
        col = entry_start - line_start
        start = line_start
        # comment lines directly above, at the entry's column, belong to it
        while start > 0:
            prev = self._bol(start - 1)
            line = text[prev : start - 1]
            if line.strip().startswith("#") and len(line) - len(line.lstrip(" ")) == col:
                start = prev
            else:
                break
        prev_blank = start > 0 and not text[self._bol(start - 1) : start - 1].strip()
        next_line_end = text.find("\n", end)
        next_blank = end < len(text) and not text[end : next_line_end if next_line_end >= 0 else len(text)].strip()
        is_last = slot == len(parent.value) - 1
        is_first = slot == 0
        if prev_blank and (next_blank or is_last):
            while start > 0 and not text[self._bol(start - 1) : start - 1].strip():
                start = self._bol(start - 1)
        elif is_first and next_blank and not prev_blank:
            while end < len(text):
                nl = text.find("\n", end)
                line = text[end : nl if nl >= 0 else len(text)]
                if line.strip():
                    break
                end = nl + 1 if nl >= 0 else len(text)
        self._commit(self._splice(start, end, ""), tree, parts)
