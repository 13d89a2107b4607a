"""The reads of `panther-ops manager deploy|remove` on one robot: compose.yaml, then the files
and facts the planners (`plan.py`, pure) ask for, over the robot's one connection; then the plan."""

from __future__ import annotations

from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.reading import read_and_plan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.manager_ops import plan as planner
from panther_ops.core.manager_ops.apply import manager_containers
from panther_ops.core.manager_ops.bundle import ManagerBundle
from panther_ops.core.manager_ops.checks import IMAGE_PROBE
from panther_ops.core.manager_ops.image_probe import probe_image
from panther_ops.core.manager_ops.service import EXISTS
from panther_ops.core.manager_ops.settings import SERVICE
from panther_ops.core.robot.read import read_compose
from panther_ops.core.robot.robot_config import parse_config
from panther_ops.errors import OpsError


def read_and_plan_deploy(ctx: RobotContext, *, sim: bool | None = None, scenario: str | None = None,
                bundle: ManagerBundle | None = None) -> RobotPlan:
    """One plan: upload, service, disable_manager; nothing is written here."""
    raw = read_compose(ctx)
    facts = {EXISTS: lambda c, path: c.transport.exists(path),
             IMAGE_PROBE: lambda c, hosts_file: probe_image(c, parse_config(raw, c.robot.stack), hosts_file),
             planner.RUNNING: lambda c, _key: _running_warning(c)}
    return read_and_plan(ctx, lambda reads: planner.plan_deploy(raw, reads, ctx.robot.desired, sim=sim,
                                                                scenario=scenario, bundle=bundle), facts)


def read_and_plan_remove(ctx: RobotContext) -> RobotPlan:
    """Take the service out, put disable_manager back as it was, delete the uploaded files."""
    raw = read_compose(ctx)
    return read_and_plan(ctx, lambda reads: planner.plan_remove(raw, reads))


def _running_warning(ctx: RobotContext) -> list[str]:
    try:
        client = ctx.transport.docker()
        if client is None:
            return []
        ctrs = manager_containers(client)
    except OpsError:
        return []
    except Exception:  # docker SDK errors: the plan stays valid, the status command says more
        return []
    if not ctrs:
        return [f"service {SERVICE} has no container: `docker compose up -d {SERVICE}` on the robot starts it"]
    state = ctrs[0].attrs.get("State", {})
    if state.get("Status") != "running":
        return [f"container {SERVICE} is {state.get('Status')} (exit code {state.get('ExitCode')}): "
                "see `panther-ops manager logs`"]
    return []
