"""`driver stop` and `driver start`: the driver's container stopped or started as it is.

``docker compose stop|start <driver service>`` as the robot user in a login shell (the same
way every compose command runs), in the compose file's directory, then the container's state
is read back: stopped (``exited``) after a stop; after a start, running and not restarted for
the settle time (the watch `driver restart` uses).
"""

from __future__ import annotations

import posixpath
import time

from panther_ops.core.config.robot import read_compose
from panther_ops.core.containers.engine import engine
from panther_ops.core.driver import planners
from panther_ops.core.fleet.pipeline import ApplyOptions, watch_services
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.services import project_dir, service_containers
from panther_ops.results import Outcome, RobotResult
from panther_ops.transport.base import Command

STOP_TIMEOUT_S = 30
"""How long a stop waits for the container to exit (docker compose's own default is 10 s; the
driver's shutdown of the motor controllers may take longer)."""


def plan_stop(ctx: RobotContext) -> RobotPlan:
    return planners.plan_run_state(read_compose(ctx), Reads(ctx.robot.name, ctx.robot.stack), "stop")


def plan_start(ctx: RobotContext) -> RobotPlan:
    return planners.plan_run_state(read_compose(ctx), Reads(ctx.robot.name, ctx.robot.stack), "start")


def apply_run_state(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions) -> RobotResult:
    """Stop or start the driver's container (``plan.data['action']``) and check its state."""
    name = ctx.robot.name
    action, service = str(plan.data["action"]), str(plan.data["service"])
    client, why = engine(ctx)
    if client is None:
        return RobotResult(name, Outcome.SKIPPED, f"{why}: nothing to {action}", data=dict(plan.data))
    wd = project_dir(ctx, plan.compose_file, plan.home)
    found = service_containers(client, service, wd, own_only=True)
    if not found:
        return RobotResult(name, Outcome.FAILED, f"no {service} container of the project in {wd}",
                           data={**plan.data, "hint": f"panther-ops driver restart -r {name}"})
    running = found[0].attrs.get("State", {}).get("Status") == "running"
    if running == (action == "start"):
        return RobotResult(name, Outcome.OK, f"{service} already {'running' if running else 'stopped'}",
                           data=dict(plan.data))
    ctx.phase(action)
    argv = ["docker", "compose", "-f", posixpath.basename(plan.compose_file), action]
    argv += ["-t", str(STOP_TIMEOUT_S)] if action == "stop" else []
    res = ctx.transport.run(Command.of(*argv, service, login=True, cwd=posixpath.dirname(plan.compose_file) or "~"),
                            timeout=STOP_TIMEOUT_S + 60)
    result = RobotResult(name, Outcome.CHANGED, "", data=dict(plan.data))
    if not res.ok:
        result.outcome = Outcome.FAILED
        result.message = f"docker compose {action} failed: {res.stderr.strip()[-400:]}"
        return result
    if action == "start":
        ctx.phase("verify")
        problem = watch_services(client, plan, opts.settle_s, wd)
        if problem:
            result.outcome = Outcome.FAILED
            result.message = problem
            result.data["hint"] = f"panther-ops driver logs -r {name}"
            return result
        result.message = f"started {service}; running after {opts.settle_s:g} s"
        return result
    deadline = time.monotonic() + 5
    while True:
        state = service_containers(client, service, wd, own_only=True)[0].attrs.get("State", {})
        if state.get("Status") == "exited":
            result.message = f"stopped {service} (exit code {state.get('ExitCode')}); `driver start` brings it back"
            return result
        if time.monotonic() >= deadline:
            result.outcome = Outcome.FAILED
            result.message = f"{service} is {state.get('Status')} after docker compose stop"
            return result
        time.sleep(0.2)
