"""The CLI side of every mutating command: plan, show, confirm, apply."""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING

import typer

if TYPE_CHECKING:
    from panther_ops.core.fleet.changes import Applier, Planner
    from panther_ops.core.fleet.inventory import Inventory, Robot


def confirm(question: str, yes: bool, refusal: str) -> bool:
    """True with --yes, else the operator's answer to ``question``; when nobody can answer (not
    interactive), ``refusal`` is the error and the answer is no."""
    if yes:
        return True
    if not sys.stdin.isatty():
        from panther_ops.cli.render import error

        error(refusal)
        return False
    return bool(typer.confirm(question, default=False, err=True))  # stdout is for data (--json)


def require(question: str, yes: bool, refusal: str, nothing: str = "nothing was changed") -> None:
    """Go on with --yes or when the operator answers yes to ``question``; otherwise stop: nobody
    can answer (not interactive, no --yes) is a usage error, ``refusal`` (exit 2); a no is
    :class:`~panther_ops.errors.Declined`, ``nothing`` (exit 5, docs/results.md)."""
    from panther_ops.errors import Declined, UsageError

    if yes:
        return
    if not sys.stdin.isatty():
        raise UsageError(refusal)
    if not typer.confirm(question, default=False, err=True):  # stdout is for data (--json)
        raise Declined(nothing)


def question(verb: str, subject: str, to_change: list[str], chosen: list[Robot]) -> str:
    """``Apply to 2 robots: panther-01, panther-03?``: the robots in inventory order (the plans
    come in the order they finished)."""
    names = [r.name for r in chosen if r.name in set(to_change)]
    return f"{verb} {len(names)} {subject}{'' if len(names) == 1 else 's'}: {', '.join(names)}?"


def mutate(
    command: str,
    inv: Inventory,
    chosen: list[Robot],
    planner: Planner,
    *,
    yes: bool,
    dry_run: bool,
    restart: bool = True,
    settle: float = 5.0,
    json_out: bool = False,
    forks: int | None = None,
    canary: int = 0,
    max_fail: float | None = None,
    applier: Applier | None = None,
    verb: str = "Apply to",
    read_only: bool = False,
    applier_for_actions: bool = False,
    drift_exit: bool = False,
) -> int:
    """Plan every robot, show the diffs, confirm, apply (with ``applier``, default the pipeline).

    Asked first (no ``--yes``), the plan is a table of every robot with the diffs under it;
    with ``--yes`` nothing waits on it, so only its diffs are shown before the changes are
    applied, and the results table follows. ``read_only``: a command that only compares
    (``config diff``): the plan is shown as a dry run's, without speaking of one.
    ``applier_for_actions``: the applier differs from the pipeline only for plans with an
    action (``apply``'s WebUI change); the others are staged while planning as usual.
    ``drift_exit``: a comparison's exit code says whether a robot would change (``config diff
    --exit-code``: 6, docs/results.md).
    """
    from panther_ops.cli.progress import FleetProgress, progress_wanted
    from panther_ops.cli.render import error, finish, print_plan_diffs, print_results
    from panther_ops.core.fleet.changes import apply_fleet, dry_run_result, plan_fleet, unstage_fleet
    from panther_ops.core.fleet.pipeline import ApplyOptions
    from panther_ops.core.fleet.runner import Connections, RunOptions
    from panther_ops.errors import ExitCode

    opts = RunOptions(forks=forks or inv.forks, canary=canary, max_fail_pct=max_fail)
    apply = ApplyOptions(restart=restart, settle_s=settle, command=command)
    early = yes and not dry_run and (applier is None or applier_for_actions)  # no question: stage while planning
    progress = FleetProgress([r.name for r in chosen], enabled=progress_wanted(json_out))
    with Connections(inv) as conns:
        with progress.live():
            fp = plan_fleet(command, inv, chosen, planner, conns, opts, progress, stage=apply if early else None)
        if fp.usage_errors:
            unstage_fleet(fp, inv, chosen, conns, opts)
            order = [r.name for r in chosen]
            refused = sorted(fp.usage_errors.items(), key=lambda item: order.index(item[0]) if item[0] in order else 0)
            for name, exc in refused:
                error(f"{name}: {exc}")
            nothing = "nothing was changed" + (" on any robot" if inv.subject == "robot" else "")
            sys.stderr.write(nothing + "\n")
            if json_out:
                from panther_ops.cli.envelope import error_of, hold_error

                hold_error({"type": "UsageError", "code": ExitCode.USAGE.name,
                            "message": f"bad input for {len(refused)} {inv.subject}(s): {nothing}",
                            inv.subject + "s": {name: error_of(exc, ExitCode.USAGE) for name, exc in refused}})
            return int(ExitCode.USAGE)
        if dry_run or not fp.to_change:
            shown = dry_run_result(fp, read_only=read_only) if dry_run else fp.results
            shown.drift_exit = drift_exit
            return finish(shown, json_out, print_results)
        if not json_out:
            if yes:  # nothing waits on the plan: its diffs now, each robot's outcome once applied
                print_plan_diffs(fp.results, command)
            else:  # before the question nothing has changed: each change is what the robot would get
                print_results(dry_run_result(fp, read_only=True), title=f"plan: {command}")
        require(question(verb, inv.subject, fp.to_change, chosen), yes,
                "changes need confirmation: pass --yes when not interactive (or --dry-run to only look)",
                "nothing was changed" + (" on any robot" if inv.subject == "robot" else ""))
        with progress.live():
            result = apply_fleet(fp, inv, chosen, conns, opts, apply, progress, applier=applier) if applier else \
                apply_fleet(fp, inv, chosen, conns, opts, apply, progress)
    code = finish(result, json_out, lambda f: print_results(f, title=command, show_diffs=False))
    progress.recap()  # last, as Ansible's
    return code

