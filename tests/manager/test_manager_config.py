from __future__ import annotations

from pathlib import Path

import pytest

from panther_ops.manager.config import (
    config_with_params,
    lights_constants,
    load_manager_config,
    safety_constants,
    shutdown_constants,
)
from panther_ops.manager.errors import ConfigError

SAFETY_2_1_1 = """\
/**:
  ros__parameters:
    timer_frequency: 20.0
    fan_turn_off_timeout: 60.0
    battery:
      temp:
        window_len: 6
    cpu:
      temp:
        window_len: 6
        fan_on: 75.0
        fan_off: 70.0
    driver:
      temp:
        window_len: 4
        fan_on: 50.0
        fan_off: 45.0
    ros_communication_timeout:
      availability: 1.0
      response: 2.0
    plugin_libs: [tick_after_timeout_bt_node]
"""

LIGHTS_2_1_1 = """\
lights_manager:
  ros__parameters:
    timer_frequency: 10.0
    battery:
      percent:
        window_len: 8
        threshold:
          low: 0.3
          critical: 0.05
      animation_period:
        low: 40.0
        critical: 10.0
      charging_anim_step: 0.05
"""

MANAGER_BT_2_0_0 = """\
manager_bt_node:
  ros__parameters:
    battery_percent_window_len: 5
    shutdown_timeout: 15.0
    lights:
      critical_battery_anim_period: 12.0
      low_battery_threshold_percent: 0.35
      timer_frequency: 5.0
    safety:
      high_bat_temp: 55.0
      critical_bat_temp: 59.0
      cpu_fan_on_temp: 75.0
      cpu_fan_off_temp: 70.0
      timer_frequency: 8.0
    some_unknown_key: 1
"""


def test_defaults_are_the_manuals_values() -> None:
    config = load_manager_config()
    safety, lights = config.safety, config.lights
    assert (safety.cpu_fan_on_temp, safety.cpu_fan_off_temp) == (70.0, 60.0)
    assert (safety.driver_fan_on_temp, safety.driver_fan_off_temp) == (45.0, 35.0)
    assert (safety.critical_bat_temp, safety.fatal_bat_temp, safety.high_bat_temp) == (55.0, 62.0, 55.0)
    assert safety.fan_turn_off_timeout == 60.0
    assert (lights.low_battery_threshold_percent, lights.critical_battery_threshold_percent) == (0.4, 0.1)
    assert (lights.low_battery_anim_period, lights.critical_battery_anim_period) == (30.0, 15.0)
    assert lights.battery_state_anim_period == 120.0
    assert lights.update_charging_anim_step == 0.1
    assert lights.battery_percent_window_len == safety.battery_temp_window_len == 6


def test_the_shipped_2_1_yaml_overrides_the_fan_thresholds(tmp_path: Path) -> None:
    safety_file, lights_file = tmp_path / "safety_manager.yaml", tmp_path / "lights_manager.yaml"
    safety_file.write_text(SAFETY_2_1_1)
    lights_file.write_text(LIGHTS_2_1_1)
    config = load_manager_config([safety_file, lights_file])
    assert (config.safety.cpu_fan_on_temp, config.safety.cpu_fan_off_temp) == (75.0, 70.0)
    assert (config.safety.driver_fan_on_temp, config.safety.driver_fan_off_temp) == (50.0, 45.0)
    assert config.safety.driver_temp_window_len == 4
    assert config.safety.timer_frequency == 20.0
    assert config.safety.service_response_timeout == 2.0
    assert config.safety.service_timeout == 3.0  # availability, then response
    assert config.lights.timer_frequency == 10.0
    assert config.lights.battery_percent_window_len == 8
    assert config.lights.low_battery_threshold_percent == 0.3
    assert config.lights.critical_battery_anim_period == 10.0
    assert config.lights.update_charging_anim_step == 0.05
    assert config.sources == (str(safety_file), str(lights_file))


def test_the_2_0_manager_bt_config_shape(tmp_path: Path) -> None:
    path = tmp_path / "manager_bt_config.yaml"
    path.write_text(MANAGER_BT_2_0_0)
    config = load_manager_config([path])
    assert config.lights.battery_percent_window_len == 5
    assert config.lights.critical_battery_anim_period == 12.0
    assert config.lights.timer_frequency == 5.0
    assert config.safety.timer_frequency == 8.0
    assert config.safety.critical_bat_temp == 59.0  # 2.0's CRITICAL_BAT_TEMP, as documented
    assert any("some_unknown_key" in note for note in config.notes)


def test_constants_carry_the_manuals_names() -> None:
    config = load_manager_config()
    lights = lights_constants(config.lights)
    safety = safety_constants(config.safety)
    assert lights["ERROR_ANIM_ID"] == 2 and lights["CHARGING_BATTERY_ANIM_ID"] == 9
    assert lights["BATTERY_STATE_ANIM_ID"] == 8
    assert lights["POWER_SUPPLY_STATUS_FULL"] == 4
    assert lights["LOW_BATTERY_THRESHOLD_PERCENT"] == 0.4
    assert safety["POWER_SUPPLY_HEALTH_OVERVOLTAGE"] == 4
    assert safety["POWER_SUPPLY_HEALTH_SAFETY_TIMER_EXPIRE"] == 8
    assert safety["CPU_FAN_ON_TEMP"] == 70.0 and safety["FAN_TURN_OFF_TIMEOUT"] == 60.0
    assert shutdown_constants(config.safety).keys() >= {"SHUTDOWN_HOSTS_PATH", "SHUTDOWN_HOSTS_FILE"}


def test_params_mapping_with_node_prefixes() -> None:
    config = config_with_params({"cpu.temp.fan_on": 80, "safety.timer_frequency": 5,
                                 "lights": {"timer_frequency": 2.0}})
    assert config.safety.cpu_fan_on_temp == 80.0
    assert config.safety.timer_frequency == 5.0
    assert config.lights.timer_frequency == 2.0


@pytest.mark.parametrize(("params", "message"), [
    ({"battery.percent.window_len": 0}, "at least 1"),
    ({"battery.percent.threshold.low": 1.5}, r"\[0, 1\]"),
    ({"cpu.temp.fan_on": "hot"}, "expected float"),
    ({"battery.temp.window_len": 2.5}, "expected int"),
    ({"fan_turn_off_timeout": -1}, "positive"),
])
def test_impossible_values_are_refused(params: dict[str, object], message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        config_with_params(params)


def test_odd_values_are_reported(tmp_path: Path) -> None:
    config = config_with_params({"cpu.temp.fan_on": 50, "cpu.temp.fan_off": 60})
    assert any("no hysteresis" in note for note in config.notes)
    broken = tmp_path / "broken.yaml"
    broken.write_text("a: [1,\n")
    with pytest.raises(ConfigError, match=r"broken.yaml:\d+: invalid YAML"):
        load_manager_config([broken])


REPO = Path(__file__).resolve().parents[2]


def test_the_projects_shipped_manager_files_load() -> None:
    """templates/config holds the stack's own files (written by the config catalogue)."""
    base = REPO / "templates" / "config"
    files = [base / "panther-2.1/panther_manager/config/safety_manager.yaml",
             base / "panther-2.1/panther_manager/config/lights_manager.yaml"]
    old = base / "panther-2.0.0/panther_manager/config/manager_bt_config.yaml"
    if not all(f.is_file() for f in [*files, old]):
        pytest.skip("templates/config is not in this checkout")
    config = load_manager_config(files)
    assert (config.safety.cpu_fan_on_temp, config.safety.cpu_fan_off_temp) == (75.0, 70.0)
    assert (config.safety.driver_fan_on_temp, config.safety.driver_fan_off_temp) == (50.0, 45.0)
    assert config.lights.low_battery_anim_period == 30.0
    assert not [n for n in config.notes if "not a manager parameter" in n]
    legacy = load_manager_config([old])
    assert (legacy.safety.high_bat_temp, legacy.safety.critical_bat_temp) == (55.0, 59.0)
