"""The manager's tick loop: messages in, Lights and Safety ticked, Shutdown when signalled.

Like the C++ lights_manager and safety_manager nodes: each tree is ticked at its
``timer_frequency`` once its required entries arrived; when the Safety tree sets
``signal_shutdown`` (or the power button is pressed) the Safety tree is halted and the
Shutdown tree is ticked at ``shutdown_frequency`` (30 Hz) until it is no longer RUNNING.
Every tick is non-blocking; the loop sleeps on the injected clock between ticks.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from enum import Enum
from pathlib import Path
from typing import Any

import py_trees
from py_trees.common import Status

from panther_ops.manager import keys
from panther_ops.manager.adapters.interfaces import PANTHER_2_1, RosInterfaces
from panther_ops.manager.blackboard import TreeBlackboard
from panther_ops.manager.clock import Clock
from panther_ops.manager.config import (
    ManagerConfig,
    lights_constants,
    safety_constants,
    shutdown_constants,
)
from panther_ops.manager.constants import ANIMATION_ID_CONSTANTS, LIGHTS_TREE, SAFETY_TREE, SHUTDOWN_TREE
from panther_ops.manager.inputs import InputFeeder, ready
from panther_ops.manager.nodes.base import NodeContext, was_skipped
from panther_ops.manager.nodes.decorators import Guard
from panther_ops.manager.robot_io import RobotIO, TopicLatch
from panther_ops.manager.shutdown_executor.backends import ShutdownBackends

TreeBuilder = Callable[[NodeContext], py_trees.behaviour.Behaviour]


@dataclass(frozen=True)
class TreeSource:
    """Where the three trees come from: the Python builders or a BT project's XML."""

    lights: TreeBuilder
    safety: TreeBuilder
    shutdown: TreeBuilder
    origin: str

    @classmethod
    def python(cls) -> TreeSource:
        """The trees built in Python (`panther_ops.manager.trees`)."""
        from panther_ops.manager.trees.lights import build_lights_tree
        from panther_ops.manager.trees.safety import build_safety_tree, build_shutdown_tree

        return cls(build_lights_tree, build_safety_tree, build_shutdown_tree, "python")

    @classmethod
    def projects(cls, lights_project: str | Path, safety_project: str | Path) -> TreeSource:
        """Trees ``Lights`` from one .btproj, ``Safety`` and ``Shutdown`` from another."""
        from panther_ops.manager.bt.project import load_bt_project

        lights = load_bt_project(lights_project)
        safety = load_bt_project(safety_project)
        return cls(lambda ctx: lights.build(LIGHTS_TREE, ctx),
                   lambda ctx: safety.build(SAFETY_TREE, ctx),
                   lambda ctx: safety.build(SHUTDOWN_TREE, ctx),
                   f"{lights_project} + {safety_project}")


def lights_entries(config: ManagerConfig, interfaces: RosInterfaces) -> dict[str, Any]:
    """The Lights tree's initial blackboard as the stack's lights manager makes it: the
    parameters' constants, the stack's animation numbers and state entries."""
    out = {k: v for k, v in lights_constants(config.lights).items() if k not in ANIMATION_ID_CONSTANTS}
    out.update(interfaces.animation_ids)
    out.update(interfaces.lights_state)
    return out


class Mode(str, Enum):
    """Where the manager is."""

    RUNNING = "running"
    SHUTTING_DOWN = "shutting_down"
    DONE = "done"


@dataclass(frozen=True)
class TreeTick:
    """One tree's result in a tick: status (or SKIPPED / WAITING) and the active branch."""

    status: str
    branch: str


@dataclass(frozen=True)
class TickReport:
    """What one manager tick did."""

    time: float
    mode: Mode
    lights: TreeTick | None
    safety: TreeTick | None
    shutdown: TreeTick | None
    shutdown_reason: str | None


def branch_of(node: py_trees.behaviour.Behaviour | None) -> str:
    """Names from the root down to `node` (Guard wrappers omitted)."""
    names: list[str] = []
    while node is not None:
        if not isinstance(node, Guard):
            names.append(node.name)
        node = node.parent
    return " / ".join(reversed(names))


def tick_tree(root: py_trees.behaviour.Behaviour) -> TreeTick:
    """Tick a tree once; report its status and the branch of the leaf that acted.

    The branch is the running leaf if there is one, else the last leaf that ran (was not
    skipped) in this tick, else empty (everything was skipped).
    """
    acted: py_trees.behaviour.Behaviour | None = None
    running: py_trees.behaviour.Behaviour | None = None
    for node in root.tick():
        if not node.children and not was_skipped(node):
            acted = node
            if running is None and node.status == Status.RUNNING:
                running = node
    status = "SKIPPED" if was_skipped(root) else root.status.value
    return TreeTick(status, branch_of(running or acted))


class _Schedule:
    """Due times on a fixed grid (start + n / frequency): no drift, missed slots skipped."""

    def __init__(self, start: float, frequency: float) -> None:
        self.start = start
        self.frequency = frequency
        self.ticks = 0

    @property
    def next(self) -> float:
        return self.start + self.ticks / self.frequency

    def due(self, now: float) -> bool:
        """True (and the slot is used) when a tick is due at `now`."""
        if now + 1e-9 < self.next:
            return False
        self.ticks = max(self.ticks + 1, int((now - self.start) * self.frequency + 1e-9) + 1)
        return True


class ManagerRuntime:
    """The three trees, their blackboards and the inputs, ticked on an injected clock."""

    def __init__(self, config: ManagerConfig, io: RobotIO, clock: Clock, *,
                 trees: TreeSource | None = None, backends: ShutdownBackends | None = None,
                 interfaces: RosInterfaces | None = None) -> None:
        self.config = config
        self.interfaces = interfaces or PANTHER_2_1
        self.io = io
        self.clock = clock
        self.trees = trees or TreeSource.python()
        self.backends = backends
        self.lights_bb = TreeBlackboard(LIGHTS_TREE)
        self.safety_bb = TreeBlackboard(SAFETY_TREE)
        self.shutdown_bb = TreeBlackboard(SHUTDOWN_TREE)
        self.lights_bb.update(lights_entries(config, self.interfaces))
        self.safety_bb.update(safety_constants(config.safety))
        self.safety_bb.update({keys.SIGNAL_SHUTDOWN: (False, ""), keys.FAN_TURNED_ON: False})
        self.shutdown_bb.update(shutdown_constants(config.safety))
        self.shutdown_bb.set(keys.SIGNAL_SHUTDOWN, (False, ""))
        self.topics = TopicLatch()
        self.lights = self.trees.lights(self._ctx(self.lights_bb, config.lights.service_timeout))
        self.safety = self.trees.safety(self._ctx(self.safety_bb, config.safety.service_timeout))
        self.shutdown = self.trees.shutdown(self._ctx(self.shutdown_bb,
                                                      config.safety.service_timeout))
        self.feeder = InputFeeder(config, self.lights_bb, self.safety_bb, self.topics)
        self.mode = Mode.RUNNING
        self.shutdown_reason: str | None = None
        self.shutdown_status: str | None = None
        self._set_up = False

    def _ctx(self, blackboard: TreeBlackboard, service_timeout: float) -> NodeContext:
        return NodeContext(self.io, self.clock, blackboard, self.backends, service_timeout, topics=self.topics)

    def setup(self) -> None:
        """Set every behaviour up (starts TickAfterTimeout timers); done once, at start."""
        if not self._set_up:
            for root in (self.lights, self.safety, self.shutdown):
                root.setup_with_descendants()
            self._set_up = True

    def begin_shutdown(self, reason: str) -> None:
        """Halt Safety and start ticking the Shutdown tree."""
        if self.mode is not Mode.RUNNING:
            return
        self.safety.stop(Status.INVALID)
        self.mode = Mode.SHUTTING_DOWN
        self.shutdown_reason = reason
        self.shutdown_bb.set(keys.SIGNAL_SHUTDOWN, (True, reason))

    def tick(self, *, lights: bool = True, safety: bool = True) -> TickReport:
        """Read messages, then tick the due trees once. Never blocks."""
        self.setup()
        reason = self.feeder.apply_all(self.io.drain())
        lights_tick = safety_tick = shutdown_tick = None
        if lights and self.mode is not Mode.DONE:
            lights_tick = (tick_tree(self.lights) if ready(self.lights_bb, keys.LIGHTS_REQUIRED)
                           else TreeTick("WAITING", ""))
        if self.mode is Mode.RUNNING:
            if safety:
                safety_tick = (tick_tree(self.safety) if ready(self.safety_bb, keys.SAFETY_REQUIRED)
                               else TreeTick("WAITING", ""))
            flag, why = self.safety_bb.get(keys.SIGNAL_SHUTDOWN, (False, ""))
            if reason is not None or flag:
                self.begin_shutdown(reason or str(why))
        elif self.mode is Mode.SHUTTING_DOWN and safety:
            shutdown_tick = tick_tree(self.shutdown)
            if shutdown_tick.status != Status.RUNNING.value:
                self.mode = Mode.DONE
                self.shutdown_status = shutdown_tick.status
        return TickReport(self.clock.now(), self.mode, lights_tick, safety_tick, shutdown_tick,
                          self.shutdown_reason)

    def run(self, *, duration: float | None = None,
            stop: Callable[[TickReport], bool] | None = None) -> TickReport | None:
        """Tick at the configured rates until DONE, `duration` passed or `stop(report)`."""
        start = self.clock.now()
        lights = _Schedule(start, self.config.lights.timer_frequency)
        safety = _Schedule(start, self.config.safety.timer_frequency)
        report: TickReport | None = None
        while self.mode is not Mode.DONE:
            now = self.clock.now()
            if duration is not None and now - start >= duration - 1e-9:
                break
            mode = self.mode
            report = self.tick(lights=lights.due(now), safety=safety.due(now))
            if self.mode is not mode:  # shutting down: the Shutdown tree's own rate from now
                safety = _Schedule(now, self.config.safety.shutdown_frequency)
                safety.ticks = 1
            if stop is not None and stop(report):
                break
            self.clock.sleep(max(0.0, min(lights.next, safety.next) - self.clock.now()))
        return report

    def blackboards(self) -> dict[str, dict[str, Any]]:
        """All entries of the three trees (for status output and tests)."""
        return {LIGHTS_TREE: self.lights_bb.entries(), SAFETY_TREE: self.safety_bb.entries(),
                SHUTDOWN_TREE: self.shutdown_bb.entries()}

    def close(self) -> None:
        """Halt the trees and drop their blackboard entries."""
        for root in (self.lights, self.safety, self.shutdown):
            root.stop(Status.INVALID)
            for node in root.iterate():
                node.shutdown()
        for bb in (self.lights_bb, self.safety_bb, self.shutdown_bb):
            bb.clear()
