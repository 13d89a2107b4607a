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

from panther_ops.core.config.launch_args import spec
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
