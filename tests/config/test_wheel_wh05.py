"""Issue 24 finding 8: ``wheel_type WH05`` on a Lynx. husarion_ugv 2.2 declares WH05 among the
wheel types (husarion_ugv_ros@2.2.0, @2.2.2:husarion_ugv_controller/launch/controller.launch.py)
and takes the model from ``robot_model:=``, else ROBOT_MODEL_NAME (/run/husarion/robot_config.env,
see panther_ops/core/robot/robot_model.py). The demo's panther-03 runs husarion_ugv 2.2.2."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.clirun import run

HOME = "robots/panther-03/home/husarion"


def compose(demo: Path) -> Path:
    return demo / HOME / "compose.yaml"


def test_wh05_on_a_lynx_by_robot_model(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = compose(demo)
    path.write_text(path.read_text().replace("launch_gamepad:=true", "launch_gamepad:=true robot_model:=lynx"))
    code, _, err = run(capsys, "-i", str(demo), "config", "set", "wheel_type", "WH05", "-r", "panther-03", "--yes")
    assert code == 0, err
    assert "robot_model:=lynx wheel_type:=WH05" in path.read_text()


def test_wh05_on_a_lynx_by_its_environment(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    env = demo / "robots/panther-03/run/husarion/robot_config.env"
    env.write_text(env.read_text().replace("ROBOT_MODEL_NAME=panther", "ROBOT_MODEL_NAME=lynx"))
    code, _, err = run(capsys, "-i", str(demo), "config", "set", "wheel_type", "WH05", "-r", "panther-03", "--yes")
    assert code == 0, err
    assert "wheel_type:=WH05" in compose(demo).read_text()


def test_wh05_on_a_panther_is_refused_naming_its_model(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    before = compose(demo).read_text()
    code, _, err = run(capsys, "-i", str(demo), "config", "set", "wheel_type", "WH05", "-r", "panther-03", "--yes")
    assert code == 2 and "robot_model is panther" in err and "ROBOT_MODEL_NAME=lynx" in " ".join(err.split())
    assert compose(demo).read_text() == before


def test_apply_sets_wh05_with_robot_model_in_one_change(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    inv = demo / "inventory.yaml"
    inv.write_text(inv.read_text().replace(
        "  panther-03:\n", "  panther-03:\n    desired:\n      launch_args: {wheel_type: WH05, robot_model: lynx}\n", 1))
    code, _, err = run(capsys, "-i", str(demo), "apply", "-r", "panther-03", "--yes")
    assert code == 0, err
    text = compose(demo).read_text()
    assert "wheel_type:=WH05" in text and "robot_model:=lynx" in text
