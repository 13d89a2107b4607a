"""Issue 24 finding 3: where each 2.2 default is read from -- the robot's ~/config tree (under
``common_dir_path``) or the image -- as upstream's launch files say, and what push and pull
make of it.

Facts (distilled from the launch files named in panther_ops/core/kinds/arg_catalogue.py):
husarion_ugv_ros@2.2.0 and @2.2.2 read these defaults under common_dir_path, the rest from the
package share; animations_config_path moves to the tree in 2.2.2 (2.2.0 and 2.2.1: the image).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from panther_ops.core.kinds.arg_catalogue import CATALOGUE
from panther_ops.core.robot.launch_args import spec
from panther_ops.core.stack import stack_from_version
from tests.clirun import run

FROM_TREE = {
    "2.2.0": {"controller_config_path", "components_config_path", "user_led_animations_file",
              "shutdown_hosts_config_path", "lights_bt_project_path", "localization_config_path"},
    "2.2.2": {"controller_config_path", "components_config_path", "user_led_animations_file",
              "shutdown_hosts_config_path", "lights_bt_project_path", "localization_config_path", "led_config_file"},
}
FROM_IMAGE = {
    "2.2.0": {"wheel_config_path": "$(find husarion_ugv_description)/config/{wheel_type}.yaml",
              "led_config_file": "$(find husarion_ugv_lights)/config/{robot_model}_animations.yaml",
              "system_monitor_config_path": "$(find husarion_ugv_diagnostics)/config/system_monitor.yaml",
              "safety_bt_project_path": "$(find husarion_ugv_manager)/behavior_trees/SafetyBT.btproj",
              "nmea_params_path": "$(find husarion_ugv_localization)/config/nmea_navsat.yaml"},
    "2.2.2": {"wheel_config_path": "$(find husarion_ugv_description)/config/{wheel_type}.yaml",
              "system_monitor_config_path": "$(find husarion_ugv_diagnostics)/config/system_monitor.yaml",
              "safety_bt_project_path": "$(find husarion_ugv_manager)/behavior_trees/SafetyBT.btproj",
              "nmea_params_path": "$(find husarion_ugv_localization)/config/nmea_navsat.yaml"},
}


@pytest.mark.parametrize("version", sorted(FROM_IMAGE))
def test_image_defaults_are_the_package_share(version: str) -> None:
    stack = stack_from_version(version)
    for key, default in FROM_IMAGE[version].items():
        assert spec(key).default_for(stack) == default, key


@pytest.mark.parametrize("version", sorted(FROM_TREE))
def test_tree_defaults_name_common_dir_path(version: str) -> None:
    stack = stack_from_version(version)
    for key in FROM_TREE[version]:
        assert spec(key).default_for(stack).startswith("<common_dir_path>/husarion_ugv_"), key
    assert {s.key for s in CATALOGUE if s.default_in_tree(stack)} == FROM_TREE[version]
    for s in CATALOGUE:  # the text and the flag say the same
        if s.available(stack):
            assert ("<common_dir_path>" in s.default_for(stack)) is s.default_in_tree(stack), s.key


HOME = "robots/panther-03/home/husarion"
ANIMS = "config/husarion_ugv_lights/config/panther_animations.yaml"


def as_220(demo: Path) -> None:
    """panther-03 on husarion_ugv 2.2.0 (no launch_gamepad before 2.2.2)."""
    compose = demo / HOME / "compose.yaml"
    text = compose.read_text().replace("humble-2.2.2-20250702", "humble-2.2.0-20240227")
    compose.write_text(text.replace(" launch_gamepad:=true", ""))


def test_push_led_on_220_points_the_argument_at_the_tree_file(demo: Path, capsys: pytest.CaptureFixture[str],
                                                             tmp_path: Path) -> None:
    as_220(demo)
    tree_file = demo / HOME / ANIMS
    mine = tree_file.read_text().replace("number_of_leds: 46", "number_of_leds: 46 # pushed", 1)
    local = tmp_path / "panther_animations.yaml"
    local.write_text(mine)
    code, _, err = run(capsys, "-i", str(demo), "config", "push", str(local), "--as", "led", "-r", "panther-03",
                       "--yes")
    assert code == 0, err
    assert tree_file.read_text() == mine
    assert ("animations_config_path:=/config/husarion_ugv_lights/config/panther_animations.yaml"
            in (demo / HOME / "compose.yaml").read_text())


def test_push_led_on_222_uses_the_tree_without_an_argument(demo: Path, capsys: pytest.CaptureFixture[str],
                                                           tmp_path: Path) -> None:
    tree_file = demo / HOME / ANIMS
    local = tmp_path / "panther_animations.yaml"
    local.write_text(tree_file.read_text().replace("number_of_leds: 46", "number_of_leds: 46 # pushed", 1))
    before = (demo / HOME / "compose.yaml").read_text()
    code, _, err = run(capsys, "-i", str(demo), "config", "push", str(local), "--as", "led", "-r", "panther-03",
                       "--yes")
    assert code == 0, err
    assert tree_file.read_text() == local.read_text() and (demo / HOME / "compose.yaml").read_text() == before


def test_pull_led_on_220_does_not_present_the_tree_file(demo: Path, capsys: pytest.CaptureFixture[str],
                                                       tmp_path: Path) -> None:
    as_220(demo)
    tree_file = demo / HOME / ANIMS
    tree_file.write_text(tree_file.read_text() + "# not read by 2.2.0\n")
    out = tmp_path / "led.yaml"
    code, stdout, err = run(capsys, "-i", str(demo), "config", "pull", "led", "-r", "panther-03", "-o", str(out))
    assert code == 0, err
    assert "not read by 2.2.0" not in out.read_text()
    assert "config tree" not in stdout + err
