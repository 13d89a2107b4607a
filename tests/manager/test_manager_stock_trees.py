"""Each release's stock BT project (templates/config/<generation>/<pkg>/behavior_trees, equal to
upstream's: docs/conformance.md) runs on the manager as that release's stock manager runs it:
the blackboard of the stack's lights manager (husarion_ugv 2.2: husarion_ugv_msgs animation
numbers, current_battery_anim_id / current_error_anim_id, drive_state from the joy topic's
dead man button; 2.3.2: GOAL_FAILED/FLOOD_LIGHT numbers, the state animation from the twist mux's
twist_mux_controller/source through CheckStringMsg and IfThenElse), and the stock Safety tree's
own fan timing."""

from __future__ import annotations

from pathlib import Path

import pytest

from panther_ops.manager.adapters.interfaces import (
    HUSARION_UGV_2_2,
    HUSARION_UGV_2_3_2,
    PANTHER_2_0,
    PANTHER_2_1,
    RosInterfaces,
    interfaces_for,
)
from panther_ops.manager.bt.validate import validate_bt_project
from panther_ops.manager.clock import ManualClock
from panther_ops.manager.config import ManagerConfig
from panther_ops.manager.constants import PowerSupplyHealth, PowerSupplyStatus
from panther_ops.manager.robot_io import (
    BatteryMsg,
    DriverStateMsg,
    EStopMsg,
    IOStateMsg,
    JoyMsg,
    RobotMsg,
    StringMsg,
    SystemStatusMsg,
)
from panther_ops.manager.runtime import ManagerRuntime, TreeSource
from tests.manager.doubles import FakeRobotIO

CONFIG = Path(__file__).resolve().parents[2] / "templates" / "config"
STOCK = {  # generation directory, package, lights project, safety project, interfaces
    "2.0.4": ("panther-2.0", "panther_manager", "PantherLightsBT.btproj", "PantherSafetyBT.btproj", PANTHER_2_0),
    "2.1.1": ("panther-2.1", "panther_manager", "PantherLightsBT.btproj", "PantherSafetyBT.btproj", PANTHER_2_1),
    "2.2.0": ("husarion-ugv-2.2", "husarion_ugv_manager", "LightsBT.btproj", "SafetyBT.btproj", HUSARION_UGV_2_2),
    "2.2.2": ("husarion-ugv-2.2", "husarion_ugv_manager", "LightsBT.btproj", "SafetyBT.btproj", HUSARION_UGV_2_2),
    "2.3.2": ("husarion-ugv-2.2", "husarion_ugv_manager", "LightsBT.btproj", "SafetyBT.btproj", HUSARION_UGV_2_3_2),
}
OVERLAY = {"2.2.0": ("husarion-ugv-2.2.0",), "2.3.2": ("husarion-ugv-2.3", "husarion-ugv-2.3.2")}
"""2.2.0's own lights.xml, SafetyBT.btproj and shutdown.xml; 2.3.2's LightsBT.btproj, lights.xml and
safety.xml; the rest as 2.2.1+ (core/robot/files.py family_dirs, base first)."""


def project_dir(tag: str, tmp: Path) -> Path:
    """The release's project as deploy assembles it: the overlay's files over the base's."""
    base, package, *_ = STOCK[tag]
    out = tmp / tag
    out.mkdir()
    for directory in (base, *OVERLAY.get(tag, ())):
        trees = CONFIG / directory / package / "behavior_trees"
        for f in trees.iterdir() if trees.is_dir() else ():
            (out / f.name).write_bytes(f.read_bytes())
    return out


def runtime(tag: str, tmp: Path, io: FakeRobotIO, clock: ManualClock,
            interfaces: RosInterfaces | None = None) -> ManagerRuntime:
    _, _, lights, safety, ros = STOCK[tag]
    d = project_dir(tag, tmp)
    return ManagerRuntime(ManagerConfig(), io, clock, trees=TreeSource.projects(d / lights, d / safety),
                          interfaces=interfaces or ros)


def battery(status: PowerSupplyStatus, percent: float = 0.8,
            health: PowerSupplyHealth = PowerSupplyHealth.GOOD) -> BatteryMsg:
    return BatteryMsg(percent, 30.0, int(status), int(health))


def robot(*extra: RobotMsg) -> list[RobotMsg]:
    return [EStopMsg(False), IOStateMsg(aux_power=True, fan=True), SystemStatusMsg(40.0),
            DriverStateMsg(30.0, 30.0), *extra]


def animations(io: FakeRobotIO) -> list[int]:
    return [int(str(dict(r.args)["id"])) for r, _ in io.calls if r.kind == "set_led_animation"]


def run_for(rt: ManagerRuntime, clock: ManualClock, seconds: float) -> None:
    for _ in range(round(seconds * 10)):
        rt.tick()
        clock.advance(0.1)


def started(tag: str, tmp: Path, status: PowerSupplyStatus,
            seconds: float) -> tuple[ManagerRuntime, FakeRobotIO, ManualClock]:
    """Release ``tag``'s stock manager on a fake robot whose battery is in ``status``, run for
    ``seconds``: (runtime, robot, clock)."""
    io, clock = FakeRobotIO(), ManualClock()
    rt = runtime(tag, tmp, io, clock)
    io.messages = robot(battery(status))
    run_for(rt, clock, seconds)
    return rt, io, clock


@pytest.mark.parametrize("tag", sorted(STOCK))
def test_each_release_stock_project_validates_cleanly(tag: str, tmp_path: Path) -> None:
    _, _, lights, safety, _ = STOCK[tag]
    d = project_dir(tag, tmp_path)
    assert validate_bt_project(d / lights) == []
    assert validate_bt_project(d / safety) == []


@pytest.mark.parametrize("tag", ["2.2.0", "2.2.2"])
def test_2_2_stock_lights_use_husarion_ugv_numbers(tag: str, tmp_path: Path) -> None:
    """Discharging at 80 %: NO_ERROR (3), BATTERY_NOMINAL (10), READY (1) in husarion_ugv_msgs
    numbers; a charger then: CHARGER_INSERTED (9) after 300 ms, CHARGING_BATTERY (7) after 2.5 s.
    With panther_msgs' numbers (main before this change) 3 is MANUAL_ACTION, 7 CRITICAL_BATTERY,
    9 CHARGING_BATTERY, and 10 is no animation at all."""
    rt, io, clock = started(tag, tmp_path, PowerSupplyStatus.DISCHARGING, 1.0)
    assert sorted(set(animations(io))) == [1, 3, 10]
    io.calls.clear()
    io.messages = [battery(PowerSupplyStatus.CHARGING)]
    run_for(rt, clock, 4.0)
    sent = animations(io)
    assert sent.index(9) < sent.index(7)
    assert {r.args for r, _ in io.calls if dict(r.args)["id"] == 7} == {
        (("id", 7), ("param", "0.800000"), ("repeating", True))}
    rt.close()


def test_2_2_dead_man_button_shows_manual_action(tmp_path: Path) -> None:
    """2.2's lights manager sets drive_state from joy.buttons[4]: MANUAL_ACTION (4) while held."""
    rt, io, clock = started("2.2.2", tmp_path, PowerSupplyStatus.DISCHARGING, 1.0)
    io.calls.clear()
    io.messages = [JoyMsg((0, 0, 0, 0, 1, 0))]
    run_for(rt, clock, 1.0)
    assert animations(io) == [4]
    io.calls.clear()
    io.messages = [JoyMsg((0, 0, 0, 0, 0, 0))]
    run_for(rt, clock, 1.0)
    assert animations(io) == [1]
    rt.close()


@pytest.mark.parametrize("tag", ["2.0.4", "2.1.1"])
def test_2_0_and_2_1_stock_lights_keep_panther_msgs_numbers(tag: str, tmp_path: Path) -> None:
    rt, io, _ = started(tag, tmp_path, PowerSupplyStatus.CHARGING, 1.0)
    assert animations(io) == [9]  # panther_msgs CHARGING_BATTERY, at once (no Delay before 2.2)
    rt.close()


@pytest.mark.parametrize("tag", sorted(STOCK))
def test_stock_safety_holds_fan_on_under_the_fan_off_timeout(tag: str, tmp_path: Path) -> None:
    """The stock safety.xml (the same at every release) puts fan-on and fan-off under one
    TickAfterTimeout(FAN_TURN_OFF_TIMEOUT): after the fan went off, a hot CPU turns it on only
    when the 60 s have passed again. The deployed manager now does that, as the stock one."""
    # start-up fan on, then fan off after 60 s (cool robot)
    rt, io, clock = started(tag, tmp_path, PowerSupplyStatus.DISCHARGING, 61.0)
    fan = [dict(r.args)["data"] for r, _ in io.calls if r.service == "hardware/fan_enable"]
    assert fan == [True, False]
    io.calls.clear()
    io.messages = [IOStateMsg(aux_power=True, fan=False)] + [SystemStatusMsg(90.0)] * 6
    run_for(rt, clock, 30.0)  # hot, but within the timeout since the fan went off: stock waits
    assert not [r for r, _ in io.calls if r.service == "hardware/fan_enable"]
    run_for(rt, clock, 31.0)
    assert [dict(r.args)["data"] for r, _ in io.calls if r.service == "hardware/fan_enable"] == [True]
    rt.close()


MUX = "twist_mux_controller/source"


def test_2_3_2_stock_lights_follow_the_twist_mux_source(tmp_path: Path) -> None:
    """2.3.2's Lights tree: READY (1) before the mux says anything, MANUAL_ACTION (4) while the
    mux's source is manual, AUTONOMOUS_ACTION (12) while autonomous, READY again when nothing
    drives; the joy topic's dead man button no longer matters (its lights manager reads no joy)."""
    io, clock = FakeRobotIO(), ManualClock()
    rt = runtime("2.3.2", tmp_path, io, clock)
    assert interfaces_for((2, 3, 2)) is HUSARION_UGV_2_3_2
    assert rt.lights_bb.get("GOAL_FAILED_ANIM_ID") == 16 and rt.lights_bb.get("FLOOD_LIGHT_ANIM_ID") == 17
    io.messages = robot(battery(PowerSupplyStatus.DISCHARGING))
    run_for(rt, clock, 1.0)
    assert sorted(set(animations(io))) == [1, 3, 10]
    for source, expected in (("manual", [4]), ("autonomous", [12]), ("not_published", [1])):
        io.calls.clear()
        io.messages = [StringMsg(MUX, source), JoyMsg((0, 0, 0, 0, 1, 0))]
        run_for(rt, clock, 1.0)
        assert animations(io) == expected, source
    io.calls.clear()
    io.messages = [EStopMsg(True), StringMsg(MUX, "manual")]
    run_for(rt, clock, 1.0)
    assert animations(io) == [0]  # E_STOP: the IfThenElse is skipped under the E-stop
    rt.close()


def test_2_2_stock_lights_ignore_the_mux_source(tmp_path: Path) -> None:
    """2.2.2's tree keys on drive_state: a mux source message changes nothing."""
    rt, io, clock = started("2.2.2", tmp_path, PowerSupplyStatus.DISCHARGING, 1.0)
    io.calls.clear()
    io.messages = [StringMsg(MUX, "manual")]
    run_for(rt, clock, 1.0)
    assert animations(io) == []
    rt.close()
