"""BT.CPP v4 semantics of the control nodes and decorators, tick by tick."""

from __future__ import annotations

from typing import Any

import py_trees
import pytest
from py_trees.common import Status

from panther_ops.manager.clock import ManualClock
from panther_ops.manager.nodes.base import PyProgram, ScriptProgram
from panther_ops.manager.nodes.controls import (
    Fallback,
    ReactiveFallback,
    ReactiveSequence,
    Sequence,
)
from panther_ops.manager.nodes.decorators import (
    ForceFailure,
    ForceSuccess,
    Guard,
    Inverter,
    Precondition,
    Repeat,
    RetryUntilSuccessful,
    RunOnce,
)
from tests.manager.doubles import FakeRobotIO, make_ctx, tick

S, F, R = Status.SUCCESS, Status.FAILURE, Status.RUNNING


class Scripted(py_trees.behaviour.Behaviour):
    """Test double: returns the scripted statuses, then the last one; counts ticks/halts."""

    def __init__(self, name: str, *statuses: Status) -> None:
        super().__init__(name)
        self.statuses = list(statuses)
        self.ticks = 0
        self.halts = 0

    def update(self) -> Status:
        self.ticks += 1
        return self.statuses.pop(0) if len(self.statuses) > 1 else self.statuses[0]

    def terminate(self, new_status: Status) -> None:
        if new_status == Status.INVALID and self.status == Status.RUNNING:
            self.halts += 1


def always(value: bool) -> PyProgram:
    return PyProgram(str(value), lambda env: value)


@pytest.fixture
def ctx(clock: ManualClock) -> Any:
    return make_ctx(FakeRobotIO(), clock, {"flag": False, "count": 0})


def skipped(ctx: Any, name: str = "skipped") -> Guard:
    return Guard(Scripted(name, S), ctx, skip_if=always(True))


def test_sequence_resumes_from_the_running_child(ctx: Any) -> None:
    first, second = Scripted("a", S), Scripted("b", R, R, S)
    seq = Sequence("seq", [first, second])
    assert [tick(seq) for _ in range(3)] == [R, R, S]
    assert first.ticks == 1 and second.ticks == 3


def test_sequence_fails_at_once_and_restarts_next_tick(ctx: Any) -> None:
    first, second, third = Scripted("a", S), Scripted("b", F, S), Scripted("c", S)
    seq = Sequence("seq", [first, second, third])
    assert tick(seq) == F and third.ticks == 0
    assert tick(seq) == S and first.ticks == 2 and third.ticks == 1


def test_skipped_children_are_passed_over_and_all_skipped_skips_the_parent(ctx: Any) -> None:
    assert tick(Sequence("all", [skipped(ctx), skipped(ctx)])) is None
    assert tick(Sequence("some", [skipped(ctx), Scripted("a", S)])) == S
    assert tick(Fallback("all", [skipped(ctx), skipped(ctx)])) is None
    assert tick(Fallback("some", [skipped(ctx), Scripted("a", F)])) == F
    assert tick(ReactiveSequence("r", [skipped(ctx)])) is None
    assert tick(ReactiveFallback("r", [skipped(ctx)])) is None


def test_fallback_stops_at_the_first_success_and_resumes_a_running_child(ctx: Any) -> None:
    first, second, third = Scripted("a", F), Scripted("b", R, S), Scripted("c", S)
    fallback = Fallback("fb", [first, second, third])
    assert tick(fallback) == R
    assert tick(fallback) == S
    assert first.ticks == 1 and second.ticks == 2 and third.ticks == 0


def test_reactive_sequence_rechecks_earlier_children_and_halts_the_running_one(ctx: Any) -> None:
    condition, action = Scripted("cond", S, S, F), Scripted("act", R)
    seq = ReactiveSequence("rs", [condition, action])
    assert tick(seq) == R and tick(seq) == R
    assert condition.ticks == 2
    assert tick(seq) == F
    assert action.halts == 1 and action.status == Status.INVALID


def test_reactive_fallback_halts_a_lower_priority_running_child(ctx: Any) -> None:
    high, low = Scripted("high", F, F, S), Scripted("low", R)
    fallback = ReactiveFallback("rf", [high, low])
    assert tick(fallback) == R and tick(fallback) == R
    assert tick(fallback) == S and low.halts == 1


def test_skip_if_is_checked_only_when_the_node_is_not_running(ctx: Any) -> None:
    action = Scripted("act", R, R, S)
    state = {"skip": False}
    guard = Guard(action, ctx, skip_if=PyProgram("skip", lambda env: state["skip"]))
    assert tick(guard) == R
    state["skip"] = True
    assert tick(guard) == R and tick(guard) == S   # still running: not re-checked
    assert tick(guard) is None and action.ticks == 3


def test_while_halts_a_running_node_when_it_turns_false(ctx: Any) -> None:
    action = Scripted("act", R)
    state = {"go": True}
    guard = Guard(action, ctx, while_=PyProgram("go", lambda env: state["go"]))
    assert tick(guard) == R
    state["go"] = False
    assert tick(guard) is None and action.halts == 1


def test_precondition_order_and_post_scripts(ctx: Any) -> None:
    both = Guard(Scripted("a", S), ctx, failure_if=always(True), success_if=always(True))
    assert tick(both) == F
    assert tick(Guard(Scripted("a", F), ctx, success_if=always(True))) == S
    guard = Guard(Scripted("a", S, F), ctx, on_success=ScriptProgram("count += 1"),
                  on_failure=ScriptProgram("count += 10"), post=ScriptProgram("flag = true"))
    tick(guard)
    assert ctx.blackboard.get("count") == 1 and ctx.blackboard.get("flag") is True
    tick(guard)
    assert ctx.blackboard.get("count") == 11


def test_a_script_error_fails_the_node_with_a_message(ctx: Any) -> None:
    guard = Guard(Scripted("a", S), ctx, skip_if=ScriptProgram("missing_entry > 1"))
    assert tick(guard) == F
    assert "missing_entry" in guard.feedback_message


@pytest.mark.parametrize(("then_skip", "after"), [(True, None), (False, F)])
def test_run_once(ctx: Any, then_skip: bool, after: Status | None) -> None:
    child = Scripted("once", R, F)
    once = RunOnce("once", child, then_skip=then_skip)
    assert tick(once) == R and tick(once) == F
    assert tick(once) == after and tick(once) == after and child.ticks == 2


def test_force_and_invert_pass_running_and_skipped_through(ctx: Any) -> None:
    assert tick(ForceSuccess("fs", Scripted("a", F))) == S
    assert tick(ForceFailure("ff", Scripted("a", S))) == F
    assert tick(Inverter("inv", Scripted("a", S))) == F
    assert tick(Inverter("inv", Scripted("a", F))) == S
    assert tick(ForceSuccess("fs", Scripted("a", R))) == R
    assert tick(ForceSuccess("fs", skipped(ctx))) is None
    assert tick(Inverter("inv", skipped(ctx))) is None


def test_repeat_and_retry_finish_at_most_one_cycle_per_tick(ctx: Any) -> None:
    child = Scripted("a", S)
    repeat = Repeat("rep", child, num_cycles=3)
    assert [tick(repeat) for _ in range(3)] == [R, R, S] and child.ticks == 3
    flaky = Scripted("b", F, F, S)
    retry = RetryUntilSuccessful("retry", flaky, num_attempts=5)
    assert [tick(retry) for _ in range(3)] == [R, R, S]
    hopeless = RetryUntilSuccessful("retry", Scripted("c", F), num_attempts=2)
    assert [tick(hopeless) for _ in range(2)] == [R, F]


def test_precondition_decorator_ticks_the_child_only_while_true(ctx: Any) -> None:
    child = Scripted("a", R)
    node = Precondition("pre", child, ctx, ScriptProgram("flag"), otherwise=S)
    assert tick(node) == S and child.ticks == 0
    ctx.blackboard.set("flag", True)
    assert tick(node) == R
    ctx.blackboard.set("flag", False)
    assert tick(node) == S and child.halts == 1
