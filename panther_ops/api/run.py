"""One module run on one robot, as the CLI runs the same command (cli/mutate.py): plan through
core/fleet/changes.py, then (not in check mode) apply through the pipeline; the result as the
plain data an Ansible action plugin returns."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from panther_ops.api.modules import CHANGES, check_arguments
from panther_ops.core.fleet.inventory import Inventory, Robot
from panther_ops.errors import OpsError, UsageError
from panther_ops.results import FleetResult, RobotResult


def run_module(module: str, args: Mapping[str, Any], inv: Inventory, robot: Robot, *,
               check: bool = False) -> dict[str, Any]:
    """``module`` with ``args`` on ``robot``; ``check``: the plan only (panther-ops' --dry-run).

    Returns ``changed``, ``failed``, ``msg`` (panther-ops' message: a refusal is the text the
    CLI prints), ``outcome``, ``diff`` (``prepared``: the exact unified diffs, as --dry-run
    shows them), ``warnings`` and ``panther_ops`` (the robot's result as ``--json`` gives it)."""
    try:
        a = check_arguments(module, args)
        problems = inv.key_problems([robot])  # a key file that cannot be used: before anything is contacted
        if problems:
            raise problems[0]
        if module == "estop" and a["state"] == "triggered":
            return _estop(inv, robot, check)
        change = CHANGES[module](a)
        restart = change.restart if change.restart is not None else a.get("restart", True)
        result = _change(change, inv, robot, check=check, restart=restart,
                         settle=a.get("settle", 5.0))
    except UsageError as exc:  # the refusal panther-ops prints, nothing contacted or written
        return {"changed": False, "failed": True, "msg": str(exc), "outcome": "refused", "rc": int(exc.exit_code)}
    except OpsError as exc:  # panther-ops' own error for this robot, as the CLI prints it
        return {"changed": False, "failed": True, "msg": str(exc), "outcome": "failed", "rc": int(exc.exit_code)}
    return report(result)


def _change(change: Any, inv: Inventory, robot: Robot, *, check: bool, restart: bool, settle: float) -> RobotResult:
    from panther_ops.core.fleet.changes import apply_fleet, dry_run_result, plan_fleet, unstage_fleet
    from panther_ops.core.fleet.pipeline import ApplyOptions
    from panther_ops.core.fleet.runner import Connections, RunOptions

    opts = RunOptions(forks=1)
    apply = ApplyOptions(restart=restart, settle_s=settle, command=change.label)
    with Connections(inv) as conns:
        fp = plan_fleet(change.label, inv, [robot], change.planner, conns, opts)
        if fp.usage_errors:
            unstage_fleet(fp, inv, [robot], conns, opts)
            raise UsageError(f"{robot.name}: {fp.usage_errors[robot.name]}\nnothing was changed")
        if check or not fp.to_change:
            out: FleetResult = dry_run_result(fp) if check else fp.results
        else:
            out = apply_fleet(fp, inv, [robot], conns, opts, apply)
    return out.results[0]


def _estop(inv: Inventory, robot: Robot, check: bool) -> dict[str, Any]:
    """The E-stop triggered (an action, as `estop trigger`: no plan, no diff; check mode says
    it would be triggered and contacts nothing)."""
    if check:
        return {"changed": True, "failed": False, "msg": "would trigger the E-stop (check mode)", "outcome": "changed"}
    from panther_ops.core.fleet.runner import RunOptions, run_fleet
    from panther_ops.core.remote.estop.calls import trigger_task

    return report(run_fleet("estop trigger", inv, [robot], trigger_task, RunOptions(forks=1)).results[0])


def report(r: RobotResult) -> dict[str, Any]:
    """A robot's result as an action plugin's: changed/failed as panther-ops reports them."""
    failed = r.outcome.is_failure
    out: dict[str, Any] = {
        "changed": r.outcome.value == "changed", "failed": failed, "msg": r.message,
        "outcome": r.outcome.value, "warnings": list(r.warnings), "panther_ops": r.to_json(),
    }
    if r.diffs:
        out["diff"] = {"prepared": "".join(d.unified for d in r.diffs)}
    return out
