"""BT.CPP's built-in leaves: Script, ScriptCondition, SetBlackboard, Sleep, AlwaysSuccess/Failure."""

from __future__ import annotations

from typing import Any, ClassVar

import py_trees
from py_trees.common import Status

from panther_ops.manager.errors import ScriptError
from panther_ops.manager.nodes.base import (
    NodeContext,
    Ports,
    PortSpec,
    Program,
    Ref,
    bind_ports,
    program_client,
)


class Script(py_trees.behaviour.Behaviour):
    """Run a script (assignments); SUCCESS, or FAILURE when it cannot be evaluated."""

    def __init__(self, name: str, ctx: NodeContext, code: Program) -> None:
        super().__init__(name)
        self.code = code
        self.env = program_client(self, ctx, (code,))

    def update(self) -> Status:
        try:
            self.code.run(self.env)
        except ScriptError as exc:
            self.feedback_message = f"script error: {exc}"
            return Status.FAILURE
        return Status.SUCCESS


class ScriptCondition(Script):
    """SUCCESS when the expression is true, FAILURE otherwise."""

    def update(self) -> Status:
        try:
            ok = self.code.test(self.env)
        except ScriptError as exc:
            self.feedback_message = f"script error: {exc}"
            return Status.FAILURE
        return Status.SUCCESS if ok else Status.FAILURE


class SetBlackboard(py_trees.behaviour.Behaviour):
    """BT.CPP SetBlackboard: copy `value` (a literal or ``{key}``) to `output_key`."""

    def __init__(self, name: str, ctx: NodeContext, value: Any, output_key: str) -> None:
        super().__init__(name)
        self.value = Ref(ctx.resolve(value.key)) if isinstance(value, Ref) else value
        self.key = ctx.resolve(output_key.strip("{}"))
        reads = [self.value.key] if isinstance(self.value, Ref) else []
        self.client = ctx.blackboard.client(self, reads=reads, writes=[self.key])

    def update(self) -> Status:
        value = self.client.get(self.value.key) if isinstance(self.value, Ref) else self.value
        self.client.set(self.key, value)
        return Status.SUCCESS


class Sleep(py_trees.behaviour.Behaviour):
    """RUNNING for `msec` milliseconds of the injected clock, then SUCCESS."""

    PORTS: ClassVar[dict[str, PortSpec]] = {"msec": PortSpec("float")}

    def __init__(self, name: str, ctx: NodeContext, msec: Any) -> None:
        super().__init__(name)
        self.ctx = ctx
        self.ports = Ports(f"Sleep '{name}'", self.PORTS, {"msec": msec})
        bind_ports(self, ctx, self.ports)
        self.until = 0.0

    def initialise(self) -> None:
        self.until = self.ctx.clock.now() + float(self.ports.get("msec")) / 1000.0

    def update(self) -> Status:
        return Status.SUCCESS if self.ctx.clock.now() >= self.until else Status.RUNNING


class AlwaysSuccess(py_trees.behaviour.Behaviour):
    """SUCCESS."""

    def update(self) -> Status:
        return Status.SUCCESS


class AlwaysFailure(py_trees.behaviour.Behaviour):
    """FAILURE."""

    def update(self) -> Status:
        return Status.FAILURE
