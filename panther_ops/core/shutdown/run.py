"""Running the shared shutdown executor for the CLI, and `shutdown robot`.

`shutdown_hosts` drives `panther_ops.manager.shutdown_executor.ShutdownExecutor` (the one
the runtime manager's Shutdown tree uses) until every host ended: all hosts progress
together, so the wall time is about the slowest host's, not the sum. Each host ends
`changed` (went down; or the request was answered when ``ping_for_success: false``),
`skipped` (did not answer ping) or `failed` (with the reason).

`shutdown robot` does what the Shutdown tree does: the robot's hosts file first, through
the robot (its failures do not stop it), then the Built-in Computer itself with
``sudo -n shutdown now`` as the robot user (the 2.0/2.1 tree's
``ShutdownSingleHost ip=localhost user=husarion command="sudo shutdown now"``).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable

from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.kinds.hostsfile import POWER_BUDGET_S
from panther_ops.core.shutdown.links import backends_via
from panther_ops.core.shutdown.plan import RobotShutdownPlan, robot_shutdown, shutdown_plan
from panther_ops.core.shutdown.read import read_robot_hosts
from panther_ops.errors import OpsError
from panther_ops.manager.clock import Clock, MonotonicClock
from panther_ops.manager.shutdown_executor import (
    HostResult,
    HostState,
    Method,
    ShutdownBackends,
    ShutdownExecutor,
    ShutdownHost,
)
from panther_ops.results import FleetResult, Outcome, RobotResult
from panther_ops.transport.base import Command
from panther_ops.transport.lan import RobotLink

PING_INTERVAL = 0.05
"""Seconds between pings while a host goes down (the manager pings every tick, 30 Hz)."""
STEP_PERIOD = 0.05
ROBOT_COMMAND = ("sudo", "-n", "shutdown", "now")

_OUTCOMES = {HostState.SUCCESS: Outcome.CHANGED, HostState.SKIPPED: Outcome.SKIPPED}


def host_label(host: ShutdownHost) -> str:
    return host.describe()


def result_of(r: HostResult) -> RobotResult:
    """One host's end as a result row (`changed`, `skipped`, `failed`)."""
    outcome = _OUTCOMES.get(r.state, Outcome.FAILED)
    message = r.message
    if r.state is HostState.SUCCESS:
        message = "went down" if r.host.ping_for_success else "shutdown requested (ping_for_success: false)"
    data: dict[str, object] = {"ip": r.host.ip, "port": r.host.port, "method": r.host.method.value,
                               "state": r.state.value, "timeout_s": r.host.timeout}
    if r.host.method is Method.SSH:
        data["username"] = r.host.username
    if r.output.strip():
        data["output"] = r.output.strip()[-400:]
    return RobotResult(host_label(r.host), outcome, message, data=data, duration_s=r.elapsed)


def shutdown_hosts(hosts: Iterable[ShutdownHost], backends: ShutdownBackends, *, command: str = "shutdown",
                   clock: Clock | None = None, ping_interval: float = PING_INTERVAL,
                   on_step: Callable[[ShutdownExecutor], None] | None = None) -> FleetResult:
    """Shut the hosts down side by side; one result per host (backends closed afterwards)."""
    clk = clock or MonotonicClock()
    executor = ShutdownExecutor(hosts, backends, clk, ping_interval=ping_interval)
    start = time.monotonic()
    try:
        while not executor.step():
            if on_step is not None:
                on_step(executor)
            clk.sleep(STEP_PERIOD)
    finally:
        backends.close()
    fleet = FleetResult(command, [result_of(r) for r in executor.results()])
    fleet.duration_s = time.monotonic() - start
    return fleet


def summary(fleet: FleetResult) -> str:
    down = len(fleet.by_outcome(Outcome.CHANGED))
    skipped = len(fleet.by_outcome(Outcome.SKIPPED))
    failed = len(fleet.by_outcome(Outcome.FAILED))
    return f"{down} down, {skipped} skipped, {failed} failed"


# ---------------------------------------------------------------------------------------------
# shutdown robot
# ---------------------------------------------------------------------------------------------
def plan_robot_shutdown(ctx: RobotContext, power_budget: float = POWER_BUDGET_S) -> RobotPlan:
    """Read and validate the robot's hosts file (UsageError when it has errors); the plan."""
    return robot_shutdown(shutdown_plan(ctx.robot.name, read_robot_hosts(ctx), power_budget))


def shutdown_robot(ctx: RobotContext, plan: RobotShutdownPlan, *,
                   ping_interval: float = PING_INTERVAL) -> RobotResult:
    """The robot's hosts (through the robot), then the Built-in Computer itself."""
    link = RobotLink(ctx.transport, ctx.robot.name)
    hosts = FleetResult("hosts")
    if plan.hosts:
        hosts = shutdown_hosts(plan.hosts, backends_via(link), command="hosts", ping_interval=ping_interval)
    shown = " ".join(ROBOT_COMMAND)
    try:
        res = link.run(Command.of(*ROBOT_COMMAND), timeout=15)
        ok, detail = res.ok, (res.stderr.strip() or res.stdout.strip())
    except OpsError as exc:  # the robot went away while answering: the command was delivered
        ok, detail = True, f"connection closed while shutting down ({exc.message})"
    data: dict[str, object] = {"hosts": [r.to_json() for r in hosts.results], "robot_command": shown,
                               "hosts_file": plan.hosts_file.source}
    head = f"hosts: {summary(hosts)}" if plan.hosts else "no hosts in the hosts file"
    if not ok:
        result = RobotResult(ctx.robot.name, Outcome.FAILED, f"{head}; Built-in Computer: `{shown}` failed: {detail}",
                             data=data)
        result.data["hint"] = ("the robot user needs passwordless sudo for /sbin/shutdown (the manual's sudoers rule "
                               "on the Built-in Computer)")
        return result
    result = RobotResult(ctx.robot.name, Outcome.CHANGED, f"{head}; Built-in Computer: shutdown requested", data=data)
    for r in hosts.results:
        if r.outcome is Outcome.FAILED:
            result.warnings.append(f"{r.robot}: {r.message}")
    return result
