"""IfThenElse and CheckStringMsg: the nodes husarion_ugv 2.3.2's stock Lights tree adds
(husarion_ugv_ros@2.3.2:husarion_ugv_manager/behavior_trees/lights.xml). IfThenElse follows
BehaviorTree/BehaviorTree.CPP@4.9.0:src/controls/if_then_else_node.cpp; CheckStringMsg
husarion_ugv_ros@2.3.2:husarion_ugv_manager/src/plugins/condition/check_string_msg.cpp.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from py_trees.common import Status

from panther_ops.manager.bt.project import load_bt_project
from panther_ops.manager.clock import ManualClock
from panther_ops.manager.errors import BtProjectError, ScenarioError
from panther_ops.manager.robot_io import StringMsg
from panther_ops.manager.sim.model import PantherModel
from tests.manager.doubles import FakeRobotIO, make_ctx, tick
from tests.manager.test_bt_standard_nodes import write

MUX = "twist_mux_controller/source"


def build(tmp_path: Path, clock: ManualClock, body: str, entries: dict[str, object] | None = None) -> Any:
    """The tree ``T`` of ``body`` and its context (its blackboard, its topics)."""
    ctx = make_ctx(FakeRobotIO(), clock, entries)
    project = load_bt_project(write(tmp_path / "t.xml", f'<BehaviorTree ID="T">{body}</BehaviorTree>'))
    return project.build("T", ctx), ctx


def test_if_then_else_picks_the_branch_and_resumes_it(tmp_path: Path, clock: ManualClock) -> None:
    root, ctx = build(tmp_path, clock, """
      <IfThenElse>
        <ScriptCondition code="go"/>
        <Sleep msec="200"/>
        <Script code="other += 1"/>
      </IfThenElse>""", {"go": True, "other": 0})
    assert tick(root) == Status.RUNNING
    ctx.blackboard.set("go", False)  # the running branch is resumed, the condition not re-checked
    clock.advance(0.3)
    assert tick(root) == Status.SUCCESS
    assert ctx.blackboard.get("other") == 0
    assert tick(root) == Status.SUCCESS  # now the else branch
    assert ctx.blackboard.get("other") == 1


def test_if_then_else_without_else_fails_and_takes_two_or_three_children(tmp_path: Path,
                                                                          clock: ManualClock) -> None:
    root, _ = build(tmp_path, clock, '<IfThenElse><ScriptCondition code="false"/><AlwaysSuccess/></IfThenElse>')
    assert tick(root) == Status.FAILURE
    with pytest.raises(BtProjectError, match="children"):
        build(tmp_path, clock, '<IfThenElse><AlwaysSuccess/></IfThenElse>')


def test_check_string_msg_compares_the_last_message(tmp_path: Path, clock: ManualClock) -> None:
    root, ctx = build(tmp_path, clock, f'<CheckStringMsg topic_name="{MUX}" data="manual"/>')
    assert tick(root) == Status.FAILURE  # no message yet
    ctx.topics.put(StringMsg(MUX, "manual"))
    assert tick(root) == Status.SUCCESS
    assert tick(root) == Status.SUCCESS  # latched
    ctx.topics.put(StringMsg("/" + MUX, "autonomous"))
    assert tick(root) == Status.FAILURE


def test_sim_robot_publishes_the_mux_source_only_when_it_has_one() -> None:
    model = PantherModel()
    assert not [m for m in model.messages() if isinstance(m, StringMsg)]
    model.set("mux_source", "manual")
    assert [m for m in model.messages() if isinstance(m, StringMsg)] == [StringMsg(MUX, "manual")]
    with pytest.raises(ScenarioError, match="mux_source is one of"):
        model.set("mux_source", "joystick")
