"""Per-host shutdown state machines, advanced one bounded step at a time.

IDLE -> (ping; not answering -> SKIPPED) -> COMMAND_EXECUTED -> RESPONSE_RECEIVED
-> PINGING (until the host stops answering) -> SUCCESS, or FAILURE on an error or when
``timeout`` passes. A step submits at most one blocking job (to the dispatcher) and polls
at most one; it never waits. `ShutdownExecutor` steps every unfinished host per call, so
hosts proceed side by side (the manual's "semi-parallel" processing).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from concurrent.futures import Future
from dataclasses import dataclass
from enum import Enum
from typing import Any

from panther_ops.manager.clock import Clock
from panther_ops.manager.shutdown_executor.backends import CommandOutcome, ShutdownBackends
from panther_ops.manager.shutdown_executor.hosts import ShutdownHost


class HostState(str, Enum):
    """Where a host's shutdown is (names of the C++ ShutdownHostState)."""

    IDLE = "IDLE"
    COMMAND_EXECUTED = "COMMAND_EXECUTED"
    RESPONSE_RECEIVED = "RESPONSE_RECEIVED"
    PINGING = "PINGING"
    SUCCESS = "SUCCESS"
    FAILURE = "FAILURE"
    SKIPPED = "SKIPPED"

    @property
    def finished(self) -> bool:
        return self in (HostState.SUCCESS, HostState.FAILURE, HostState.SKIPPED)


@dataclass(frozen=True)
class HostResult:
    """How one host's shutdown ended (or where it is)."""

    host: ShutdownHost
    state: HostState
    message: str
    output: str = ""
    elapsed: float = 0.0


class HostShutdown:
    """One host's shutdown as a state machine; call `step()` until `finished`."""

    def __init__(self, host: ShutdownHost, backends: ShutdownBackends, clock: Clock,
                 ping_interval: float = 0.5) -> None:
        self.host = host
        self.backends = backends
        self.clock = clock
        self.ping_interval = ping_interval
        self.state = HostState.IDLE
        self.message = "waiting"
        self.output = ""
        self.started: float | None = None
        self.command_time = 0.0
        self.last_ping = float("-inf")
        self.ended: float | None = None
        self._job: Future[Any] | None = None

    @property
    def finished(self) -> bool:
        return self.state.finished

    def _submit(self, fn: Callable[[], Any]) -> None:
        self._job = self.backends.dispatcher.submit(fn)

    def _take(self, default: Any) -> Any:
        """The finished job's result (exceptions become `default`), or None if not done."""
        job = self._job
        if job is None or not job.done():
            return None
        self._job = None
        try:
            return job.result()
        except Exception as exc:  # a backend bug must not kill the manager
            if isinstance(default, CommandOutcome):
                return CommandOutcome(False, error=f"{type(exc).__name__}: {exc}")
            return default

    def _end(self, state: HostState, message: str) -> None:
        self.state = state
        self.message = message
        self.ended = self.clock.now()
        self._job = None

    def step(self) -> HostState:
        """Advance by at most one transition; never blocks."""
        now = self.clock.now()
        if self.started is None:
            self.started = now
        if self.state is HostState.IDLE:
            self._step_idle(now)
        elif self.state is HostState.COMMAND_EXECUTED:
            self._step_command(now)
        elif self.state is HostState.RESPONSE_RECEIVED:
            if self.host.ping_for_success:
                self.state, self.message = HostState.PINGING, "waiting for the host to go down"
            else:
                self._end(HostState.SUCCESS, "shutdown requested")
        elif self.state is HostState.PINGING:
            self._step_pinging(now)
        return self.state

    def _step_idle(self, now: float) -> None:
        if self._job is None:
            ip = self.host.ip
            self._submit(lambda: self.backends.pinger.is_reachable(ip))
            self.message = "checking that the host answers"
            return
        reachable = self._take(False)
        if reachable is None:
            return
        if not reachable:
            self._end(HostState.SKIPPED, "host does not answer ping, skipped")
            return
        remote, host = self.backends.remote_for(self.host), self.host
        self._submit(lambda: remote.request(host))
        self.command_time = now
        self.state, self.message = HostState.COMMAND_EXECUTED, f"shutdown requested ({host.method.value})"

    def _step_command(self, now: float) -> None:
        outcome = self._take(CommandOutcome(False))
        if outcome is None:
            if now - self.command_time > self.host.timeout:
                self._end(HostState.FAILURE, "Timeout exceeded waiting for a response")
            return
        self.output = outcome.output
        if not outcome.ok:
            self._end(HostState.FAILURE, outcome.error or "request failed")
            return
        self.state, self.message = HostState.RESPONSE_RECEIVED, "response received"

    def _step_pinging(self, now: float) -> None:
        """As the stock ShutdownHost's PINGING state: a ping's answer is looked at before the clock,
        so a host is failed only by an echo that came back past its time limit; a ping on its way
        at the limit is waited for, and past the limit the next one goes out at once
        (husarion_ugv_ros@2.2.2:husarion_ugv_manager/include/husarion_ugv_manager/plugins/
        shutdown_host.hpp, ``Call``: ``IsAvailable()``, then ``TimeoutExceeded``)."""
        past = now - self.command_time > self.host.timeout
        if self._job is not None:
            reachable = self._take(True)
            if reachable is None:  # on its way: its answer decides
                return
            if reachable is False:
                self._end(HostState.SUCCESS, "host is down")
                return
            if past:
                self._end(HostState.FAILURE, "Timeout exceeded: the host still answers ping")
                return
        if past or now - self.last_ping >= self.ping_interval:
            ip = self.host.ip
            self._submit(lambda: self.backends.pinger.is_reachable(ip))
            self.last_ping = now

    def result(self) -> HostResult:
        """The host's current result."""
        end = self.ended if self.ended is not None else self.clock.now()
        elapsed = end - self.started if self.started is not None else 0.0
        return HostResult(self.host, self.state, self.message, self.output, elapsed)


class ShutdownExecutor:
    """Shut several hosts down side by side; each `step()` advances every unfinished host."""

    def __init__(self, hosts: Iterable[ShutdownHost], backends: ShutdownBackends, clock: Clock,
                 ping_interval: float = 0.5) -> None:
        unique: dict[tuple[str, str, int], ShutdownHost] = {}
        for host in hosts:
            unique.setdefault(host.key, host)
        self.machines = [HostShutdown(h, backends, clock, ping_interval) for h in unique.values()]

    @property
    def done(self) -> bool:
        return all(m.finished for m in self.machines)

    def step(self) -> bool:
        """Advance every unfinished host once; return True when all are finished."""
        for machine in self.machines:
            if not machine.finished:
                machine.step()
        return self.done

    def results(self) -> list[HostResult]:
        return [m.result() for m in self.machines]

    @property
    def failed(self) -> list[HostResult]:
        return [r for r in self.results() if r.state is HostState.FAILURE]


def run_all(hosts: Iterable[ShutdownHost], clock: Clock, backends: ShutdownBackends | None = None,
            *, period: float = 0.05) -> list[HostResult]:
    """Shut the hosts down and wait until each one ended (blocking convenience).

    Args:
        hosts: the hosts (duplicates by ip/user/port are dropped).
        clock: a real clock with real backends; a manual clock only with an inline dispatcher.
        backends: defaults to `ShutdownBackends.real()` (closed afterwards).
        period: pause between steps.

    Returns:
        One result per host, in order.
    """
    own = backends is None
    used = backends if backends is not None else ShutdownBackends.real()
    executor = ShutdownExecutor(hosts, used, clock)
    try:
        while not executor.step():
            clock.sleep(period)
    finally:
        if own:
            used.close()
    return executor.results()
