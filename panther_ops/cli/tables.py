"""Tables that fit the terminal: every table of the CLI is a ``FitTable``.

Laid out when printed, at the console's width (80 columns is the rule to meet):

- a ``name`` column (robot, host) and an ``id`` column (backup ids ``rollback --to`` needs,
  image ids) are never wrapped nor broken;
- a column that says nothing for the rows shown (every cell empty or ``-``) is left out;
- a ``message`` column (a result's message, a reason) stays a column while every message fits
  it on one line; otherwise each message goes on its own full-width line under its row, as a
  row's ``note`` (an unreachable robot's reason) always does;
- a ``path`` column is shortened from the left (``…/config/battery.yaml``), never so far that
  a file's name is cut or two different paths look the same;
- ``text`` columns wrap at words;
- when the table still does not fit, the columns with a ``drop`` rank are hidden, highest
  rank first, then other columns from the right (never the first, a name or an id), and a line
  under the table names them;
- ``--wide`` (``output.wide()``) shows everything: every column (empty ones too) at its full
  width, no path shortened, the table as wide as it needs (past the edge of a narrow terminal).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

if TYPE_CHECKING:
    from rich.console import Console, ConsoleOptions
    from rich.segment import Segment
    from rich.text import Text

Kind = Literal["name", "id", "path", "text", "message"]
NOTHING = ("", "-")
"""Cells that say nothing: a column of only these is left out."""
ELLIPSIS = "…"
NOTE_INDENT = 2
TEXT_MIN = 16
"""The narrowest a wrapping text column is made (unless its content is narrower)."""
PATH_MIN = 16


@dataclass(frozen=True)
class Column:
    header: str
    kind: Kind = "text"
    drop: int = 0
    """0: always shown; otherwise hidden when the table does not fit, highest rank first."""
    justify: Literal["left", "right"] = "left"


@dataclass
class _Row:
    cells: list[Text]
    note: Text | None


@dataclass
class Layout:
    """Which columns are shown, how wide, and what went under the rows or was hidden."""

    columns: list[int]
    widths: list[int]
    notes_from: list[int] = field(default_factory=list)
    hidden: list[str] = field(default_factory=list)

    def total(self) -> int:
        return table_width(self.widths)


def table_width(widths: Sequence[int]) -> int:
    """Columns of a boxed table: ``│ a │ b │``."""
    return sum(widths) + 3 * len(widths) + 1


def _text(markup: str) -> Text:
    from rich.text import Text

    return Text.from_markup(markup)


def _lines(cell: Text) -> list[Text]:
    return list(cell.split("\n", allow_blank=True)) if cell.plain else [cell]


def _natural(cell: Text) -> int:
    return max((line.cell_len for line in _lines(cell)), default=0)


def _longest_word(cell: Text) -> int:
    from rich.cells import cell_len

    return max((cell_len(w) for w in cell.plain.split()), default=0)


def shorten_left(path: str, width: int) -> str:
    """``path`` in at most ``width`` columns, cut from the left at a ``/`` when there is one
    (``…/config/battery.yaml``)."""
    if len(path) <= width:
        return path
    tail = path[len(path) - (width - 1):]
    cut = tail.find("/")
    if 0 < cut < len(tail) - 1:
        tail = tail[cut:]
    return ELLIPSIS + tail


def _distinct_width(paths: Iterable[str], natural: int) -> int:
    """The narrowest width (at least ``PATH_MIN``) at which different paths still look different."""
    values = {p for p in paths if p not in NOTHING}
    for width in range(min(PATH_MIN, natural), natural):
        if len({shorten_left(p, width) for p in values}) == len(values):
            return width
    return natural


class FitTable:
    """A boxed table laid out at the width it is printed at (see the module's text)."""

    def __init__(self, title: str | None, columns: Sequence[Column | str], *, wide: bool | None = None,
                 title_justify: Literal["left", "center"] = "center") -> None:
        self.title = title
        self.columns = [c if isinstance(c, Column) else Column(c) for c in columns]
        self.rows: list[_Row] = []
        self.title_justify = title_justify
        self._wide = wide

    @property
    def wide(self) -> bool:
        if self._wide is not None:
            return self._wide
        from panther_ops.cli.output import wide

        return wide()

    def add_row(self, *cells: str, note: str = "") -> None:
        """A row of rich-markup cells (text from robots or users escaped by the caller); ``note``:
        a line of its own under the row, the table's full width."""
        if len(cells) != len(self.columns):
            raise ValueError(f"{len(cells)} cells for {len(self.columns)} columns")
        self.rows.append(_Row([_text(c) for c in cells], _text(note) if note else None))

    # -- layout ----------------------------------------------------------------------------------
    def _says_something(self, i: int) -> bool:
        return i == 0 or any(r.cells[i].plain.strip() not in NOTHING for r in self.rows)

    def _natural(self, i: int) -> int:
        from rich.cells import cell_len

        header = cell_len(self.columns[i].header)
        return max([header, *(_natural(r.cells[i]) for r in self.rows)])

    def _minimum(self, i: int) -> int:
        col = self.columns[i]
        natural = self._natural(i)
        header_word = max((len(w) for w in col.header.split()), default=0)
        if col.kind in ("name", "id"):
            return natural
        if col.kind == "path":  # each file's whole name at least (…/name.yaml), no two paths alike
            paths = [r.cells[i].plain for r in self.rows]
            names = max((len(p.rsplit("/", 1)[-1]) + 2 for p in paths if "/" in p), default=0)
            return min(natural, max(header_word, names, _distinct_width(paths, natural)))
        words = max([header_word, *(min(_longest_word(r.cells[i]), TEXT_MIN) for r in self.rows)])
        return min(natural, max(words, min(TEXT_MIN, natural)))

    def layout(self, width: int) -> Layout:
        if self.wide:
            return Layout(list(range(len(self.columns))), [self._natural(i) for i in range(len(self.columns))])
        shown = [i for i in range(len(self.columns)) if self._says_something(i)]
        notes_from: list[int] = []
        hidden: list[str] = []
        while True:
            natural = [self._natural(i) for i in shown]
            if table_width(natural) <= width:
                return Layout(shown, natural, notes_from, hidden)
            messages = [i for i in shown if self.columns[i].kind == "message"]
            if messages:  # a message that does not fit goes under its row
                notes_from += messages
                shown = [i for i in shown if i not in messages]
                continue
            minimum = [self._minimum(i) for i in shown]
            if table_width(minimum) <= width:
                return Layout(shown, _spread(minimum, natural, width - table_width(minimum)), notes_from, hidden)
            ranked = [i for i in shown if self.columns[i].drop]
            rest = [i for i in shown[1:] if self.columns[i].kind not in ("name", "id")]
            if not ranked and not rest:  # only names and ids left: as narrow as it goes, past the edge
                return Layout(shown, minimum, notes_from, hidden)
            # the ranked columns first, highest rank first; then any but names and ids, from the right
            gone = max(ranked, key=lambda i: (self.columns[i].drop, i)) if ranked else rest[-1]
            hidden.append(self.columns[gone].header)
            shown.remove(gone)

    # -- rendering ---------------------------------------------------------------------------------
    def __rich_console__(self, console: Console, options: ConsoleOptions) -> Iterator[Segment]:
        from rich import box
        from rich.segment import Segment
        from rich.text import Text

        lay = self.layout(options.max_width)
        self._room_for_notes(lay, options.max_width)
        frame = box.HEAVY_HEAD.substitute(options, safe=True)
        padded = [w + 2 for w in lay.widths]
        total = lay.total()
        new_line = Segment.line()
        if self.title:
            title = Text.from_markup(self.title, style="italic", justify=self.title_justify)
            for line in title.wrap(console, max(total, min(title.cell_len, options.max_width)),
                                   justify=self.title_justify):
                yield from line.render(console)
                yield new_line
        yield Segment(frame.get_top(padded))
        yield new_line
        header = [Text(self.columns[i].header, style="bold") for i in lay.columns]
        yield from self._row_lines(console, frame, header, lay, head=True)
        yield Segment(frame.get_row(padded, "head"))
        yield new_line
        inner = total - 2 - 2
        for row in self.rows:
            yield from self._row_lines(console, frame, [row.cells[i] for i in lay.columns], lay, head=False)
            notes = [row.cells[i] for i in lay.notes_from if row.cells[i].plain.strip()]
            notes += [row.note] if row.note is not None else []
            for note in notes:
                for piece in note.wrap(console, max(1, inner - NOTE_INDENT), overflow="fold"):
                    piece.pad_left(NOTE_INDENT)
                    piece.align("left", max(inner, piece.cell_len))
                    yield Segment(frame.mid_left + " ")
                    yield from piece.render(console)
                    yield Segment(" " + frame.mid_right)
                    yield new_line
        yield Segment(frame.get_bottom(padded))
        yield new_line
        if lay.hidden:
            hidden = Text(f"not shown at this width: {', '.join(lay.hidden)} (--wide shows them)", style="dim")
            for line in hidden.wrap(console, options.max_width):
                line.rstrip()
                yield from line.render(console)
                yield new_line

    def _room_for_notes(self, lay: Layout, width: int) -> None:
        """Notes are full-width lines: a table with notes is widened (its last column) up to
        what its longest note needs, at most ``width``."""
        notes = [r.note for r in self.rows if r.note is not None]
        notes += [r.cells[i] for r in self.rows for i in lay.notes_from]
        longest = max((_natural(n) for n in notes), default=0)
        if not longest or not lay.widths:
            return
        want = min(width, longest + NOTE_INDENT + 4)
        if lay.total() < want:
            lay.widths[-1] += want - lay.total()

    def _row_lines(self, console: Console, frame: Any, cells: list[Text], lay: Layout, *, head: bool) -> Iterator[Any]:
        from rich.segment import Segment
        from rich.text import Text

        columns: list[list[Text]] = []
        for i, cell, width in zip(lay.columns, cells, lay.widths, strict=True):
            columns.append(self._cell_lines(console, self.columns[i], cell, width, head))
        height = max((len(c) for c in columns), default=1)
        left, sep, right = (frame.head_left, frame.head_vertical, frame.head_right) if head else \
            (frame.mid_left, frame.mid_vertical, frame.mid_right)
        for n in range(height):
            yield Segment(left)
            for k, (lines, width) in enumerate(zip(columns, lay.widths, strict=True)):
                line = lines[n].copy() if n < len(lines) else Text("")
                justify = self.columns[lay.columns[k]].justify
                line.align(justify, max(width, line.cell_len))
                yield Segment(" ")
                yield from line.render(console)
                yield Segment(" " + (sep if k < len(columns) - 1 else ""))
            yield Segment(right)
            yield Segment.line()

    def _cell_lines(self, console: Console, col: Column, cell: Text, width: int, head: bool) -> list[Text]:
        from rich.text import Text

        out: list[Text] = []
        for line in _lines(cell):
            if head or col.kind in {"text", "message"}:
                out.extend(line.wrap(console, width, overflow="fold"))
            elif col.kind == "path" and line.cell_len > width:
                out.append(Text(shorten_left(line.plain, width), style=line.style))
            else:  # name, id: never broken
                out.append(line)
        return out


def _spread(minimum: list[int], natural: list[int], room: int) -> list[int]:
    """Widths from ``minimum`` towards ``natural``, the spare ``room`` shared fairly: the columns
    that lack least are made whole first, the rest share what is left evenly."""
    widths = list(minimum)
    wanting = sorted((k for k in range(len(widths)) if natural[k] > minimum[k]), key=lambda k: natural[k] - minimum[k])
    for n, k in enumerate(wanting):
        given = min(natural[k] - widths[k], room // (len(wanting) - n))
        widths[k] += given
        room -= given
    return widths
