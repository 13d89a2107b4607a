"""Parallel and Delay: standard BehaviorTree.CPP v4 nodes that husarion_ugv 2.2's stock Lights
tree uses (issue 24, finding 1). Their behaviour follows BehaviorTree/BehaviorTree.CPP@4.6.2
src/controls/parallel_node.cpp and src/decorators/delay_node.cpp.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from py_trees.common import Status

from panther_ops.manager.blackboard import TreeBlackboard
from panther_ops.manager.bt.project import load_bt_project
from panther_ops.manager.bt.validate import validate_bt_project
from panther_ops.manager.clock import ManualClock
from panther_ops.manager.errors import BtProjectError
from tests.manager.doubles import FakeRobotIO, make_ctx, tick


def write(path: Path, body: str) -> Path:
    path.write_text(f'<?xml version="1.0"?>\n<root BTCPP_format="4">\n{body}\n</root>\n')
    return path


BOARD: dict[str, TreeBlackboard] = {}


def build(tmp_path: Path, clock: ManualClock, body: str, entries: dict[str, object] | None = None) -> Any:
    project = load_bt_project(write(tmp_path / "t.xml", f'<BehaviorTree ID="T">{body}</BehaviorTree>'))
    ctx = make_ctx(FakeRobotIO(), clock, entries)
    BOARD["last"] = ctx.blackboard
    return project.build("T", ctx)


def board() -> TreeBlackboard:
    return BOARD["last"]


def test_parallel_with_the_default_counts_succeeds_when_every_child_has(tmp_path: Path, clock: ManualClock) -> None:
    # success_count -1: all children; a child that completed is not ticked again in the round
    root = build(tmp_path, clock, """
      <Parallel failure_count="1" success_count="-1">
        <Script code="a += 1"/>
        <Sleep msec="200"/>
      </Parallel>""", {"a": 0})
    assert tick(root) == Status.RUNNING
    clock.advance(0.1)
    assert tick(root) == Status.RUNNING
    clock.advance(0.2)
    assert tick(root) == Status.SUCCESS
    assert board().get("a") == 1  # the Script ran once in the round
    assert tick(root) == Status.RUNNING  # a new round
    assert board().get("a") == 2


@pytest.mark.parametrize(("counts", "children", "decided", "sleeper"), [
    # the Sleep ticked first, RUNNING, is halted (BT.CPP resetChildren)
    pytest.param('failure_count="1" success_count="-1"', '<Sleep msec="500"/><AlwaysFailure/>', Status.FAILURE, 0,
                 id="fails-at-failure-count-and-halts-the-running-child"),
    # the Sleep after the deciding child is never started
    pytest.param('success_count="1" failure_count="2"', '<AlwaysSuccess/><Sleep msec="500"/>', Status.SUCCESS, 1,
                 id="success-count-reached-before-the-last-child"),
])
def test_parallel_decides_at_its_count_and_leaves_the_sleep_invalid(
        tmp_path: Path, clock: ManualClock, counts: str, children: str, decided: Status, sleeper: int) -> None:
    root = build(tmp_path, clock, f"<Parallel {counts}>{children}</Parallel>")
    assert tick(root) == decided
    assert root.children[sleeper].status == Status.INVALID


def test_parallel_counts_skipped_children_as_successes_with_a_negative_success_count(
        tmp_path: Path, clock: ManualClock) -> None:
    root = build(tmp_path, clock, """
      <Parallel failure_count="1" success_count="-1">
        <AlwaysSuccess/>
        <AlwaysSuccess _skipIf="true"/>
      </Parallel>""")
    assert tick(root) == Status.SUCCESS
    all_skipped = build(tmp_path, clock, """
      <Parallel failure_count="1" success_count="2">
        <AlwaysSuccess _skipIf="true"/>
        <AlwaysSuccess _skipIf="true"/>
      </Parallel>""")
    assert tick(all_skipped) is None  # SKIPPED when every child was skipped


def test_delay_waits_then_returns_the_childs_outcome_and_starts_over(tmp_path: Path, clock: ManualClock) -> None:
    root = build(tmp_path, clock, '<Delay delay_msec="300"><Script code="n += 1"/></Delay>', {"n": 0})
    assert tick(root) == Status.RUNNING
    clock.advance(0.299)
    assert tick(root) == Status.RUNNING
    assert board().get("n") == 0
    clock.advance(0.001)
    assert tick(root) == Status.SUCCESS
    assert board().get("n") == 1
    assert tick(root) == Status.RUNNING  # the next run waits again


def test_delay_halted_starts_over(tmp_path: Path, clock: ManualClock) -> None:
    root = build(tmp_path, clock, """
      <ReactiveSequence>
        <ScriptCondition code="go"/>
        <Delay delay_msec="1000"><AlwaysSuccess/></Delay>
      </ReactiveSequence>""", {"go": True})
    assert tick(root) == Status.RUNNING
    clock.advance(0.6)
    board().set("go", False)
    assert tick(root) == Status.FAILURE  # the Delay is halted
    board().set("go", True)
    clock.advance(0.6)
    assert tick(root) == Status.RUNNING  # 1 s from now again, not from the first start
    clock.advance(1.0)
    assert tick(root) == Status.SUCCESS


def test_the_22_lights_tree_shape_validates_and_builds(tmp_path: Path, clock: ManualClock) -> None:
    """A Lights project shaped like husarion_ugv_ros@2.2.2:husarion_ugv_manager/behavior_trees/lights.xml:
    a Parallel of SubTrees (_autoremap), Delays with _skipIf under a Parallel, backslash-continued
    scripts. Written here from those facts."""
    write(tmp_path / "lights.xml", """
      <BehaviorTree ID="Battery">
        <Parallel name="ChargingSequence" failure_count="1" success_count="-1"
                  _skipIf="battery_status != POWER_SUPPLY_STATUS_CHARGING \\&#10;&amp;&amp; battery_status != POWER_SUPPLY_STATUS_FULL">
          <Delay delay_msec="300" _skipIf="current_anim_id == CHARGING_BATTERY_ANIM_ID">
            <CallSetLedAnimationService id="{CHARGING_BATTERY_ANIM_ID}" param="" repeating="false"
                                        service_name="lights/set_animation"/>
          </Delay>
          <Delay delay_msec="2500" _skipIf="battery_percent_round == 1.0">
            <CallSetLedAnimationService id="{CHARGING_BATTERY_ANIM_ID}" param="{battery_percent_round}"
                                        repeating="true" service_name="lights/set_animation"
                                        _onSuccess="charging_anim_percent = battery_percent_round; \\&#10;current_anim_id = CHARGING_BATTERY_ANIM_ID"/>
          </Delay>
        </Parallel>
      </BehaviorTree>
      <BehaviorTree ID="Lights">
        <Parallel failure_count="1" success_count="-1">
          <SubTree ID="Battery" _autoremap="true"/>
        </Parallel>
      </BehaviorTree>""")
    project = write(tmp_path / "LightsBT.btproj", '<include path="lights.xml"/>')
    assert [f for f in validate_bt_project(project) if f.severity.value == "error"] == []


@pytest.mark.parametrize(("body", "code"), [
    ('<Parallel success_count="3"><AlwaysSuccess/><AlwaysSuccess/></Parallel>', "bt-parallel-count"),
    ('<Parallel failure_count="5"><AlwaysSuccess/></Parallel>', "bt-parallel-count"),
    ('<Parallel success_count="all"><AlwaysSuccess/></Parallel>', "bt-port-value"),
    ("<Delay><AlwaysSuccess/></Delay>", "bt-port-missing"),
    ('<Delay delay_msec="soon"><AlwaysSuccess/></Delay>', "bt-port-value"),
    ('<Delay delay_msec="5"><AlwaysSuccess/><AlwaysSuccess/></Delay>', "bt-children"),
])
def test_parallel_and_delay_mistakes_are_findings(tmp_path: Path, body: str, code: str) -> None:
    write(tmp_path / "lights.xml", f'<BehaviorTree ID="Lights">{body}</BehaviorTree>')
    found = validate_bt_project(write(tmp_path / "P.btproj", '<include path="lights.xml"/>'))
    assert code in [f.code for f in found if f.severity.value == "error"], found


def test_delay_without_its_port_does_not_build(tmp_path: Path, clock: ManualClock) -> None:
    with pytest.raises(BtProjectError, match="delay_msec"):
        build(tmp_path, clock, "<Delay><AlwaysSuccess/></Delay>")
