"""Shutdown actions: SignalShutdown, ShutdownSingleHost, ShutdownHostsFromFile, ExecuteCommand.

Each tick advances a non-blocking state machine (`shutdown_executor`); network I/O and
commands run in the context's dispatcher, never in the tick.
"""

from __future__ import annotations

from concurrent.futures import Future
from typing import Any, ClassVar, Generic, TypeVar

from py_trees.common import Status

from panther_ops.manager.errors import ShutdownHostsError
from panther_ops.manager.keys import SIGNAL_SHUTDOWN
from panther_ops.manager.nodes.base import NodeContext, PortedLeaf, PortSpec
from panther_ops.manager.shutdown_executor.backends import CommandOutcome, ShutdownBackends
from panther_ops.manager.shutdown_executor.hosts import (
    DEFAULT_COMMAND,
    ShutdownHost,
    load_shutdown_hosts,
)
from panther_ops.manager.shutdown_executor.machine import (
    HostShutdown,
    HostState,
    ShutdownExecutor,
)


class SignalShutdown(PortedLeaf):
    """Ask the manager to shut the robot down: ``signal_shutdown = (true, reason)``."""

    PORTS: ClassVar[dict[str, PortSpec]] = {"reason": PortSpec("str", "", "reason to shut the robot down")}
    ALIASES: ClassVar[dict[str, str]] = {"message": "reason"}
    WRITES: ClassVar[tuple[str, ...]] = (SIGNAL_SHUTDOWN,)

    def __init__(self, name: str, ctx: NodeContext, **ports: Any) -> None:
        super().__init__(name, ctx, **ports)
        self.key = ctx.resolve(SIGNAL_SHUTDOWN)

    def update(self) -> Status:
        reason = self.port("reason")
        assert self.ports.client is not None
        self.ports.client.set(self.key, (True, reason))
        self.feedback_message = f"shutdown signalled: {reason}"
        return Status.SUCCESS


class _ShutdownLeaf(PortedLeaf):
    def backends(self) -> ShutdownBackends | None:
        if self.ctx.shutdown is None:
            self.feedback_message = "no shutdown backends in this tree's context"
        return self.ctx.shutdown


Work = TypeVar("Work", HostShutdown, ShutdownExecutor)


class _StepLeaf(_ShutdownLeaf, Generic[Work]):
    """A leaf whose work is one non-blocking state machine (``work``): started by `initialise`
    (None when it cannot start: the feedback says why; the leaf then fails), advanced by each
    `update`, dropped when the tree halts the leaf."""

    work: Work | None = None

    def initialise(self) -> None:
        self.work = None
        backends = self.backends()
        if backends is not None:
            self.work = self.start(backends)

    def start(self, backends: ShutdownBackends) -> Work | None:
        raise NotImplementedError

    def update(self) -> Status:
        return Status.FAILURE if self.work is None else self.step(self.work)

    def step(self, work: Work) -> Status:
        raise NotImplementedError

    def terminate(self, new_status: Status) -> None:
        if new_status == Status.INVALID:
            self.work = None


class ShutdownSingleHost(_StepLeaf[HostShutdown]):
    """Shut one host down over SSH (or HTTP when a `secret` is given)."""

    PORTS: ClassVar[dict[str, PortSpec]] = {
        "command": PortSpec("str", DEFAULT_COMMAND, "command to execute on shutdown"),
        "ip": PortSpec("str", description="IP of the host to shutdown"),
        "ping_for_success": PortSpec("bool", True, "ping host until it is not available"),
        "port": PortSpec("int", 22, "SSH communication port"),
        "timeout": PortSpec("float", 5.0, "time in s to wait for the host to shutdown"),
        "username": PortSpec("str", "", "user to log into while executing the command"),
        "secret": PortSpec("str", "", "HTTP shutdown secret (husarion-shutdown); empty for SSH"),
    }
    ALIASES: ClassVar[dict[str, str]] = {"user": "username"}

    def start(self, backends: ShutdownBackends) -> HostShutdown | None:
        try:
            host = ShutdownHost(
                ip=self.port("ip"), username=self.port("username") or None, port=self.port("port"),
                command=self.port("command"), timeout=self.port("timeout"),
                ping_for_success=self.port("ping_for_success"), secret=self.port("secret") or None,
            )
        except ValueError as exc:
            self.feedback_message = str(exc)
            return None
        return HostShutdown(host, backends, self.ctx.clock)

    def step(self, work: HostShutdown) -> Status:
        state = work.step()
        self.feedback_message = f"{work.host.describe()}: {work.message}"
        if state in (HostState.SUCCESS, HostState.SKIPPED):
            return Status.SUCCESS
        return Status.FAILURE if state is HostState.FAILURE else Status.RUNNING


class ShutdownHostsFromFile(_StepLeaf[ShutdownExecutor]):
    """Shut down every host of a YAML file, side by side; SUCCESS only if none failed."""

    PORTS: ClassVar[dict[str, PortSpec]] = {
        "shutdown_hosts_file": PortSpec("str", description="global path to YAML file"),
    }
    ALIASES: ClassVar[dict[str, str]] = {"shutdown_host_file": "shutdown_hosts_file"}

    def start(self, backends: ShutdownBackends) -> ShutdownExecutor | None:
        path = self.port("shutdown_hosts_file")
        try:
            hosts_file = load_shutdown_hosts(path)
        except ShutdownHostsError as exc:
            self.feedback_message = str(exc)
            return None
        self.problems = hosts_file.problems
        if not hosts_file.hosts:
            self.feedback_message = f"{path}: no hosts to shut down"
            return None
        return ShutdownExecutor(hosts_file.hosts, backends, self.ctx.clock)

    def step(self, work: ShutdownExecutor) -> Status:
        done = work.step()
        results = work.results()
        self.feedback_message = "; ".join(f"{r.host.describe()}: {r.state.value} ({r.message})"
                                          for r in results)
        if not done:
            return Status.RUNNING
        return Status.FAILURE if work.failed else Status.SUCCESS


class ExecuteCommand(_ShutdownLeaf):
    """Run a local command (2.2's node, used to power the Built-in Computer off)."""

    PORTS: ClassVar[dict[str, PortSpec]] = {
        "command": PortSpec("str", description="command to execute"),
        "timeout": PortSpec("float", 1.0, "time in s to wait for the command"),
    }

    def initialise(self) -> None:
        self.job: Future[CommandOutcome] | None = None
        self.started = self.ctx.clock.now()

    def update(self) -> Status:
        backends = self.backends()
        if backends is None:
            return Status.FAILURE
        if self.job is None:
            command, timeout = self.port("command"), self.port("timeout")
            local = backends.local
            self.job = backends.dispatcher.submit(lambda: local.run(command, timeout))
            self.feedback_message = f"running '{command}'"
        if not self.job.done():
            if self.ctx.clock.now() - self.started > self.port("timeout"):
                self.feedback_message = "Timeout exceeded"
                return Status.FAILURE
            return Status.RUNNING
        try:
            outcome = self.job.result()
        except Exception as exc:  # a runner bug is a failed command, not a crash
            outcome = CommandOutcome(False, error=f"{type(exc).__name__}: {exc}")
        self.feedback_message = outcome.error or outcome.output.strip()
        return Status.SUCCESS if outcome.ok else Status.FAILURE
