"""Control nodes with BehaviorTree.CPP v4 semantics, as py_trees composites.

* `Sequence` / `Fallback` remember the running child and resume from it.
* `ReactiveSequence` / `ReactiveFallback` re-tick every child from the first one each tick
  and halt a child that was running when an earlier one takes over.
* A skipped child is passed over; when all children were skipped the composite is skipped.
"""

from __future__ import annotations

from collections.abc import Iterator
from collections.abc import Sequence as SequenceOf
from typing import ClassVar

import py_trees
from py_trees.common import Status

from panther_ops.manager.nodes.base import Outcome, TickGen, finish, halt, tick_child

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


def run_outcome(node: py_trees.behaviour.Behaviour) -> Outcome:
    """Tick a whole tree once; return its outcome (None when the root was skipped)."""
    for _ in node.tick():
        pass
    return None if getattr(node, "skipped", False) else node.status


CONTROLS: dict[str, type[BtComposite]] = {
    "Sequence": Sequence,
    "Fallback": Fallback,
    "ReactiveSequence": ReactiveSequence,
    "ReactiveFallback": ReactiveFallback,
}
