"""The simulated Panther: linear battery, scenarios, and the 10 Hz snapshot runner."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import pytest

from panther_ops.manager.clock import MonotonicClock
from panther_ops.manager.errors import ScenarioError
from panther_ops.manager.paths import SCENARIOS
from panther_ops.manager.sim import (
    BatteryPlugin,
    PantherModel,
    Simulation,
    load_scenario,
    parse_scenario,
    run_simulation,
)
from panther_ops.manager.sim.scenario import ScenarioPlayer


@pytest.mark.parametrize(("value", "charge", "scale"), [
    (70.0, 0.7, "percent (2.0.0)"),
    (0.7, 0.7, "fraction (2.0.1+)"),
    (100, 1.0, "percent (2.0.0)"),
    (0.05, 0.05, "fraction (2.0.1+)"),
])
def test_initial_charge_in_either_scale(value: float, charge: float, scale: str) -> None:
    plugin = BatteryPlugin.from_params({"initial_charge_percentage": value})
    assert plugin.initial_charge == pytest.approx(charge) and plugin.charge_scale == scale


def test_battery_defaults_are_the_manuals() -> None:
    plugin = BatteryPlugin.from_params({})
    assert (plugin.simulate_discharging, plugin.charging_time, plugin.power_load,
            plugin.capacity) == (False, 6.0, 120.0, 20.0)


@pytest.mark.parametrize("params", [
    {"initial_charge_percentage": 150},
    {"charging_time": 0},
    {"power_load": -1},
    {"voltage": 40},
])
def test_impossible_battery_parameters(params: dict[str, Any]) -> None:
    with pytest.raises(ScenarioError):
        BatteryPlugin.from_params(params)


def test_linear_discharge_charge_and_stop_when_empty() -> None:
    model = PantherModel(battery=BatteryPlugin.from_params(
        {"simulate_discharging": True, "initial_charge_percentage": 70.0}))
    model.advance(0.0)
    model.advance(3600.0)
    assert model.charge == pytest.approx(0.7 - 120 / (20 * 42), abs=1e-9)  # 120 W for an hour
    model.charger = True
    model.advance(7200.0)
    assert model.charge == pytest.approx(0.7 - 120 / 840 + 1 / 6, abs=1e-9)  # 6 h full charge
    assert model.status().name == "CHARGING"
    model.charger = False
    model.advance(7200.0 + 8 * 3600)
    assert model.charge == 0.0 and model.depleted
    still = PantherModel(battery=BatteryPlugin.from_params({"initial_charge_percentage": 0.5}))
    still.advance(0.0)
    still.advance(10 * 3600.0)
    assert still.charge == 0.5  # simulate_discharging false: no discharge


def test_health_and_status_from_the_state() -> None:
    model = PantherModel()
    assert (model.status().name, model.health().name) == ("DISCHARGING", "GOOD")
    model.set("bat_temp", 45)
    assert model.health().name == "OVERHEAT"
    model.set("bat_temp", -11)
    assert model.health().name == "COLD"
    model.set("health", "dead")
    assert model.health().name == "DEAD"
    model.set("charger", True)
    model.set("charge", 1.0)
    assert model.status().name == "FULL"
    model.set("status", "UNKNOWN")
    assert model.status().name == "UNKNOWN" and model.messages()[0].percentage != model.charge
    with pytest.raises(ScenarioError, match="not one of"):
        model.set("health", "TIRED")


def test_ramps_are_linear_and_sets_cancel_them() -> None:
    scenario = parse_scenario({"events": [{"at": 10, "ramp": {"bat_temp": 65}, "over": 20},
                                          {"at": 25, "set": {"bat_temp": 30}}]})
    model, player = scenario.build_model(), ScenarioPlayer(scenario)
    temps = {}
    for t in (0, 10, 15, 20, 25, 30):
        player.apply(model, float(t))
        temps[t] = model.bat_temp
    assert temps == {0: 25.0, 10: 25.0, 15: 35.0, 20: 45.0, 25: 30.0, 30: 30.0}


@pytest.mark.parametrize(("doc", "message"), [
    ({"weather": "sunny"}, "unknown keys weather"),
    ({"events": [{"set": {"fan": True}}]}, "needs 'at'"),
    ({"events": [{"at": 1, "set": {"wings": True}}]}, "cannot set 'wings'"),
    ({"events": [{"at": 1, "ramp": {"fan": 1}, "over": 2}]}, "cannot ramp 'fan'"),
    ({"events": [{"at": 1, "ramp": {"cpu_temp": 80}}]}, "needs 'over'"),
    ({"events": [{"at": 1, "press": "reset"}]}, "cannot press"),
    ({"robot": {"charge": 70}}, "fraction 0-1"),
    ({"shutdown_hosts": [{"username": "x"}]}, "needs an 'ip'"),
])
def test_scenario_errors_name_the_problem(doc: dict[str, Any], message: str) -> None:
    with pytest.raises(ScenarioError, match=message):
        parse_scenario(doc, "bad.yaml")


def test_shipped_scenarios_load() -> None:
    names = {p.stem for p in SCENARIOS.glob("*.yaml")}
    assert {"battery_overheat", "charging", "fan_hysteresis", "low_battery"} <= names
    for path in SCENARIOS.glob("*.yaml"):
        scenario = load_scenario(path)
        assert scenario.description and scenario.duration > 0


def test_snapshots_at_10_hz_with_the_fast_clock() -> None:
    started = time.monotonic()
    snaps = list(run_simulation(SCENARIOS / "battery_overheat.yaml"))
    assert time.monotonic() - started < 10          # 90 simulated seconds
    assert [s.tick for s in snaps[:3]] == [0, 1, 2]
    assert [s.time for s in snaps[:3]] == [0.0, 0.1, 0.2]
    last = snaps[-1]
    assert last.mode == "done" and last.powered_off and last.shutdown_reason
    assert len(last.front) == len(last.rear) == 46
    assert all(c == (0, 0, 0) for c in last.front)  # powered off: dark bumpers
    running = next(s for s in snaps if s.safety and s.safety.status == "RUNNING")
    assert running.safety is not None and running.safety.branch.startswith("Safety / ")


def test_the_real_clock_runs_in_real_time() -> None:
    scenario = parse_scenario({"duration": 0.5})
    started = time.monotonic()
    snaps = list(run_simulation(scenario, clock=MonotonicClock()))
    elapsed = time.monotonic() - started
    assert len(snaps) == 5 and 0.4 <= elapsed < 2.0


def test_simulation_cleans_its_temporary_hosts_file(tmp_path: Path) -> None:
    scenario = parse_scenario({"shutdown_hosts": [{"ip": "192.0.2.3", "username": "u"}]})
    simulation = Simulation(scenario)
    hosts_file = Path(simulation.config.safety.shutdown_hosts_path)
    assert hosts_file.is_file() and "192.0.2.3" in hosts_file.read_text()
    assert "shutdown_delay" not in hosts_file.read_text()
    simulation.step()
    simulation.close()
    assert not hosts_file.exists()


REPO = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize(("version", "scale"), [("panther-2.0", "fraction (2.0.1+)"),
                                                ("panther-2.1", "fraction (2.0.1+)")])
def test_the_projects_battery_plugin_files_in_both_scales(version: str, scale: str) -> None:
    path = REPO / "templates/config" / version / "panther_gazebo/config/battery_plugin_config.yaml"
    if not path.is_file():
        pytest.skip(f"{path} is not in this checkout")
    plugin = BatteryPlugin.from_file(path)
    assert plugin.initial_charge == pytest.approx(0.7) and plugin.charge_scale == scale
