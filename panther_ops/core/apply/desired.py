"""`panther-ops apply` and `config diff`: the inventory's desired state (launch arguments,
controller, image, GPS, shutdown hosts, the WebUI on the User Computer) converged in one plan
per robot.

Reading here: compose.yaml (kept for the write when there is a desired state to converge),
the files the planner (`plan_desired.py`, pure) asks for, and the WebUI's state on the User
Computer when it asks for it. The robot's files go through the pipeline (backup, recreate,
verify, roll back); the WebUI's settings are an action after them (`desired_applier`):
`sudo snap set` on the User Computer through the robot's connection, the WebUI restarted when
it was running, read back.
"""

from __future__ import annotations

from typing import Any

from panther_ops.core.apply import plan_desired as planner
from panther_ops.core.config.robot import read_compose
from panther_ops.core.fleet.pipeline import ApplyOptions, apply_plan
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.reading import read_and_plan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.errors import OpsError, UsageError
from panther_ops.results import Outcome, RobotResult
from panther_ops.secret import Secret


def plan_desired(ctx: RobotContext, *, force: bool = False) -> RobotPlan:
    """Converge the robot to the inventory's ``desired:`` launch_args, controller, image, GPS,
    shutdown hosts and WebUI."""
    from panther_ops.core.remote.webui.desired import read_desired_webui
    from panther_ops.core.remote.webui.plan_desired import FACT
    from panther_ops.core.shutdown.plan_desired import DEFAULT_FACT

    desired = ctx.robot.desired
    if desired.get("shutdown_hosts") is not None:
        desired = {**desired, "shutdown_hosts": _resolved_hosts(ctx, desired["shutdown_hosts"])}
    raw = read_compose(ctx, keep=bool(desired))
    return read_and_plan(ctx, lambda reads: planner.plan_desired(raw, reads, desired, force=force),
                         {FACT: read_desired_webui, DEFAULT_FACT: _image_hosts})


def _image_hosts(ctx: RobotContext, _key: str) -> bytes:
    """The shutdown hosts file the robot's image ships (or panther-ops' template of its release)."""
    from panther_ops.core.config.push import pull
    from panther_ops.core.kinds import FileKind

    return pull(ctx, FileKind.SHUTDOWN_HOSTS)[0]


def _resolved_hosts(ctx: RobotContext, entries: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """``desired.shutdown_hosts`` with each ``secret: {env|file: ...}`` read (a relative file is
    relative to the inventory): the robot's manager needs the value itself."""
    from panther_ops.core.kinds.hostsfile import SecretRef

    out = []
    for i, entry in enumerate(entries):
        ref = entry.get("secret")
        if isinstance(ref, dict) and len(ref) == 1:
            (kind, where), = ref.items()
            try:
                secret = SecretRef(str(kind), str(where)).resolve(ctx.inventory.path.parent)
            except UsageError as exc:
                raise UsageError(f"{ctx.inventory.path}: desired.shutdown_hosts[{i}].{exc.message}",
                                 hint="set it, or change the inventory's reference") from None
            out.append({**entry, "secret": secret.reveal()})
        else:
            out.append(entry)
    return out


def desired_applier(password: Secret | None) -> Any:
    """Carry out `plan_desired`'s plans: the files through the pipeline, then the WebUI's
    settings (files that failed or rolled back leave the WebUI untouched)."""
    def apply(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions) -> RobotResult:
        from panther_ops.core.remote.webui.desired import apply_desired_webui
        from panther_ops.core.remote.webui.plan_desired import ACTION

        result = apply_plan(ctx, plan, opts)
        if plan.data.get("action") != ACTION or opts.dry_run:
            return result
        if plan.edits and result.outcome is not Outcome.CHANGED:
            return result
        files = f"{plan.data.get('files_summary')}; " if plan.edits else ""
        try:
            outcome, message, after = apply_desired_webui(ctx, plan.data["webui"]["wanted"], password)
        except OpsError as exc:
            outcome, message, after = Outcome.FAILED, f"WebUI: {exc.message}", {}
            if exc.hint:
                result.warnings.append(exc.hint)
        result.data["webui_after"] = after
        if outcome is Outcome.SKIPPED and plan.edits:
            result.warnings.append(message)
            result.message = plan.data.get("files_summary", result.message)
        else:
            result.outcome = outcome if outcome is not Outcome.OK or not plan.edits else Outcome.CHANGED
            result.message = files + message
        return result

    return apply
