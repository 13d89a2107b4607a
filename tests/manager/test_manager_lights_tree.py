"""The Lights tree picks the right animation in each battery state (simulation, fast clock)."""

from __future__ import annotations

from tests.manager.doubles import calls, simulate

COOL = {"bat_temp": 25, "cpu_temp": 45, "driver_temp": 30}


def anims(snapshots: list[object]) -> list[tuple[float, str]]:
    return [(t, c.removeprefix("lights/set_animation")) for t, c in
            calls(snapshots, contains="lights/set_animation")]  # type: ignore[arg-type]


def test_discharging_shows_ready_once_and_e_stop_while_pressed() -> None:
    snaps = simulate({"robot": COOL, "events": [{"at": 10, "set": {"e_stop": True}},
                                                 {"at": 20, "set": {"e_stop": False}}]},
                     duration=30)
    assert anims(snaps) == [
        (0.0, "(id=1, param='', repeating=True)"),    # READY
        (10.0, "(id=0, param='', repeating=True)"),   # E_STOP
        (20.0, "(id=1, param='', repeating=True)"),   # READY again
    ]
    shown = {round(s.time, 1): s.animations["front"] for s in snaps}
    assert shown[5.0] == "READY" and shown[15.0] == "E_STOP" and shown[25.0] == "READY"


def test_low_battery_every_low_period_below_the_low_threshold() -> None:
    snaps = simulate({"robot": {**COOL, "charge": 0.3}}, duration=100)
    low = [t for t, c in anims(snaps) if c.startswith("(id=6,")]
    assert low == [30.0, 60.1, 90.2]   # LOW_BATTERY_ANIM_PERIOD after each one shown
    assert not [c for _, c in anims(snaps) if c.startswith("(id=7,")]
    shown = {round(s.time, 1): s.animations["front"] for s in snaps}
    assert shown[31.0] == "LOW_BATTERY" and shown[36.0] == "READY"  # 2 s x 2, then READY again


def test_critical_battery_every_critical_period_and_no_low_animation() -> None:
    snaps = simulate({"robot": {**COOL, "charge": 0.05}}, duration=50)
    critical = [t for t, c in anims(snaps) if c.startswith("(id=7,")]
    assert critical == [15.0, 30.1, 45.2]
    assert not [c for _, c in anims(snaps) if c.startswith("(id=6,")]


def test_no_battery_animation_above_the_low_threshold() -> None:
    snaps = simulate({"robot": {**COOL, "charge": 0.41}}, duration=70)
    assert [c for _, c in anims(snaps)] == ["(id=1, param='', repeating=True)"]


def test_charging_shows_the_rounded_percentage_and_updates_it() -> None:
    snaps = simulate({"robot": {**COOL, "charge": 0.64},
                      "battery": {"charging_time": 0.02},          # 72 s for a full charge
                      "events": [{"at": 5, "set": {"charger": True}}]}, duration=40)
    charging = [(t, c) for t, c in anims(snaps) if c.startswith("(id=9,")]
    assert charging[0] == (5.0, "(id=9, param='0.600000', repeating=True)")
    params = [c.split("param=")[1].split(",")[0] for _, c in charging]
    assert params == ["'0.600000'", "'0.700000'", "'0.800000'", "'0.900000'", "'1.000000'"]
    assert snaps[-1].battery_status == "FULL"
    assert snaps[-1].animations == {"front": "CHARGING_BATTERY", "rear": "CHARGING_BATTERY"}


def test_charging_with_e_stop_reminds_every_20_s() -> None:
    snaps = simulate({"robot": {**COOL, "charger": True, "e_stop": True}}, duration=45)
    reminders = [t for t, c in anims(snaps) if c.startswith("(id=0,")]
    assert reminders == [20.0, 40.1]
    assert all("repeating=False" in c for _, c in anims(snaps) if c.startswith("(id=0,"))


def test_error_while_charging_on_overheat_or_overvoltage_only() -> None:
    overheat = simulate({"robot": {**COOL, "charger": True},
                         "events": [{"at": 5, "set": {"bat_temp": 50}}]}, duration=20)
    assert [c for _, c in anims(overheat)][-1] == "(id=2, param='', repeating=True)"
    assert overheat[-1].animations["front"] == "ERROR"
    discharging_hot = simulate({"robot": COOL, "events": [{"at": 5, "set": {"bat_temp": 50}}]},
                               duration=20)
    assert not [c for _, c in anims(discharging_hot) if c.startswith("(id=2,")]


def test_error_on_unknown_status_once() -> None:
    snaps = simulate({"robot": COOL, "events": [{"at": 5, "set": {"status": "UNKNOWN"}},
                                                 {"at": 15, "set": {"status": "auto"}}]},
                     duration=25)
    assert anims(snaps) == [
        (0.0, "(id=1, param='', repeating=True)"),
        (5.0, "(id=2, param='', repeating=True)"),
        (15.0, "(id=1, param='', repeating=True)"),
    ]
    assert {s.animations["rear"] for s in snaps if 6 <= s.time < 15} == {"ERROR"}


def test_bumpers_show_the_animation_colours() -> None:
    snaps = simulate({"robot": COOL, "events": [{"at": 5, "set": {"e_stop": True}}]}, duration=8)
    ready = next(s for s in snaps if s.time == 1.0)
    stopped = next(s for s in snaps if s.time == 6.1)
    assert len(ready.front) == len(ready.rear) == 46
    assert {c for c in ready.front if c != (0, 0, 0)} <= {(0, g, 0) for g in range(256)}
    assert any(c != (0, 0, 0) for c in ready.front)
    assert {c for c in stopped.front if c != (0, 0, 0)} <= {(r, 0, 0) for r in range(256)}
    assert ready.rear == ready.front[::-1]  # rear led_range 45-0, symmetric image
