"""What every manager behaviour shares: context, ports, blackboard access, SKIPPED.

BehaviorTree.CPP v4 has a fifth status, SKIPPED, that py_trees lacks: a node whose
precondition says "skip" is not run and its parent moves on as if it were not there; a
Sequence whose children were all skipped is itself skipped. The Panther trees rely on it
(TickAfterTimeout only restarts its timer when the child really succeeded). Here a skipped
behaviour ends the tick with status INVALID (BT.CPP keeps it IDLE) and ``skipped = True``;
the composites and decorators of this package read that flag.
"""

from __future__ import annotations

from collections.abc import Callable, Generator, Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar

import py_trees
from py_trees.common import Status

from panther_ops.manager.blackboard import TreeBlackboard
from panther_ops.manager.bt.expression import Env, format_value, parse, to_number, truthy
from panther_ops.manager.clock import Clock
from panther_ops.manager.errors import BtProjectError, ScriptError
from panther_ops.manager.robot_io import RobotIO, TopicLatch

if TYPE_CHECKING:
    from panther_ops.manager.shutdown_executor.backends import ShutdownBackends

Outcome = Status | None
"""A tick's result inside this package: a py_trees status, or None for SKIPPED."""
TickGen = Generator[py_trees.behaviour.Behaviour, None, Outcome]


@dataclass
class NodeContext:
    """What behaviours of one tree use: the robot, the clock and the tree's blackboard."""

    io: RobotIO
    clock: Clock
    blackboard: TreeBlackboard
    shutdown: ShutdownBackends | None = None
    service_timeout: float = 1.0
    resolve: Callable[[str], str] = field(default=lambda name: name.lstrip("@"))
    """Maps a name used in the tree to its blackboard key (SubTree scopes)."""
    topics: TopicLatch = field(default_factory=TopicLatch)
    """The last message of each string topic (CheckStringMsg), fed by the runtime's inputs."""

    def scoped(self, resolve: Callable[[str], str]) -> NodeContext:
        """The same context seen from a subtree scope."""
        return NodeContext(self.io, self.clock, self.blackboard, self.shutdown,
                           self.service_timeout, resolve, self.topics)


def was_skipped(node: py_trees.behaviour.Behaviour) -> bool:
    """True when `node` was skipped in its last tick."""
    return bool(getattr(node, "skipped", False))


def finish(node: py_trees.behaviour.Behaviour, outcome: Outcome) -> Iterator[py_trees.behaviour.Behaviour]:
    """Close a tick of a control node: record SKIPPED or the status, stop when done."""
    if outcome is None:
        node.skipped = True  # type: ignore[attr-defined]
        if node.status != Status.INVALID or any(c.status != Status.INVALID for c in node.children):
            node.stop(Status.INVALID)
        node.status = Status.INVALID
    elif outcome != Status.RUNNING:
        node.stop(outcome)
    else:
        node.status = outcome
    yield node


def tick_child(child: py_trees.behaviour.Behaviour) -> TickGen:
    """Tick a child and return its outcome (None when it skipped itself)."""
    yield from child.tick()
    return None if was_skipped(child) else child.status


def halt(node: py_trees.behaviour.Behaviour) -> None:
    """Halt a node that is running (BT.CPP haltChild)."""
    if node.status == Status.RUNNING:
        node.stop(Status.INVALID)


# ---------------------------------------------------------------- ports


@dataclass(frozen=True)
class Ref:
    """A port value read from the blackboard at tick time (``{key}`` in XML)."""

    key: str


REQUIRED = object()


@dataclass(frozen=True)
class PortSpec:
    """A declared input port: its type ("bool", "int", "float", "str") and default."""

    kind: str
    default: Any = REQUIRED
    description: str = ""


def convert(value: Any, kind: str) -> Any:
    """Convert a port value to its declared kind (XML gives strings)."""
    try:
        if kind == "bool":
            return truthy(value)
        if kind == "int":
            number = to_number(value)
            if number is None or not float(number).is_integer():
                raise ScriptError(f"{value!r} is not an integer")
            return int(number)
        if kind == "float":
            number = to_number(value)
            if number is None:
                raise ScriptError(f"{value!r} is not a number")
            return float(number)
        return format_value(value)
    except ScriptError as exc:
        raise ScriptError(f"expected {kind}: {exc}") from None


class Ports:
    """A behaviour's port values: literals converted once, references read each tick."""

    def __init__(self, owner: str, specs: Mapping[str, PortSpec], values: Mapping[str, Any],
                 aliases: Mapping[str, str] | None = None) -> None:
        self.specs = specs
        self.values: dict[str, Any] = {}
        for name, value in values.items():
            canonical = (aliases or {}).get(name, name)
            if canonical not in specs:
                raise BtProjectError(f"{owner}: unknown port '{name}' (ports: {', '.join(specs)})")
            spec = specs[canonical]
            try:
                self.values[canonical] = value if isinstance(value, Ref) else convert(value, spec.kind)
            except ScriptError as exc:
                raise BtProjectError(f"{owner}: port '{name}': {exc}") from None
        for name, spec in specs.items():
            if name not in self.values:
                if spec.default is REQUIRED:
                    raise BtProjectError(f"{owner}: missing required port '{name}'")
                self.values[name] = spec.default
        self.client: py_trees.blackboard.Client | None = None

    def refs(self) -> list[str]:
        """Blackboard keys the ports read."""
        return [v.key for v in self.values.values() if isinstance(v, Ref)]

    def get(self, name: str) -> Any:
        """The port's value now (reading and converting a blackboard reference)."""
        value = self.values[name]
        if not isinstance(value, Ref):
            return value
        assert self.client is not None, "ports with references need a blackboard client"
        try:
            if py_trees.blackboard.Blackboard.activity_stream is None:
                raw = py_trees.blackboard.Blackboard.storage[self.client.absolute_name(value.key)]
            else:
                raw = self.client.get(value.key)
        except KeyError:
            raise ScriptError(f"port '{name}': '{value.key}' is not on the blackboard") from None
        return convert(raw, self.specs[name].kind)


def bind_ports(behaviour: py_trees.behaviour.Behaviour, ctx: NodeContext, ports: Ports,
               writes: Iterable[str] = ()) -> None:
    """Resolve port references through the scope and attach the behaviour's client."""
    for name, value in list(ports.values.items()):
        if isinstance(value, Ref):
            ports.values[name] = Ref(ctx.resolve(value.key))
    ports.client = ctx.blackboard.client(behaviour, reads=ports.refs(),
                                         writes=[ctx.resolve(w) for w in writes])


class PortedLeaf(py_trees.behaviour.Behaviour):
    """A leaf with declared input ports (the custom Panther nodes)."""

    PORTS: ClassVar[dict[str, PortSpec]] = {}
    ALIASES: ClassVar[dict[str, str]] = {}
    WRITES: ClassVar[tuple[str, ...]] = ()

    def __init__(self, name: str, ctx: NodeContext, **ports: Any) -> None:
        super().__init__(name)
        self.ctx = ctx
        self.ports = Ports(f"{type(self).__name__} '{name}'", self.PORTS, ports, self.ALIASES)
        bind_ports(self, ctx, self.ports, self.WRITES)

    def port(self, name: str) -> Any:
        """Current value of an input port."""
        return self.ports.get(name)


# ---------------------------------------------------------------- programs


class ClientEnv:
    """Script names read and written through a behaviour's blackboard client.

    Reads of declared keys go straight to their storage slots (the client's access check is
    done once, here, rather than on every tick); writes go through the client.
    """

    def __init__(self, client: py_trees.blackboard.Client, resolve: Callable[[str], str]) -> None:
        self.client = client
        self.resolve = resolve
        self.slots: dict[str, str] = {}

    def _slot(self, name: str) -> str:
        slot = self.slots.get(name)
        if slot is None:
            key = self.resolve(name)
            if not self.client.is_registered(key):
                raise ScriptError(f"'{name}' was not declared by this node")
            slot = self.client.absolute_name(key)
            self.slots[name] = slot
        return slot

    def get(self, name: str) -> Any:
        if py_trees.blackboard.Blackboard.activity_stream is not None:
            try:
                return self.client.get(self.resolve(name))
            except KeyError:
                raise ScriptError(f"'{name}' is not on the blackboard") from None
        try:
            return py_trees.blackboard.Blackboard.storage[self._slot(name)]
        except KeyError:
            raise ScriptError(f"'{name}' is not on the blackboard") from None

    def set(self, name: str, value: Any) -> None:
        self.client.set(self.resolve(name), value)

    def exists(self, name: str) -> bool:
        return bool(self.client.exists(self.resolve(name)))


class Program:
    """A condition or script over blackboard entries: the names it reads and writes."""

    reads: frozenset[str]
    writes: frozenset[str]
    text: str

    def run(self, env: Env) -> Any:
        raise NotImplementedError

    def test(self, env: Env) -> bool:
        return truthy(self.run(env))


class PyProgram(Program):
    """A condition or script written in Python, for the trees built in code."""

    def __init__(self, text: str, fn: Callable[[Env], Any], reads: Iterable[str] = (),
                 writes: Iterable[str] = ()) -> None:
        self.text = text
        self.fn = fn
        self.reads = frozenset(reads)
        self.writes = frozenset(writes)

    def run(self, env: Env) -> Any:
        return self.fn(env)


class ScriptProgram(Program):
    """A parsed BT.CPP script (see `bt.expression`)."""

    def __init__(self, source: str) -> None:
        self.script = parse(source)
        self.text = source
        self.reads = self.script.reads
        self.writes = self.script.writes

    def run(self, env: Env) -> Any:
        return self.script.run(env)


def program_client(behaviour: py_trees.behaviour.Behaviour, ctx: NodeContext,
                   programs: Iterable[Program | None]) -> ClientEnv:
    """A client declaring every name the programs read or write, wrapped as an Env."""
    reads: set[str] = set()
    writes: set[str] = set()
    for program in programs:
        if program is not None:
            reads |= {ctx.resolve(n) for n in program.reads}
            writes |= {ctx.resolve(n) for n in program.writes}
    client = ctx.blackboard.client(behaviour, reads=reads, writes=writes)
    return ClientEnv(client, ctx.resolve)
