"""Decorators with BehaviorTree.CPP v4 semantics, including the Panther `TickAfterTimeout`.

`Guard` carries a node's pre- and post-conditions (``_skipIf``, ``_while``, ``_successIf``,
``_failureIf``, ``_onSuccess``, ``_onFailure``, ``_post``). Time is read from the injected
clock only. Loops (`Repeat`, `RetryUntilSuccessful`) finish at most one cycle per tick, so
a tick always does bounded work (BT.CPP may loop inside one tick for synchronous children).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any, ClassVar

import py_trees
from py_trees.common import Status

from panther_ops.manager.errors import ScriptError
from panther_ops.manager.nodes.base import (
    NodeContext,
    Outcome,
    Ports,
    PortSpec,
    Program,
    TickGen,
    bind_ports,
    finish,
    halt,
    program_client,
    tick_child,
)


class BtDecorator(py_trees.decorators.Decorator):
    """A decorator that may skip its child or decide without ticking it."""

    def __init__(self, name: str, child: py_trees.behaviour.Behaviour) -> None:
        super().__init__(name=name, child=child)
        self.skipped = False

    def tick(self) -> Iterator[py_trees.behaviour.Behaviour]:
        self.skipped = False
        if self.status != Status.RUNNING:
            self.initialise()
        outcome = yield from self.decide()
        yield from finish(self, outcome)

    def decide(self) -> TickGen:
        raise NotImplementedError

    def update(self) -> Status:
        return self.status


class Guard(BtDecorator):
    """A node's BT.CPP pre- and post-conditions.

    Preconditions are checked when the node is not running, in BT.CPP's order
    (failureIf, successIf, skipIf, while); ``_while`` is re-checked while running and halts
    the node when false. Post-conditions run when the node ends with SUCCESS / FAILURE.
    """

    def __init__(
        self,
        child: py_trees.behaviour.Behaviour,
        ctx: NodeContext,
        *,
        skip_if: Program | None = None,
        while_: Program | None = None,
        success_if: Program | None = None,
        failure_if: Program | None = None,
        on_success: Program | None = None,
        on_failure: Program | None = None,
        post: Program | None = None,
    ) -> None:
        super().__init__(name=f"{child.name} ?", child=child)
        self.skip_if, self.while_ = skip_if, while_
        self.success_if, self.failure_if = success_if, failure_if
        self.on_success, self.on_failure, self.post = on_success, on_failure, post
        self.env = program_client(self, ctx, (skip_if, while_, success_if, failure_if,
                                              on_success, on_failure, post))

    def _test(self, program: Program | None) -> bool:
        return program is not None and program.test(self.env)

    def decide(self) -> TickGen:
        child = self.decorated
        try:
            outcome: Outcome
            if child.status != Status.RUNNING:
                if self._test(self.failure_if):
                    outcome = Status.FAILURE
                elif self._test(self.success_if):
                    outcome = Status.SUCCESS
                elif self._test(self.skip_if) or (
                    self.while_ is not None and not self.while_.test(self.env)
                ):
                    outcome = None
                else:
                    outcome = yield from tick_child(child)
            elif self.while_ is not None and not self.while_.test(self.env):
                halt(child)
                outcome = None
            else:
                outcome = yield from tick_child(child)
            if outcome == Status.SUCCESS and self.on_success is not None:
                self.on_success.run(self.env)
            elif outcome == Status.FAILURE and self.on_failure is not None:
                self.on_failure.run(self.env)
            if outcome in (Status.SUCCESS, Status.FAILURE) and self.post is not None:
                self.post.run(self.env)
        except ScriptError as exc:
            self.feedback_message = f"script error: {exc}"
            halt(child)
            return Status.FAILURE
        self.feedback_message = "skipped" if outcome is None else ""
        return outcome


class TickAfterTimeout(BtDecorator):
    """Skip the child until `timeout` seconds passed since its last success (Panther node).

    The timer starts when the tree is set up (BT.CPP: when the node is created), so a child
    under ``TickAfterTimeout(60)`` first runs a minute after start.
    """

    PORTS: ClassVar[dict[str, PortSpec]] = {
        "timeout": PortSpec("float", description="time in s to wait before ticking child again"),
    }

    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, ctx: NodeContext,
                 timeout: Any) -> None:
        super().__init__(name=name, child=child)
        self.ctx = ctx
        self.ports = Ports(f"TickAfterTimeout '{name}'", self.PORTS, {"timeout": timeout})
        bind_ports(self, ctx, self.ports)
        self.last_success: float | None = None

    def setup(self, **kwargs: Any) -> None:
        self.last_success = self.ctx.clock.now()

    def decide(self) -> TickGen:
        now = self.ctx.clock.now()
        if self.last_success is None:
            self.last_success = now
        if now - self.last_success < float(self.ports.get("timeout")):
            self.feedback_message = f"next tick in {self.last_success + self.ports.get('timeout') - now:.1f} s"
            return None
        outcome = yield from tick_child(self.decorated)
        if outcome == Status.SUCCESS:
            self.last_success = self.ctx.clock.now()
        self.feedback_message = ""
        return outcome


class Delay(BtDecorator):
    """BT.CPP Delay: RUNNING for ``delay_msec`` milliseconds of the injected clock, then the
    child's outcome; the delay starts over once the child completes or the node is halted
    (BehaviorTree/BehaviorTree.CPP@4.6.2:src/decorators/delay_node.cpp, a standard node the
    husarion_ugv 2.2 Lights tree uses). A skipped child does not restart the delay.
    """

    PORTS: ClassVar[dict[str, PortSpec]] = {
        "delay_msec": PortSpec("int", description="Tick the child after a few milliseconds"),
    }

    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, ctx: NodeContext,
                 ports: dict[str, Any]) -> None:
        super().__init__(name=name, child=child)
        self.ctx = ctx
        self.ports = Ports(f"Delay '{name}'", self.PORTS, ports)
        bind_ports(self, ctx, self.ports)
        self.until: float | None = None

    def decide(self) -> TickGen:
        now = self.ctx.clock.now()
        if self.until is None:
            try:
                msec = int(self.ports.get("delay_msec"))
            except ScriptError as exc:
                self.feedback_message = f"port error: {exc}"
                return Status.FAILURE
            self.until = now + max(msec, 0) / 1000.0
        if now < self.until:
            self.feedback_message = f"child in {self.until - now:.2f} s"
            return Status.RUNNING
        self.feedback_message = ""
        outcome = yield from tick_child(self.decorated)
        if outcome in (Status.SUCCESS, Status.FAILURE):
            self.until = None
        return outcome

    def terminate(self, new_status: Status) -> None:
        if new_status == Status.INVALID and not self.skipped:  # halted: the next tick starts over
            self.until = None


class RunOnce(BtDecorator):
    """Tick the child until it completes once; then skip (``then_skip``) or repeat its result."""

    PORTS: ClassVar[dict[str, PortSpec]] = {"then_skip": PortSpec("bool", True)}

    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, then_skip: Any = True) -> None:
        super().__init__(name=name, child=child)
        self.then_skip = bool(Ports(name, self.PORTS, {"then_skip": then_skip}).values["then_skip"])
        self.returned: Status | None = None

    def decide(self) -> TickGen:
        if self.returned is not None:
            return None if self.then_skip else self.returned
        outcome = yield from tick_child(self.decorated)
        if outcome in (Status.SUCCESS, Status.FAILURE):
            self.returned = outcome
        return outcome


class ForceSuccess(BtDecorator):
    """A completed child counts as SUCCESS."""

    def decide(self) -> TickGen:
        outcome = yield from tick_child(self.decorated)
        return outcome if outcome in (None, Status.RUNNING) else Status.SUCCESS


class ForceFailure(BtDecorator):
    """A completed child counts as FAILURE."""

    def decide(self) -> TickGen:
        outcome = yield from tick_child(self.decorated)
        return outcome if outcome in (None, Status.RUNNING) else Status.FAILURE


class Inverter(BtDecorator):
    """SUCCESS and FAILURE swapped; RUNNING and SKIPPED unchanged."""

    def decide(self) -> TickGen:
        outcome = yield from tick_child(self.decorated)
        if outcome == Status.SUCCESS:
            return Status.FAILURE
        if outcome == Status.FAILURE:
            return Status.SUCCESS
        return outcome


class _Loop(BtDecorator):
    """Tick the child again while it ends with `again`, at most the port's count of times
    (-1: forever), one round per tick; any other outcome of the child ends the loop with it."""

    PORT: ClassVar[str]
    PORTS: ClassVar[dict[str, PortSpec]]
    again: ClassVar[Status]

    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, limit: Any) -> None:
        super().__init__(name=name, child=child)
        self.limit = int(Ports(name, self.PORTS, {self.PORT: limit}).values[self.PORT])
        self.count = 0

    def initialise(self) -> None:
        self.count = 0

    def decide(self) -> TickGen:
        outcome = yield from tick_child(self.decorated)
        if outcome != self.again:
            return outcome
        self.count += 1
        return Status.RUNNING if self.limit < 0 or self.count < self.limit else self.again


class Repeat(_Loop):
    """Run the child `num_cycles` times while it succeeds (-1: forever), one cycle per tick."""

    PORT, again = "num_cycles", Status.SUCCESS
    PORTS: ClassVar[dict[str, PortSpec]] = {PORT: PortSpec("int")}

    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, num_cycles: Any) -> None:
        super().__init__(name, child, num_cycles)


class RetryUntilSuccessful(_Loop):
    """Retry a failing child up to `num_attempts` times (-1: forever), one attempt per tick."""

    PORT, again = "num_attempts", Status.FAILURE
    PORTS: ClassVar[dict[str, PortSpec]] = {PORT: PortSpec("int")}

    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, num_attempts: Any) -> None:
        super().__init__(name, child, num_attempts)


class Precondition(BtDecorator):
    """BT.CPP ``<Precondition if="..." else="FAILURE">``: tick the child only while true."""

    def __init__(self, name: str, child: py_trees.behaviour.Behaviour, ctx: NodeContext,
                 condition: Program, otherwise: Outcome = Status.FAILURE) -> None:
        super().__init__(name=name, child=child)
        self.condition = condition
        self.otherwise = otherwise
        self.env = program_client(self, ctx, (condition,))

    def decide(self) -> TickGen:
        try:
            ok = self.condition.test(self.env)
        except ScriptError as exc:
            self.feedback_message = f"script error: {exc}"
            ok = False
        if not ok:
            halt(self.decorated)
            return self.otherwise
        outcome = yield from tick_child(self.decorated)
        return outcome


class SubTree(BtDecorator):
    """An instantiated ``<SubTree>``: passes its child's outcome through."""

    def decide(self) -> TickGen:
        outcome = yield from tick_child(self.decorated)
        return outcome
