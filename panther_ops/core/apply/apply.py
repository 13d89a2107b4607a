"""The executor of `panther-ops apply` plans (planner: `plan.py`; reads: `read.py`).

The robot's files go through the pipeline (backup, recreate, verify, roll back); the WebUI's
settings are an action after them: `sudo snap set` on the User Computer through the robot's
connection, the WebUI restarted when it was running, read back.
"""

from __future__ import annotations

from typing import Any

from panther_ops.core.fleet.pipeline import ApplyOptions, apply_plan
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.errors import OpsError
from panther_ops.results import Outcome, RobotResult
from panther_ops.secret import Secret


def desired_applier(password: Secret | None) -> Any:
    """Carry out `read_and_plan_desired`'s plans: the files through the pipeline, then the WebUI's
    settings (files that failed or rolled back leave the WebUI untouched)."""
    def apply(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions) -> RobotResult:
        from panther_ops.core.remote.webui.apply import apply_desired_webui
        from panther_ops.core.remote.webui.plan import ACTION

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
