"""Issue 24, finding 7: the deployed manager runs with what the stock manager of the robot's
release runs with (its parameter files in the image over its node defaults), the robot's own
values carried over, and every intended difference said in the plan.

Facts (core/manager_ops/stock.py): husarion/husarion_ugv_ros@2.0.4
panther_manager/config/safety_manager_config.yaml, @2.1.1 panther_manager/config/safety_manager.yaml
and @2.2.2 husarion_ugv_manager/config/safety_manager.yaml set the fans to CPU 75/70 °C and driver
50/45 °C (the node defaults are 70/60 and 45/35); 2.2's lights_manager.yaml sets the charging
step to 0.05; 2.2's nodes read battery.anim_period.* (src/*_parameters.yaml), not the shipped
file's battery.animation_period.low.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml

from panther_ops.core.fleet.runner import Connections, RobotContext
from panther_ops.core.manager_ops import read as manager_read
from panther_ops.core.manager_ops.checks import ImageFacts
from panther_ops.core.manager_ops.read import read_and_plan_deploy
from panther_ops.core.manager_ops.stock import intended_differences, robot_params, stock_manager
from panther_ops.manager.config import load_manager_config
from tests.manager_ops.test_manager_deploy import ROOT, apply, make_fleet

SAFETY_21 = """/**:
  safety_manager:
    ros__parameters:
      timer_frequency: 10.0
      fan_turn_off_timeout: 60.0
      cpu:
        temp:
          window_len: 6
          fan_on: 80.0
          fan_off: 72.0
      driver:
        temp:
          window_len: 6
          fan_on: 50.0
          fan_off: 45.0
"""
"""A robot whose image's safety_manager.yaml was changed (CPU fan at 80/72 °C)."""


def _deployed_config(tmp_path: Path, template: str, desired: dict[str, Any] | None = None) -> Any:
    inv = make_fleet(tmp_path, {"r": (template, desired or {})})
    with Connections(inv) as conns:
        ctx = RobotContext(inv.robots["r"], conns.get(inv.robots["r"]), inv)
        plan = read_and_plan_deploy(ctx)
        apply(ctx, plan)
    return plan, load_manager_config([tmp_path / "robots/r" / f"{ROOT}/config/manager.yaml".lstrip("/")])


@pytest.mark.parametrize(("template", "step"), [("panther-2.0.4.yaml", 0.1), ("panther-2.1.1.yaml", 0.1),
                                                ("husarion-ugv-2.2.2.yaml", 0.05)])
def test_deployed_manager_has_the_stock_fan_thresholds_of_the_release(tmp_path: Path, template: str,
                                                                      step: float) -> None:
    """No engine to read the image (a local robot): the release's stock values, not 70/60 and 45/35."""
    plan, cfg = _deployed_config(tmp_path, template)
    s = cfg.safety
    assert (s.cpu_fan_on_temp, s.cpu_fan_off_temp, s.driver_fan_on_temp, s.driver_fan_off_temp) == (75, 70, 50, 45)
    assert cfg.lights.update_charging_anim_step == step and not cfg.notes
    assert plan.data["parameters"]["origin"].startswith("the stock values of ")
    assert "stock parameters: the stock values of" in plan.summary


def test_the_robots_own_values_are_read_from_its_image(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """ROS 2 mode asks the driver image (the probe) for the stock manager's files: the robot's
    own values go into manager.yaml; a file the image lacks falls back to the release's."""
    paths = stock_manager((2, 1, 1)).paths()

    def probe(_ctx: Any, cfg: Any, _hosts: str) -> ImageFacts:
        return ImageFacts(cfg.compose.driver_image, {"python3", "ssh"}, None, {paths[1]: SAFETY_21})

    monkeypatch.setattr(manager_read, "probe_image", probe)
    plan, cfg = _deployed_config(tmp_path, "panther-2.1.1.yaml")
    assert (cfg.safety.cpu_fan_on_temp, cfg.safety.cpu_fan_off_temp) == (80, 72)
    assert (cfg.safety.driver_fan_on_temp, cfg.safety.driver_fan_off_temp) == (50, 45)
    assert cfg.lights.update_charging_anim_step == 0.1
    origin = plan.data["parameters"]["origin"]
    assert origin == ("the robot's own, read in husarion/panther:humble-2.1.1-20240828: "
                      "$(find panther_manager)/config/safety_manager.yaml")
    assert any("$(find panther_manager)/config/lights_manager.yaml is not in husarion/panther" in w
               for w in plan.warnings)


def test_22_reads_the_nodes_names_not_the_shipped_files_unread_key() -> None:
    stock = stock_manager((2, 2, 2))
    lights = ("/**:\n  lights_manager:\n    ros__parameters:\n      battery:\n        animation_period:\n"
              "          low: 99.0\n        anim_period:\n          critical: 20.0\n        charging_anim_step: 0.05\n")
    got = robot_params(stock, {stock.paths()[0]: lights, stock.paths()[1]: None}, "img")
    assert got.values["battery.animation_period.low"] == 30.0  # the node's default: 99 is not read by 2.2
    assert got.values["battery.animation_period.critical"] == 20.0
    assert got.values["battery.charging_anim_step"] == 0.05 and got.values["cpu.temp.fan_on"] == 75.0


def test_a_parameter_file_the_image_lacks_gives_that_files_stock_values_only() -> None:
    stock = stock_manager((2, 2, 2))
    got = robot_params(stock, {stock.paths()[0]: None, stock.paths()[1]: SAFETY_21}, "img")
    assert got.values["battery.charging_anim_step"] == 0.05  # 2.2's shipped lights file, not the node's 0.1
    assert got.values["cpu.temp.fan_on"] == 80.0 and got.values["driver.temp.fan_off"] == 45.0  # the robot's own


def test_the_plan_says_every_difference_and_the_desired_overrides(tmp_path: Path) -> None:
    plan, cfg = _deployed_config(tmp_path, "husarion-ugv-2.2.2.yaml",
                                 {"manager": {"params": {"cpu.temp.fan_on": 80}}})
    assert cfg.safety.cpu_fan_on_temp == 80  # the inventory wins
    diffs = plan.data["differences"]
    intended = intended_differences(stock_manager((2, 2, 2)), (2, 2, 2))
    assert diffs[: len(intended)] == list(intended) and "bt_server_port" in intended[-1]
    assert diffs[-1] == "cpu.temp.fan_on: 80 (desired.manager.params; the robot's stock manager: 75.0)"
    text = next(e.after for e in plan.edits if e.path.endswith("manager.yaml")).decode()  # type: ignore[union-attr]
    assert "# Intended differences from the stock manager of husarion_ugv 2.2.x (docs/manager.md):" in text
    assert all(f"# - {d}\n" in text for d in intended)
    body = yaml.safe_load(text)["/**"]["ros__parameters"]
    assert body["cpu.temp.fan_on"] == 80 and body["cpu.temp.fan_off"] == 70.0


def test_the_probe_reads_the_stock_files_where_the_image_has_them(tmp_path: Path) -> None:
    """PROBE (run by sh as in the driver container) resolves $(find pkg) in AMENT_PREFIX_PATH and
    prints each stock parameter file after its own mark; a file without a final newline too."""
    import os
    import subprocess

    from panther_ops.core.manager_ops.checks import PROBE, parse_probe

    share = tmp_path / "opt/ros/share/panther_manager/config"
    share.mkdir(parents=True)
    (share / "safety_manager.yaml").write_text(SAFETY_21.rstrip("\n"))
    (share / "shutdown_hosts_config.yaml").write_text("hosts: []\n")
    paths = stock_manager((2, 1, 1)).paths()
    cp = subprocess.run(["sh", "-c", PROBE, "probe", "$(find panther_manager)/config/shutdown_hosts_config.yaml",
                         *paths], capture_output=True, text=True, check=True, timeout=10,
                        env={**os.environ, "AMENT_PREFIX_PATH": f"/nonexistent:{tmp_path / 'opt/ros'}"})
    facts = parse_probe("img", cp.stdout)
    assert facts.hosts_text == "hosts: []\n"
    assert facts.param_texts == {paths[1]: SAFETY_21}  # the lights file is not there
    assert robot_params(stock_manager((2, 1, 1)), {p: facts.param_texts.get(p) for p in paths},
                        "img").values["cpu.temp.fan_on"] == 80.0
