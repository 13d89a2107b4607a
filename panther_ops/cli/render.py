"""Rendering: rich tables and diffs on a terminal, one JSON document with --json.

Data goes to stdout, progress and messages to stderr, so ``--json | jq`` works.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any

from panther_ops.cli.tables import Column, FitTable
from panther_ops.core.reimage.device import human_size
from panther_ops.errors import ExitCode
from panther_ops.results import FleetResult, Outcome, RobotResult

STYLE = {
    Outcome.OK: "green",
    Outcome.CHANGED: "yellow",
    Outcome.FAILED: "red",
    Outcome.ROLLED_BACK: "magenta",
    Outcome.UNREACHABLE: "red",
    Outcome.SKIPPED: "dim",
}


def _console(stderr: bool = False) -> Any:
    """The stream's console as the output module sets it up (terminal or pipe, colour, width)."""
    from panther_ops.cli.output import console

    return console(stderr)


def esc(text: object) -> str:
    """Text from robots or users, shown literally (no rich markup)."""
    from rich.markup import escape

    return escape(str(text))


def emit_json(doc: dict[str, Any]) -> None:
    """The run's one JSON document (written when the run ends, with its exit code: cli/envelope.py)."""
    from panther_ops.cli.envelope import hold

    hold(doc)


def counted(n: int, noun: str) -> str:
    """``1 robot``, ``3 robots``, ``0 warnings``."""
    return f"{n} {noun}{'' if n == 1 else 's'}"


def human_bytes(n: int | None) -> str:
    """A byte count as core says it (``12 B``, ``1.5 GiB``); ``-`` when unknown."""
    return "-" if n is None else human_size(n)


def print_results(fleet: FleetResult, *, title: str | None = None, show_diffs: bool = True) -> None:
    """The generic per-robot table: robot, outcome, message; then diffs and warnings."""
    table = new_table(title, (Column(fleet.subject, "name"), Column("result"), Column("message", "message")))
    for r in fleet.results:
        table.add_row(esc(r.robot), result_cell(r), esc(shown_message(r)))
    show(table)
    if show_diffs:
        print_diffs(fleet)
    print_warnings(fleet)
    print_summary(fleet)


def shown_message(r: RobotResult) -> str:
    """A result's message as its row shows it: without a leading ``would change:`` when the
    result column already says so (the JSON keeps the message whole)."""
    word = outcome_word(r)
    return r.message.removeprefix(f"{word}: ") if r.message.startswith(f"{word}: ") else r.message


def print_plan_diffs(fleet: FleetResult, command: str) -> None:
    """The diffs a change is about to write (``--yes``: no plan table), under a heading."""
    if any(r.diffs for r in fleet.results):
        _console().print(f"[bold]plan: {esc(command)}[/]")
        print_diffs(fleet)


def print_diffs(fleet: FleetResult) -> None:
    """Every robot's diffs, each a real patch.

    One robot: the paths are from its root (``--- a/home/husarion/compose.yaml``: ``patch -p1``
    in a copy of its tree). Several robots: from the fleet's root, each robot a directory named
    after it (``--- a/panther-01/home/husarion/compose.yaml``), so the whole output is one patch
    for a tree holding one directory per robot (the demo fleet's ``robots/``). A diff the same as
    an earlier robot's says so in its heading.
    """
    from panther_ops.cli.output import print_exact
    from panther_ops.core.yaml.diff import under_directory

    several = len(fleet.results) > 1
    first: dict[tuple[str, str], str] = {}
    out = _console()
    for r in fleet.results:
        for d in r.diffs:
            same = first.setdefault((d.path, d.unified), r.robot)
            note = f" (the same change as {same})" if same != r.robot else ""
            out.print(f"[bold]{esc(r.robot)}[/]: {esc(d.path)}{esc(note)}", soft_wrap=True)
            print_exact(styled_diff(under_directory(d.unified, r.robot) if several else d.unified))


DIFF_STYLE = (("+++", "bold"), ("---", "bold"), ("@@", "cyan"), ("+", "green"), ("-", "red"))


def styled_diff(unified: str) -> Any:
    """A unified diff as rich Text: headers bold, hunks cyan, additions green, removals red.

    The text is shown as is (no markup); print it with ``output.print_exact`` (no wrapping:
    a diff line is never folded into two).
    """
    from rich.text import Text

    text = Text(no_wrap=True, overflow="ignore", end="")
    for line in unified.splitlines(keepends=True):
        style = next((st for prefix, st in DIFF_STYLE if line.startswith(prefix)), "")
        text.append(line, style=style)
    return text


def print_warnings(fleet: FleetResult) -> None:
    from panther_ops.cli.output import print_message

    for r in fleet.results:
        for w in r.warnings:
            print_message(f"[yellow]warning[/] {r.robot}: {esc(w)}")
        if "hint" in r.data:
            print_message(f"[dim]hint[/] {r.robot}: {esc(r.data['hint'])}")
    for n in fleet.notes:
        print_message(f"[yellow]note[/] {esc(n)}")


def outcome_word(r: RobotResult) -> str:
    """``changed``, or ``would change`` for a plan not applied (a dry run): nothing changed yet."""
    return "would change" if r.outcome is Outcome.CHANGED and r.data.get("dry_run") else r.outcome.value


def outcome_counts(results: Iterable[RobotResult]) -> list[tuple[int, str, str]]:
    """How many results say each word (``would change`` apart from ``changed``), in the order
    the words first come: (count, word, style)."""
    counts: dict[tuple[str, str], int] = {}
    for r in results:
        key = (outcome_word(r), STYLE[r.outcome])
        counts[key] = counts.get(key, 0) + 1
    return [(n, word, style) for (word, style), n in counts.items()]


def print_summary(fleet: FleetResult) -> None:
    """``3 robots: 2 changed, 1 ok in 0.4 s``; a plan not applied (a dry run) says ``would change``."""
    grouped = (r for o in Outcome for r in fleet.by_outcome(o))  # ok first, then changed, ...
    parts = [f"[{style}]{n} {word}[/]" for n, word, style in outcome_counts(grouped)]
    code = fleet.exit_code
    tail = "" if code is ExitCode.OK else f" (exit {int(code)}: {code.name.lower()})"
    _console(stderr=True).print(
        f"{counted(len(fleet.results), fleet.subject)}: " + ", ".join(parts)
        + f" in {fleet.duration_s:.1f} s{tail}"
    )


def finish(fleet: FleetResult, json_out: bool, human: Callable[[FleetResult], None]) -> int:
    """Render a fleet result one way or the other; returns its exit code."""
    if json_out:
        emit_json(fleet.to_json())
    else:
        human(fleet)
    return int(fleet.exit_code)


def error(message: str) -> None:
    from panther_ops.cli.output import print_message

    print_message(f"[bold red]error[/] {esc(message)}")


def outcome_cell(outcome: Outcome) -> str:
    """An outcome as a table cell, in its colour."""
    return f"[{STYLE[outcome]}]{outcome.value}[/]"


def result_cell(r: RobotResult) -> str:
    """A robot's result as a table cell, in its colour: a dry run's change says ``would change``."""
    return f"[{STYLE[r.outcome]}]{outcome_word(r)}[/]"


def new_table(title: str | None, columns: tuple[str | Column, ...], **kw: Any) -> FitTable:
    """A table that fits the width it is printed at (``cli/tables.py``): a column named as a
    string is wrapping text."""
    return FitTable(title, columns, **kw)


def show(table: Any, stderr: bool = False) -> None:
    """A table on stdout, never cropped (``--wide`` runs past the edge; a narrow layout does not)."""
    _console(stderr).print(table, crop=False)


def print_table(table: Any, fleet: FleetResult) -> None:
    """A fleet result's table on stdout, then its warnings and the summary line."""
    show(table)
    print_warnings(fleet)
    print_summary(fleet)
