"""The manual's Faults Handle table, row by row, and the fan notes, in deterministic
simulation (fast clock, 10 Hz)."""

from __future__ import annotations

from typing import Any

import pytest

from tests.manager.doubles import calls, simulate

E_STOP = "hardware/e_stop_trigger()"
AUX_OFF = "hardware/aux_power_enable(data=False)"
FAN_ON = "hardware/fan_enable(data=True)"
FAN_OFF = "hardware/fan_enable(data=False)"
COOL = {"bat_temp": 30, "cpu_temp": 45, "driver_temp": 30}


def safety_calls(snapshots: list[Any]) -> list[str]:
    """Every Safety call except the fan's (fan handling is tested on its own)."""
    return [c for _, c in calls(snapshots, contains="hardware/") if "fan_enable" not in c]


@pytest.mark.parametrize(("health_events", "robot"), [
    ([], COOL),                                                   # GOOD
    ([{"at": 5, "set": {"health": "UNKNOWN"}}], COOL),            # UNKNOWN
    ([], {**COOL, "bat_temp": -15}),                              # COLD (from the temperature)
    ([{"at": 5, "set": {"health": "COLD"}}], COOL),               # COLD (reported)
], ids=["GOOD", "UNKNOWN", "COLD-temperature", "COLD-reported"])
def test_good_unknown_and_cold_need_no_action(health_events: list[Any], robot: dict[str, Any]) -> None:
    snaps = simulate({"robot": robot, "events": health_events}, duration=100)
    assert safety_calls(snaps) == []
    assert snaps[-1].mode == "running" and not snaps[-1].e_stop and snaps[-1].aux
    if robot["bat_temp"] < -10:
        assert snaps[-1].battery_health == "COLD"


def test_overheat_turns_the_fan_on_and_keeps_it_on() -> None:
    snaps = simulate({"robot": COOL, "events": [{"at": 70, "set": {"bat_temp": 50}}]}, duration=200)
    fan = calls(snaps, contains="fan_enable")
    assert fan[:2] == [(0.0, FAN_ON), (60.0, FAN_OFF)]        # start-up run, then cool
    assert len(fan) == 3 and fan[2][1] == FAN_ON and 70 <= fan[2][0] < 71
    assert safety_calls(snaps) == []                           # 50 °C: no E-stop, AUX stays on
    assert snaps[-1].fan and snaps[-1].battery_health == "OVERHEAT" and snaps[-1].mode == "running"


def test_overheat_above_55_triggers_the_e_stop_and_turns_aux_off() -> None:
    snaps = simulate({"robot": COOL, "events": [{"at": 70, "set": {"bat_temp": 58}}]}, duration=120)
    assert safety_calls(snaps) == [E_STOP, AUX_OFF]
    when = dict((c, t) for t, c in calls(snaps))
    assert 70 <= when[E_STOP] < 71 and when[AUX_OFF] > when[E_STOP]
    last = snaps[-1]
    assert last.e_stop and not last.aux and last.fan and last.mode == "running"


def test_overheat_above_55_with_e_stop_already_on_only_turns_aux_off() -> None:
    snaps = simulate({"robot": {**COOL, "e_stop": True},
                      "events": [{"at": 5, "set": {"bat_temp": 58}}]}, duration=20)
    assert safety_calls(snaps) == [AUX_OFF]


def test_overheat_above_62_shuts_the_robot_down() -> None:
    snaps = simulate({"robot": COOL, "events": [{"at": 10, "ramp": {"bat_temp": 63}, "over": 10}],
                      "shutdown_hosts": [{"ip": "192.0.2.3", "username": "husarion"}]},
                     duration=60)
    reasons = {s.shutdown_reason for s in snaps}
    assert "Fatal battery temperature" in reasons
    first = next(s for s in snaps if s.mode != "running")
    assert first.bat_temp > 62
    assert snaps[-1].mode == "done" and snaps[-1].powered_off
    assert snaps[-1].hosts == {"192.0.2.3": False}
    assert E_STOP in safety_calls(snaps)  # it passed 55 °C on the way up


def test_dead_battery_shuts_the_robot_down() -> None:
    snaps = simulate({"robot": COOL, "events": [{"at": 10, "set": {"health": "DEAD"}}]}, duration=30)
    stop = next(s for s in snaps if s.mode != "running")
    assert stop.shutdown_reason == "Battery dead" and 10 <= stop.time < 10.2
    assert snaps[-1].powered_off and safety_calls(snaps) == []


def test_overvoltage_triggers_the_e_stop_and_error_light_only_with_the_charger() -> None:
    snaps = simulate({"robot": COOL, "events": [{"at": 10, "set": {"health": "OVERVOLTAGE"}}]},
                     duration=30)
    assert safety_calls(snaps) == [E_STOP]
    assert calls(snaps, contains="id=2,") == []          # no charger: no ERROR animation
    assert snaps[-1].animations["front"] == "E_STOP"     # the E-stop animation instead
    charging = simulate({"robot": {**COOL, "charger": True},
                         "events": [{"at": 10, "set": {"health": "OVERVOLTAGE"}}]}, duration=30)
    assert safety_calls(charging) == [E_STOP]
    assert calls(charging, contains="id=2,")[0][0] == 10.0
    assert charging[-1].animations == {"front": "ERROR", "rear": "ERROR"}


def test_fan_runs_about_60_s_after_start() -> None:
    fan = calls(simulate({"robot": COOL}, duration=100), contains="fan_enable")
    assert fan == [(0.0, FAN_ON), (60.0, FAN_OFF)]


def test_cpu_fan_hysteresis_with_the_60_s_minimum() -> None:
    snaps = simulate({"robot": COOL, "events": [
        {"at": 80, "set": {"cpu_temp": 75}},    # above 70: on
        {"at": 90, "set": {"cpu_temp": 65}},    # between 60 and 70: stays on
        {"at": 100, "set": {"cpu_temp": 55}},   # at or below 60: off, but >= 60 s after on
    ]}, duration=250)
    fan = calls(snaps, contains="fan_enable")
    assert fan[:2] == [(0.0, FAN_ON), (60.0, FAN_OFF)]
    on, off = fan[2], fan[3]
    assert on[1] == FAN_ON and 80 <= on[0] < 81                # at once, not after a lock-out
    assert off[1] == FAN_OFF and off[0] - on[0] >= 60 and off[0] <= on[0] + 125
    assert len(fan) == 4
    between = [s.fan for s in snaps if 91 <= s.time < off[0] - 0.05]
    assert all(between)


def test_driver_fan_hysteresis_uses_the_hotter_driver() -> None:
    snaps = simulate({"robot": COOL, "events": [
        {"at": 70, "set": {"driver_rear_temp": 47}},   # only the rear driver above 45
        {"at": 90, "set": {"driver_rear_temp": 40}},   # between 35 and 45: stays on
        {"at": 140, "set": {"driver_rear_temp": 33}},  # at or below 35: off
    ]}, duration=260)
    fan = calls(snaps, contains="fan_enable")[2:]
    assert [c for _, c in fan] == [FAN_ON, FAN_OFF]
    assert 70 <= fan[0][0] < 71 and fan[1][0] >= 140


def test_fan_thresholds_follow_the_parameters() -> None:
    """With the shipped 2.1 YAML values (75/70) a CPU at 72 °C does not need the fan."""
    events = [{"at": 70, "set": {"cpu_temp": 72}}]
    default = simulate({"robot": COOL, "events": events}, duration=100)
    shipped = simulate({"robot": COOL, "events": events,
                        "params": {"cpu.temp.fan_on": 75.0, "cpu.temp.fan_off": 70.0}},
                       duration=100)
    assert len(calls(default, contains="fan_enable")) == 3
    assert len(calls(shipped, contains="fan_enable")) == 2


def test_fan_is_not_turned_off_while_the_battery_overheats() -> None:
    snaps = simulate({"robot": {**COOL, "bat_temp": 50}}, duration=200)
    fan = calls(snaps, contains="fan_enable")
    assert fan[0] == (0.0, FAN_ON) and FAN_OFF not in [c for _, c in fan]
    assert all(s.fan for s in snaps[1:])
