"""The nodes a BT project may use: kind, ports and how to build each one."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import py_trees
from py_trees.common import Status

from panther_ops.manager.errors import BtProjectError
from panther_ops.manager.nodes import controls, decorators, scripting, services, shutdown, topics
from panther_ops.manager.nodes.base import NodeContext, PortedLeaf, PortSpec, ScriptProgram

Behaviour = py_trees.behaviour.Behaviour
Factory = Callable[[str, NodeContext, dict[str, Any], list[Behaviour]], Behaviour]

PRECONDITIONS = ("_failureIf", "_successIf", "_skipIf", "_while")
POSTCONDITIONS = ("_onSuccess", "_onFailure", "_post")
SCRIPT_ATTRIBUTES = PRECONDITIONS + POSTCONDITIONS


@dataclass(frozen=True)
class NodeType:
    """A node ID: control, decorator, action or condition; its ports; its factory."""

    kind: str
    build: Factory
    ports: Mapping[str, PortSpec] = field(default_factory=dict)
    aliases: Mapping[str, str] = field(default_factory=dict)
    scripts: frozenset[str] = frozenset()
    """Ports holding script code (parsed, names checked)."""
    children: tuple[int, int | None] = (0, 0)
    """Allowed number of children (min, max or None for any)."""


def _single(children: list[Behaviour], name: str) -> Behaviour:
    if len(children) != 1:
        raise BtProjectError(f"decorator '{name}' needs exactly one child, has {len(children)}")
    return children[0]


def _control(cls: type[controls.BtComposite]) -> NodeType:
    return NodeType("control", lambda name, ctx, ports, children: cls(name, children),
                    children=(1, None))


def _decorator(build: Callable[[str, Behaviour, NodeContext, dict[str, Any]], Behaviour],
               ports: Mapping[str, PortSpec] | None = None, scripts: frozenset[str] = frozenset(),
               ) -> NodeType:
    return NodeType("decorator",
                    lambda name, ctx, p, children: build(name, _single(children, name), ctx, p),
                    ports or {}, scripts=scripts, children=(1, 1))


def _leaf(cls: type[PortedLeaf], kind: str = "action") -> NodeType:
    return NodeType(kind, lambda name, ctx, ports, children: cls(name, ctx, **ports),
                    cls.PORTS, cls.ALIASES)


def _status(text: Any) -> Status | None:
    value = str(text).upper()
    if value == "SKIPPED":
        return None
    try:
        return Status[value]
    except KeyError:
        raise BtProjectError(f"'else' must be SUCCESS, FAILURE, RUNNING or SKIPPED, not {text!r}") from None


def _script(kind: str, cls: type[scripting.Script]) -> NodeType:
    return NodeType(kind, lambda name, ctx, p, children: cls(name, ctx, ScriptProgram(str(p["code"]))),
                    {"code": PortSpec("str")}, scripts=frozenset({"code"}))


REGISTRY: dict[str, NodeType] = {
    **{tag: _control(cls) for tag, cls in controls.CONTROLS.items()},
    "IfThenElse": NodeType("control", lambda name, ctx, ports, children: controls.IfThenElse(name, children),
                           children=(2, 3)),
    "Parallel": NodeType("control", lambda name, ctx, ports, children: controls.Parallel(name, children, ctx, ports),
                         controls.Parallel.PORTS, children=(1, None)),
    "Delay": _decorator(decorators.Delay,
                        decorators.Delay.PORTS),
    "ForceSuccess": _decorator(lambda n, c, ctx, p: decorators.ForceSuccess(n, c)),
    "ForceFailure": _decorator(lambda n, c, ctx, p: decorators.ForceFailure(n, c)),
    "Inverter": _decorator(lambda n, c, ctx, p: decorators.Inverter(n, c)),
    "RunOnce": _decorator(lambda n, c, ctx, p: decorators.RunOnce(n, c, p.get("then_skip", True)),
                          decorators.RunOnce.PORTS),
    "Repeat": _decorator(lambda n, c, ctx, p: decorators.Repeat(n, c, p["num_cycles"]),
                         decorators.Repeat.PORTS),
    "RetryUntilSuccessful": _decorator(
        lambda n, c, ctx, p: decorators.RetryUntilSuccessful(n, c, p["num_attempts"]),
        decorators.RetryUntilSuccessful.PORTS),
    "TickAfterTimeout": _decorator(
        lambda n, c, ctx, p: decorators.TickAfterTimeout(n, c, ctx, p["timeout"]),
        decorators.TickAfterTimeout.PORTS),
    "Precondition": _decorator(
        lambda n, c, ctx, p: decorators.Precondition(n, c, ctx, ScriptProgram(str(p["if"])),
                                                     _status(p.get("else", "FAILURE"))),
        {"if": PortSpec("str"), "else": PortSpec("str", "FAILURE")}, frozenset({"if"})),
    "CallSetBoolService": _leaf(services.CallSetBoolService),
    "CallTriggerService": _leaf(services.CallTriggerService),
    "CallSetLedAnimationService": _leaf(services.CallSetLedAnimationService),
    "CheckStringMsg": _leaf(topics.CheckStringMsg, "condition"),
    "SignalShutdown": _leaf(shutdown.SignalShutdown),
    "ShutdownSingleHost": _leaf(shutdown.ShutdownSingleHost),
    "ShutdownHostsFromFile": _leaf(shutdown.ShutdownHostsFromFile),
    "ExecuteCommand": _leaf(shutdown.ExecuteCommand),
    "Script": _script("action", scripting.Script),
    "ScriptCondition": _script("condition", scripting.ScriptCondition),
    "SetBlackboard": NodeType(
        "action",
        lambda n, ctx, p, ch: scripting.SetBlackboard(n, ctx, p["value"], str(p["output_key"])),
        {"value": PortSpec("str"), "output_key": PortSpec("str")}),
    "Sleep": NodeType("action", lambda n, ctx, p, ch: scripting.Sleep(n, ctx, p["msec"]),
                      scripting.Sleep.PORTS),
    "AlwaysSuccess": NodeType("action", lambda n, ctx, p, ch: scripting.AlwaysSuccess(n)),
    "AlwaysFailure": NodeType("action", lambda n, ctx, p, ch: scripting.AlwaysFailure(n)),
}
"""Every node the manager can build, by BT.CPP ID (SubTree is handled by the builder)."""

GENERIC_TAGS = {"Action", "Condition", "Decorator", "Control"}
"""BT.CPP v3-style ``<Action ID="X">`` elements are accepted too."""
