"""Test doubles and helpers for the runtime manager tests (no real robot, host or network)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import py_trees

from panther_ops.manager.blackboard import TreeBlackboard
from panther_ops.manager.clock import ManualClock
from panther_ops.manager.nodes.base import NodeContext, Outcome
from panther_ops.manager.nodes.controls import run_outcome
from panther_ops.manager.robot_io import RobotMsg, ServiceRequest, ServiceResult
from panther_ops.manager.shutdown_executor.backends import (
    CommandOutcome,
    InlineDispatcher,
    ShutdownBackends,
)
from panther_ops.manager.shutdown_executor.hosts import ShutdownHost


@dataclass
class FakeCall:
    """A service call the test decides the outcome of."""

    response: ServiceResult | None = None
    cancelled: bool = False

    def done(self) -> bool:
        return self.response is not None

    def result(self) -> ServiceResult:
        assert self.response is not None
        return self.response

    def cancel(self) -> None:
        self.cancelled = True


@dataclass
class FakeRobotIO:
    """Test double of RobotIO: scripted messages, recorded calls, scripted answers."""

    answer: ServiceResult | None = field(default_factory=lambda: ServiceResult(True))
    messages: list[RobotMsg] = field(default_factory=list)
    calls: list[tuple[ServiceRequest, FakeCall]] = field(default_factory=list)

    def drain(self) -> list[RobotMsg]:
        out, self.messages = self.messages, []
        return out

    def call(self, request: ServiceRequest) -> FakeCall:
        handle = FakeCall(self.answer)
        self.calls.append((request, handle))
        return handle

    @property
    def requests(self) -> list[str]:
        return [str(r) for r, _ in self.calls]


class FakePinger:
    """Test double: answers ping from a table, optionally until a time."""

    def __init__(self, clock: ManualClock, up: dict[str, float | bool]) -> None:
        self.clock = clock
        self.up = up
        self.pings: list[str] = []

    def is_reachable(self, ip: str) -> bool:
        self.pings.append(ip)
        state = self.up.get(ip, False)
        if isinstance(state, bool):
            return state
        return self.clock.now() < state


class FakeRemote:
    """Test double of RemoteShutdown: records requests, answers from a table."""

    def __init__(self, outcomes: dict[str, CommandOutcome] | None = None,
                 pinger: FakePinger | None = None, down_after: float | None = None) -> None:
        self.outcomes = outcomes or {}
        self.requests: list[ShutdownHost] = []
        self.pinger = pinger
        self.down_after = down_after

    def request(self, host: ShutdownHost) -> CommandOutcome:
        self.requests.append(host)
        if self.pinger is not None and self.down_after is not None:
            self.pinger.up[host.ip] = self.pinger.clock.now() + self.down_after
        return self.outcomes.get(host.ip, CommandOutcome(True, "bye"))


class FakeLocalRunner:
    """Test double of LocalRunner: records commands, never runs them."""

    def __init__(self, outcome: CommandOutcome | None = None) -> None:
        self.commands: list[str] = []
        self.outcome = outcome or CommandOutcome(True)

    def run(self, command: str, timeout: float) -> CommandOutcome:
        self.commands.append(command)
        return self.outcome


def fake_backends(clock: ManualClock, up: dict[str, float | bool] | None = None,
                  outcomes: dict[str, CommandOutcome] | None = None,
                  down_after: float | None = 1.0) -> ShutdownBackends:
    """Shutdown backends made of test doubles and an inline dispatcher."""
    pinger = FakePinger(clock, dict(up or {}))
    remote = FakeRemote(outcomes, pinger, down_after)
    return ShutdownBackends(pinger, remote, remote, FakeLocalRunner(), InlineDispatcher())


def make_ctx(io: Any, clock: ManualClock, entries: dict[str, Any] | None = None,
             backends: ShutdownBackends | None = None, tree: str = "Test") -> NodeContext:
    """A node context over a fresh tree blackboard holding `entries`."""
    blackboard = TreeBlackboard(tree)
    blackboard.update(entries or {})
    return NodeContext(io, clock, blackboard, backends, service_timeout=1.0)


def tick(node: py_trees.behaviour.Behaviour) -> Outcome:
    """Tick once; the outcome (None when skipped)."""
    return run_outcome(node)


def simulate(doc: dict[str, Any], trees: Any = None, duration: float | None = None) -> list[Any]:
    """Run a scenario given as a mapping with the fast clock; all snapshots."""
    from panther_ops.manager.sim.runner import run_simulation
    from panther_ops.manager.sim.scenario import parse_scenario

    scenario = parse_scenario({"duration": 120, **doc}, "<test scenario>")
    return list(run_simulation(scenario, trees=trees, duration=duration))


def calls(snapshots: list[Any], *, contains: str = "") -> list[tuple[float, str]]:
    """(time, call) of every service call, optionally only those containing `contains`."""
    return [(round(s.time, 1), c) for s in snapshots for c in s.calls if contains in c]
