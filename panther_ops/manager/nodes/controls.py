"""Control nodes with BehaviorTree.CPP v4 semantics, as py_trees composites.

* `Sequence` / `Fallback` remember the running child and resume from it.
* `ReactiveSequence` / `ReactiveFallback` re-tick every child from the first one each tick
  and halt a child that was running when an earlier one takes over.
* A skipped child is passed over; when all children were skipped the composite is skipped.
* `Parallel` ticks every child not yet completed, every tick, and decides by counting
  successes and failures against its ``success_count`` / ``failure_count`` ports
  (BehaviorTree/BehaviorTree.CPP@4.6.2:src/controls/parallel_node.cpp, a standard node the
  husarion_ugv 2.2 Lights tree uses).
"""

from __future__ import annotations

from collections.abc import Iterator
from collections.abc import Sequence as SequenceOf
from typing import ClassVar

import py_trees
from py_trees.common import Status

from panther_ops.manager.errors import ScriptError
from panther_ops.manager.nodes.base import (
    NodeContext,
    Outcome,
    Ports,
    PortSpec,
    TickGen,
    bind_ports,
    finish,
    halt,
    tick_child,
)

Children = SequenceOf[py_trees.behaviour.Behaviour] | None


class BtComposite(py_trees.composites.Composite):
    """Shared tick plumbing: SKIPPED flag, initialise on (re)entry, `finish`.

    The concrete classes also derive from py_trees' Sequence / Selector, so py_trees' display
    and dot rendering draw them with the right symbols; their tick is this one.
    """

    MEMORY: ClassVar[bool]
    """Resume from a running child (py_trees' ``memory``), or start from the first each tick."""

    def __init__(self, name: str, children: Children = None) -> None:
        # the next class in the MRO is py_trees' Sequence or Selector, which take `memory`
        super().__init__(name, memory=self.MEMORY, children=children)  # type: ignore[call-arg]
        self._bt_init()

    def _bt_init(self) -> None:
        self.skipped = False
        self.index = 0
        self.skipped_count = 0

    def tick(self) -> Iterator[py_trees.behaviour.Behaviour]:
        self.skipped = False
        if self.status != Status.RUNNING:
            self.index = 0
            self.skipped_count = 0
            self.initialise()
        outcome = yield from self.run_children()
        yield from finish(self, outcome)

    def run_children(self) -> TickGen:
        raise NotImplementedError

    def halt_others(self, keep: py_trees.behaviour.Behaviour) -> None:
        for child in self.children:
            if child is not keep:
                halt(child)


class ResumingComposite(BtComposite):
    """Children in order, resuming from a running child (Sequence, Fallback).

    `passes` is the child outcome that moves on to the next child; any other ends the tick
    with `decides`. When every child passed, the composite returns `passes` itself.
    """

    MEMORY = True
    passes: ClassVar[Status]
    decides: ClassVar[Status]

    def run_children(self) -> TickGen:
        while self.index < len(self.children):
            child = self.children[self.index]
            self.current_child = child
            outcome = yield from tick_child(child)
            if outcome is None:
                self.skipped_count += 1
            elif outcome == Status.RUNNING:
                return Status.RUNNING
            elif outcome != self.passes:
                self.index = 0
                return self.decides
            self.index += 1
        all_skipped = self.skipped_count == len(self.children)
        self.index = 0
        return None if all_skipped else self.passes


class ReactiveComposite(BtComposite):
    """Every tick from the first child; a child that does not pass halts the others.

    `passes` and `decides` as in `ResumingComposite`.
    """

    MEMORY = False
    passes: ClassVar[Status]
    decides: ClassVar[Status]

    def run_children(self) -> TickGen:
        all_skipped = True
        for child in self.children:
            self.current_child = child
            outcome = yield from tick_child(child)
            if outcome is None:
                continue
            all_skipped = False
            if outcome != self.passes:
                self.halt_others(child)
                return Status.RUNNING if outcome == Status.RUNNING else self.decides
        return None if all_skipped else self.passes


class Sequence(ResumingComposite, py_trees.composites.Sequence):
    """BT.CPP Sequence: children in order; resumes from a running child; fails at once."""

    passes, decides = Status.SUCCESS, Status.FAILURE


class Fallback(ResumingComposite, py_trees.composites.Selector):
    """BT.CPP Fallback: the first child that does not fail decides; resumes a running one."""

    passes, decides = Status.FAILURE, Status.SUCCESS


class ReactiveSequence(ReactiveComposite, py_trees.composites.Sequence):
    """BT.CPP ReactiveSequence: every tick from the first child; conditions are re-checked."""

    passes, decides = Status.SUCCESS, Status.FAILURE


class ReactiveFallback(ReactiveComposite, py_trees.composites.Selector):
    """BT.CPP ReactiveFallback: every tick from the first child; a success ends it."""

    passes, decides = Status.FAILURE, Status.SUCCESS


class Parallel(BtComposite, py_trees.composites.Parallel):
    """BT.CPP Parallel: each tick, every child that has not completed in this round is ticked.

    SUCCESS once ``success_count`` children succeeded (a negative count: all but ``-n - 1``;
    with a negative count a skipped child counts as a success), FAILURE once ``failure_count``
    children failed or success has become impossible; then the children are reset. SKIPPED when
    every child ticked this time was skipped; else RUNNING.
    """

    MEMORY = False
    PORTS: ClassVar[dict[str, PortSpec]] = {
        "success_count": PortSpec("int", -1, "number of children that need to succeed to trigger a SUCCESS"),
        "failure_count": PortSpec("int", 1, "number of children that need to fail to trigger a FAILURE"),
    }

    def __init__(self, name: str, children: Children, ctx: NodeContext, ports: dict[str, object]) -> None:
        py_trees.composites.Parallel.__init__(
            self, name, policy=py_trees.common.ParallelPolicy.SuccessOnAll(synchronise=False), children=children)
        self._bt_init()
        self.ports = Ports(f"Parallel '{name}'", self.PORTS, ports)
        bind_ports(self, ctx, self.ports)
        self.completed: set[int] = set()
        self.successes = 0
        self.failures = 0

    def initialise(self) -> None:
        self.completed.clear()
        self.successes = self.failures = 0

    @staticmethod
    def threshold(count: int, children: int) -> int:
        """A port's count as a number of children (negative: counted from the number of children)."""
        return count if count >= 0 else max(children + count + 1, 0)

    def run_children(self) -> TickGen:
        try:
            success_count = int(self.ports.get("success_count"))
            failure_count = int(self.ports.get("failure_count"))
        except ScriptError as exc:
            self.feedback_message = f"port error: {exc}"
            return Status.FAILURE
        total = len(self.children)
        need_success = self.threshold(success_count, total)
        need_failure = self.threshold(failure_count, total)
        if total < need_success or total < need_failure:
            self.feedback_message = (f"{total} children cannot reach success_count {success_count} / "
                                     f"failure_count {failure_count}")
            return Status.FAILURE
        skipped = 0
        for i, child in enumerate(self.children):
            if i not in self.completed:
                self.current_child = child
                outcome = yield from tick_child(child)
                if outcome is None:
                    skipped += 1
                elif outcome == Status.SUCCESS:
                    self.completed.add(i)
                    self.successes += 1
                elif outcome == Status.FAILURE:
                    self.completed.add(i)
                    self.failures += 1
            if self.successes >= need_success or (success_count < 0 and self.successes + skipped >= need_success):
                self.initialise()
                return Status.SUCCESS
            if total - self.failures < need_success or self.failures == need_failure:
                self.initialise()
                return Status.FAILURE
        return None if skipped == total else Status.RUNNING


def run_outcome(node: py_trees.behaviour.Behaviour) -> Outcome:
    """Tick a whole tree once; return its outcome (None when the root was skipped)."""
    for _ in node.tick():
        pass
    return None if getattr(node, "skipped", False) else node.status


class IfThenElse(BtComposite, py_trees.composites.Sequence):
    """BT.CPP IfThenElse (BehaviorTree.CPP@4.9.0:src/controls/if_then_else_node.cpp): the first child
    is the condition; on SUCCESS the second child runs, on FAILURE the third (FAILURE when there are
    only two); the chosen child is resumed while it runs, and its outcome is the node's."""

    MEMORY = True

    def run_children(self) -> TickGen:
        if self.index == 0:
            condition = self.children[0]
            self.current_child = condition
            outcome = yield from tick_child(condition)
            if outcome == Status.RUNNING:
                return Status.RUNNING
            if outcome == Status.SUCCESS:
                self.index = 1
            elif outcome == Status.FAILURE:
                if len(self.children) < 3:
                    return Status.FAILURE
                self.index = 2
            else:  # a skipped condition: BT.CPP throws "Something unexpected happened in IfThenElseNode"
                raise RuntimeError(f"IfThenElse '{self.name}': its condition was skipped")
        chosen = self.children[self.index]
        self.current_child = chosen
        outcome = yield from tick_child(chosen)
        if outcome == Status.RUNNING:
            return Status.RUNNING
        self.index = 0
        return outcome


CONTROLS: dict[str, type[BtComposite]] = {
    "Sequence": Sequence,
    "Fallback": Fallback,
    "ReactiveSequence": ReactiveSequence,
    "ReactiveFallback": ReactiveFallback,
}
