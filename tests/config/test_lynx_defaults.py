"""Issue 24 (conformance, ``2.2.*:launch:wheel_type``): on husarion_ugv 2.2 the default wheel type
follows the robot's model. husarion_ugv_ros@2.2.0, @2.2.2:husarion_ugv_controller/launch/
controller.launch.py (and husarion_ugv_description/launch/load_urdf.launch.py) declare
``wheel_type`` with ``default_wheel_type = {"lynx": "WH05", "panther": "WH01"}[robot_model]``, and
``robot_model`` defaults to ROBOT_MODEL_NAME. So a Lynx whose command sets no ``wheel_type`` runs
WH05: `config get`, the controller's limits and the file a controller edit starts from follow it.
The demo's panther-03 runs husarion_ugv 2.2.2; ROBOT_MODEL_NAME=lynx in its robot_config.env (or
``robot_model:=lynx``) makes it a Lynx."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

from panther_ops.core.robot.launch_args import spec
from panther_ops.core.stack import stack_from_version
from tests.clirun import run

ROBOT = "robots/panther-03"
TREE_CONTROLLER = f"{ROBOT}/home/husarion/config/husarion_ugv_controller/config"


def lynx(demo: Path) -> None:
    env = demo / ROBOT / "run/husarion/robot_config.env"
    env.write_text(env.read_text().replace("ROBOT_MODEL_NAME=panther", "ROBOT_MODEL_NAME=lynx"))


def test_the_catalogue_default_follows_the_model() -> None:
    wheel = spec("wheel_type")
    s222, s211 = stack_from_version("2.2.2"), stack_from_version("2.1.1")
    assert wheel.default_for(s222, "lynx") == "WH05"
    assert wheel.default_for(s222, "panther") == wheel.default_for(s222) == "WH01"
    assert wheel.default_for(s211, "lynx") == "WH01"  # panther_ros has no model


def test_config_get_wheel_type_on_a_lynx_is_wh05(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    lynx(demo)
    code, out, err = run(capsys, "-i", str(demo), "config", "get", "wheel_type", "-r", "panther-03", "--json")
    assert code == 0, err
    assert json.loads(out)["robots"][0]["data"]["value"] == "WH05"


def test_config_get_on_a_panther_stays_wh01(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = run(capsys, "-i", str(demo), "config", "get", "wheel_type", "-r", "panther-03", "--json")
    assert code == 0, err
    assert json.loads(out)["robots"][0]["data"]["value"] == "WH01"


def test_a_lynx_by_robot_model_argument(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = demo / ROBOT / "home/husarion/compose.yaml"
    path.write_text(path.read_text().replace("launch_gamepad:=true", "launch_gamepad:=true robot_model:=lynx"))
    code, out, err = run(capsys, "-i", str(demo), "config", "get", "wheel_type", "-r", "panther-03", "--json")
    assert code == 0, err
    assert json.loads(out)["robots"][0]["data"]["value"] == "WH05"


def test_controller_limit_above_wh05_is_refused_on_a_lynx(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """1.8 m/s is within WH01's 2.0 but above the Lynx's 1.5 (husarion_ugv_ros@2.2.2:
    husarion_ugv_controller/config/WH05_controller.yaml)."""
    lynx(demo)
    before = (demo / TREE_CONTROLLER / "WH05_controller.yaml").read_bytes()
    code, _, err = run(capsys, "-i", str(demo), "config", "set", "controller.linear.x.max_velocity", "1.8",
                       "-r", "panther-03", "--yes")
    assert code == 2 and "WH05 limit of 1.5" in err
    assert (demo / TREE_CONTROLLER / "WH05_controller.yaml").read_bytes() == before


def test_controller_edit_on_a_lynx_edits_the_wh05_file(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    lynx(demo)
    wh01 = (demo / TREE_CONTROLLER / "WH01_controller.yaml").read_bytes()
    code, _, err = run(capsys, "-i", str(demo), "config", "set", "controller.linear.x.max_velocity", "1.2",
                       "-r", "panther-03", "--yes")
    assert code == 0, err
    doc = yaml.safe_load((demo / TREE_CONTROLLER / "WH05_controller.yaml").read_text())
    drive = doc["/**"]["drive_controller"]["ros__parameters"]
    assert drive["linear"]["x"]["max_velocity"] == 1.2 and drive["wheel_radius"] == 0.144
    assert (demo / TREE_CONTROLLER / "WH01_controller.yaml").read_bytes() == wh01


# The Lynx's and 2.2's simulation files (conformance: no template of lynx_animations.yaml,
# battery_plugin.yaml, 2.2.2's joy2twist_lynx.yaml): `config pull` hands out the template, which
# its kind's validator accepts for that robot, and `config push` writes the Lynx's own file.

def pulled(demo: Path, capsys: pytest.CaptureFixture[str], kind: str) -> tuple[str, str]:
    code, out, err = run(capsys, "-i", str(demo), "config", "pull", kind, "-r", "panther-03")
    assert code == 0, err
    return out, err


@pytest.mark.parametrize(("kind", "source"), [
    ("led", "husarion_ugv_ros@2.2.2:husarion_ugv_lights/config/lynx_animations.yaml"),
    ("joy2twist", "husarion_ugv_ros@2.2.2:husarion_ugv_bringup/config/joy2twist_lynx.yaml"),
    ("battery", "husarion_ugv_ros@2.2.2:husarion_ugv_gazebo/config/battery_plugin.yaml"),
])
def test_pull_on_a_lynx_gives_its_template(demo: Path, capsys: pytest.CaptureFixture[str], kind: str,
                                           source: str) -> None:
    from panther_ops.core.kinds import FileKind, Target, check_file

    lynx(demo)
    if kind == "joy2twist":  # the tree holds the Panther's (the demo's image copied it): the Lynx's is not there
        assert not (demo / ROBOT / "home/husarion/config/husarion_ugv_bringup/config/joy2twist_lynx.yaml").exists()
    out, err = pulled(demo, capsys, kind)
    assert f"written from {source}" in " ".join(err.split())
    target = Target(stack_from_version("2.2.2"), "WH05")
    check_file(FileKind(kind), "pulled", out.encode(), target=target)  # raises if refused
    if kind == "led":
        assert yaml.safe_load(out)["segments_map"]["left"] == ["fl", "rl"]
    if kind == "joy2twist":
        assert yaml.safe_load(out)["/**"]["ros__parameters"]["linear_velocity_factor"]["fast"] == 1.5


def test_push_led_onto_a_lynx_writes_its_own_animations(demo: Path, tmp_path: Path,
                                                        capsys: pytest.CaptureFixture[str]) -> None:
    lynx(demo)
    out, _ = pulled(demo, capsys, "led")
    mine = tmp_path / "lynx_animations.yaml"
    mine.write_text(out.replace("duration: 8", "duration: 9"))
    lights = demo / ROBOT / "home/husarion/config/husarion_ugv_lights/config"
    panther = (lights / "panther_animations.yaml").read_bytes()
    code, _, err = run(capsys, "-i", str(demo), "config", "push", str(mine), "--as", "led", "-r", "panther-03", "--yes")
    assert code == 0, err
    assert (lights / "panther_animations.yaml").read_bytes() == panther
    assert "duration: 9" in (lights / "lynx_animations.yaml").read_text()


def test_push_battery_onto_a_22_robot_is_refused(demo: Path, tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    """2.2's driver passes battery_config_path to the battery driver (husarion_ugv_battery/launch/
    battery.launch.py); the plugin file is the simulation's (husarion_ugv_gazebo/launch/simulate_robot.launch.py)."""
    out, _ = pulled(demo, capsys, "battery")
    mine = tmp_path / "battery.yaml"
    mine.write_text(out)
    before = (demo / ROBOT / "home/husarion/compose.yaml").read_bytes()
    code, _, err = run(capsys, "-i", str(demo), "config", "push", str(mine), "--as", "battery", "-r", "panther-03",
                       "--yes")
    assert code == 2 and "simulation only" in err
    assert (demo / ROBOT / "home/husarion/compose.yaml").read_bytes() == before
