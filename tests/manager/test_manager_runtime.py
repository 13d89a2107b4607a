"""The tick loop: blackboard entries from messages, moving averages, readiness, shutdown."""

from __future__ import annotations

import math

import py_trees
import pytest

from panther_ops.manager.clock import ManualClock
from panther_ops.manager.config import config_with_params, default_config
from panther_ops.manager.inputs import round_percent
from panther_ops.manager.robot_io import (
    BatteryMsg,
    DriverStateMsg,
    EStopMsg,
    IOStateMsg,
    SystemStatusMsg,
)
from panther_ops.manager.runtime import ManagerRuntime, Mode
from tests.manager.doubles import FakeLocalRunner, FakeRobotIO, fake_backends


def battery(percent: float, status: int = 2, health: int = 1, temp: float = 30.0) -> BatteryMsg:
    return BatteryMsg(percent, temp, status, health)


def everything(percent: float = 0.8) -> list[object]:
    return [battery(percent), EStopMsg(False), IOStateMsg(True, False),
            SystemStatusMsg(50.0), DriverStateMsg(30.0, 31.0)]


def test_blackboards_hold_the_manuals_entries_and_constants(clock: ManualClock) -> None:
    runtime = ManagerRuntime(default_config(), FakeRobotIO(messages=everything()), clock)  # type: ignore[arg-type]
    runtime.tick()
    runtime.tick()
    lights = runtime.blackboards()["Lights"]
    safety = runtime.blackboards()["Safety"]
    assert {"battery_percent", "battery_percent_round", "battery_status", "charging_anim_percent",
            "current_anim_id", "e_stop_state"} <= lights.keys()
    assert {"aux_state", "bat_temp", "cpu_temp", "driver_temp", "e_stop_state",
            "fan_state"} <= safety.keys()
    assert lights["LOW_BATTERY_THRESHOLD_PERCENT"] == 0.4 and safety["CPU_FAN_ON_TEMP"] == 70.0
    assert runtime.blackboards()["Shutdown"]["SHUTDOWN_HOSTS_PATH"] == ""
    assert safety["signal_shutdown"] == (False, "")
    assert lights["current_anim_id"] == 1   # READY was requested and remembered
    runtime.close()
    assert all(not k.startswith(runtime.lights_bb.namespace)
               for k in py_trees.blackboard.Blackboard.storage)


def test_trees_wait_for_their_required_messages(clock: ManualClock) -> None:
    io = FakeRobotIO(messages=[battery(0.8)])
    runtime = ManagerRuntime(default_config(), io, clock)  # type: ignore[arg-type]
    report = runtime.tick()
    assert report.lights is not None and report.lights.status == "WAITING"
    assert report.safety is not None and report.safety.status == "WAITING"
    io.messages = [EStopMsg(False)]
    report = runtime.tick()
    assert report.lights is not None and report.lights.status == "RUNNING"  # Lights needs two
    assert report.safety is not None and report.safety.status == "WAITING"
    io.messages = [IOStateMsg(True, False), SystemStatusMsg(40.0), DriverStateMsg(30, 30)]
    assert runtime.tick().safety.status != "WAITING"  # type: ignore[union-attr]


def test_moving_averages_over_the_configured_windows(clock: ManualClock) -> None:
    config = config_with_params({"battery.percent.window_len": 3, "cpu.temp.window_len": 2})
    io = FakeRobotIO()
    runtime = ManagerRuntime(config, io, clock)  # type: ignore[arg-type]
    for percent, cpu in ((0.9, 40.0), (0.6, 60.0), (0.3, 80.0), (0.3, 80.0)):
        io.messages = [battery(percent), SystemStatusMsg(cpu)]
        runtime.tick()
    lights, safety = runtime.lights_bb, runtime.safety_bb
    assert lights.get("battery_percent") == pytest.approx(0.4)   # (0.6 + 0.3 + 0.3) / 3
    assert lights.get("battery_percent_round") == "0.400000"
    assert safety.get("cpu_temp") == 80.0                        # (80 + 80) / 2
    io.messages = [battery(math.nan, status=0, health=0), DriverStateMsg(30.0, 50.0)]
    runtime.tick()
    assert lights.get("battery_percent") == pytest.approx(0.4)   # UNKNOWN: not averaged
    assert lights.get("battery_status") == 0
    assert safety.get("driver_temp") == 50.0                     # the hotter driver


def test_percent_rounding_like_std_to_string() -> None:
    assert round_percent(0.649, 0.1) == "0.600000"
    assert round_percent(0.65, 0.1) == "0.700000"
    assert round_percent(0.7, 0.05) == "0.700000"
    assert round_percent(1.0, 0.1) == "1.000000"


def test_power_button_runs_the_shutdown_tree(clock: ManualClock, tmp_path: object) -> None:
    backends = fake_backends(clock)
    io = FakeRobotIO(messages=everything())
    runtime = ManagerRuntime(default_config(), io, clock, backends=backends)  # type: ignore[arg-type]
    runtime.tick()
    io.messages = [IOStateMsg(True, True, power_button=True)]
    report = runtime.tick()
    assert report.mode is Mode.SHUTTING_DOWN and report.shutdown_reason == "Power button pressed"
    assert runtime.shutdown_bb.get("signal_shutdown") == (True, "Power button pressed")
    final = runtime.run(duration=5)
    assert final is not None and final.mode is Mode.DONE
    assert runtime.shutdown_status == "SUCCESS"
    runner: FakeLocalRunner = backends.local  # type: ignore[assignment]
    assert runner.commands == ["sudo shutdown now"]


def test_run_ticks_each_tree_at_its_frequency(clock: ManualClock) -> None:
    config = config_with_params({"lights.timer_frequency": 10.0, "safety.timer_frequency": 5.0})
    io = FakeRobotIO(messages=everything())
    runtime = ManagerRuntime(config, io, clock)  # type: ignore[arg-type]
    lights = safety = 0

    def count(report: object) -> bool:
        nonlocal lights, safety
        lights += report.lights is not None  # type: ignore[attr-defined]
        safety += report.safety is not None  # type: ignore[attr-defined]
        io.messages = everything()
        return False

    runtime.run(duration=2.0, stop=count)
    assert (lights, safety) == (20, 10)
    assert clock.now() == pytest.approx(2.0)
