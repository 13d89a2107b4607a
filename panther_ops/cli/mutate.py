"""The CLI side of every mutating command: plan, show, confirm, apply."""

from __future__ import annotations

import sys
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import typer

if TYPE_CHECKING:
    from collections.abc import Callable

    from panther_ops.cli.context import Fleet
    from panther_ops.core.fleet.changes import FleetPlan, Planner
    from panther_ops.core.fleet.inventory import Inventory, Robot
    from panther_ops.core.fleet.plan import RobotPlan
    from panther_ops.results import FleetResult
    from panther_ops.secret import Secret


def confirm(question: str, yes: bool, refusal: str) -> bool:
    """True with --yes, else the operator's answer to ``question``; when nobody can answer (not
    interactive), ``refusal`` is the error and the answer is no."""
    if yes:
        return True
    if not sys.stdin.isatty():
        from panther_ops.cli.render import error

        error(refusal)
        return False
    return ask(question)


NOTHING_WRITTEN = "interrupted at the confirmation (Ctrl-C): nothing was changed (no robot written)"


def ask(question: str) -> bool:
    """The operator's answer to ``question`` ([y/N], on stderr: stdout is for data). Ctrl-C
    there is :class:`~panther_ops.errors.Interrupted` (exit 130, saying that nothing was
    written); an end of input (Ctrl-D) aborts as click does."""
    from panther_ops.errors import Interrupted

    try:
        return bool(typer.confirm(question, default=False, err=True))
    except (typer.Abort, KeyboardInterrupt) as exc:
        if isinstance(exc.__context__, EOFError):
            raise
        sys.stderr.write("\n")  # the prompt's line ends; the message goes on its own
        raise Interrupted(NOTHING_WRITTEN) from None


def require(question: str, yes: bool, refusal: str, nothing: str = "nothing was changed") -> None:
    """Go on with --yes or when the operator answers yes to ``question``; otherwise stop: nobody
    can answer (not interactive, no --yes) is a usage error, ``refusal`` (exit 2); a no is
    :class:`~panther_ops.errors.Declined`, ``nothing`` (exit 5, docs/results.md)."""
    from panther_ops.errors import Declined, UsageError

    if yes:
        return
    if not sys.stdin.isatty():
        raise UsageError(refusal)
    if not ask(question):
        raise Declined(nothing)


def question(verb: str, subject: str, to_change: list[str], chosen: list[Robot]) -> str:
    """``Apply to 2 robots: panther-01, panther-03?``: the robots in inventory order (the plans
    come in the order they finished)."""
    names = [r.name for r in chosen if r.name in set(to_change)]
    return f"{verb} {len(names)} {subject}{'' if len(names) == 1 else 's'}: {', '.join(names)}?"


@dataclass(frozen=True)
class Asking:
    """How a change speaks before it acts; the defaults are those of a configuration change.

    ``verb`` starts the default question (``Apply to 2 robots: panther-01, panther-03?``);
    ``question``: the whole question instead, from the robots to change and their plans;
    ``refusal``: the error when nobody can answer (from the question); ``nothing``: what a
    no, or a robot's bad input, leaves (``nothing was changed``); ``dry_note``: a dry run's
    note from the robots it would change; ``idle``: the note when no robot needs the change
    and every robot is ok."""

    verb: str = "Apply to"
    question: Callable[[list[str], dict[str, RobotPlan]], str] | None = None
    refusal: Callable[[str], str] | None = None
    nothing: str = ""
    dry_note: Callable[[list[str]], str] | None = None
    idle: str = ""


@dataclass(frozen=True)
class Change:
    """What one command changes: ``read_only``: a command that only compares (``config
    diff``): the plan is shown as a dry run's, without speaking of one; ``drift_exit``: a
    comparison's exit code says whether a robot would change (``config diff --exit-code``: 6,
    docs/results.md); ``view``: how the results of the change are shown (default: the generic
    table; a plan or a dry run is always the table); ``restart``: whether a changed file
    recreates its container; ``sudo_password``: for a plan's steps that run sudo beside the
    robot (`apply`'s WebUI settings)."""

    command: str
    planner: Planner
    asking: Asking = field(default_factory=Asking)
    read_only: bool = False
    drift_exit: bool = False
    view: Callable[[FleetResult], None] | None = None
    restart: bool = True
    sudo_password: Secret | None = None


def mutate(change: Change, inv: Inventory, chosen: list[Robot], given: Fleet) -> int:
    """Plan every robot, show the diffs, confirm, apply through the pipeline (each plan's
    steps by their executors, `core/fleet/steps.py`), with the shared options ``given`` on the
    command line (--yes, --dry-run, --settle, --json, --forks, --canary, --max-fail).

    Asked first (no ``--yes``), the plan is a table of every robot with the diffs under it;
    with ``--yes`` nothing waits on it, so only its diffs are shown before the changes are
    applied, and the results table follows. With ``--yes`` a plan of file edits alone is
    staged while the others are planned (`changes.plan_fleet`); a plan with steps waits for
    phase 2.
    """
    from panther_ops.cli.progress import FleetProgress, progress_wanted
    from panther_ops.cli.render import finish, print_plan_diffs, print_results
    from panther_ops.core.fleet.changes import apply_fleet, dry_run_result, plan_fleet, unstage_fleet
    from panther_ops.core.fleet.pipeline import ApplyOptions
    from panther_ops.core.fleet.runner import Connections, RunOptions

    command, o, asking = change.command, given, change.asking
    yes, dry_run, json_out = o.yes and not change.read_only, o.dry_run or change.read_only, o.json_out
    opts = RunOptions(forks=o.forks or inv.forks, canary=o.canary, max_fail_pct=o.max_fail)
    apply = ApplyOptions(restart=change.restart, settle_s=o.settle, command=command,
                         sudo_password=change.sudo_password)
    early = yes and not dry_run  # no question: stage while planning
    progress = FleetProgress([r.name for r in chosen], enabled=progress_wanted(json_out), printing=not json_out)
    nothing = asking.nothing or "nothing was changed" + (" on any robot" if inv.subject == "robot" else "")
    with Connections(inv) as conns:
        with progress.live():
            fp = plan_fleet(command, inv, chosen, change.planner, conns, opts, progress, stage=apply if early else None)
        if fp.usage_errors:
            unstage_fleet(fp, inv, chosen, conns, opts)
            return _refused(fp, inv, chosen, nothing, json_out)
        if dry_run or not fp.to_change:
            shown = dry_run_result(fp, read_only=change.read_only) if dry_run else fp.results
            names = [r.name for r in chosen if r.name in set(fp.to_change)]
            if dry_run and asking.dry_note is not None:
                shown.notes = [asking.dry_note(names)]
            elif asking.idle and not names and all(r.outcome.value == "ok" for r in shown.results):
                shown.notes.append(asking.idle)
            shown.drift_exit = change.drift_exit
            return finish(shown, json_out, print_results)
        if not json_out:
            if yes:  # nothing waits on the plan: its diffs now, each robot's outcome once applied
                print_plan_diffs(fp.results, command)
            else:  # before the question nothing has changed: each change is what the robot would get
                print_results(dry_run_result(fp, read_only=True), title=f"plan: {command}")
        asked = question(asking.verb, inv.subject, fp.to_change, chosen) if asking.question is None else \
            asking.question([r.name for r in chosen if r.name in set(fp.to_change)], fp.plans)
        require(asked, yes, asking.refusal(asked) if asking.refusal else
                "changes need confirmation: pass --yes when not interactive (or --dry-run to only look)", nothing)
        with progress.live():
            result = apply_fleet(fp, inv, chosen, conns, opts, apply, progress)
    code = finish(result, json_out, change.view or (lambda f: print_results(f, title=command, show_diffs=False)))
    progress.recap()  # last, as Ansible's
    return code


def _refused(fp: FleetPlan, inv: Inventory, chosen: list[Robot], nothing: str, json_out: bool) -> int:
    """Bad input for some robots: each named with its error, nothing done anywhere (exit 2)."""
    from panther_ops.cli.render import error
    from panther_ops.errors import ExitCode

    order = [r.name for r in chosen]
    refused = sorted(fp.usage_errors.items(), key=lambda item: order.index(item[0]) if item[0] in order else 0)
    for name, exc in refused:
        error(f"{name}: {exc}")
    sys.stderr.write(nothing + "\n")
    if json_out:
        from panther_ops.cli.envelope import error_of, hold_error

        hold_error({"type": "UsageError", "code": ExitCode.USAGE.name,
                    "message": f"bad input for {len(refused)} {inv.subject}(s): {nothing}",
                    inv.subject + "s": {name: error_of(exc, ExitCode.USAGE) for name, exc in refused}})
    return int(ExitCode.USAGE)
