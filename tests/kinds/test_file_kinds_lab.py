"""Issue 11 on the lab: a wheel type change migrates a mounted custom controller file (finding 7),
and a pushed file that its validator refuses leaves the robot untouched (finding 1). Issue 24: the
gamepad runs as upstream's compose file has it (bash -c) and takes a pushed parameters file."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml

from tests.badinput.test_file_kinds import JOY2TWIST
from tests.config.test_config_lab import COMPOSE, driver_state, pristine, robot_of, run_cli
from tests.labtools import containers

pytestmark = pytest.mark.lab
__all__ = ["pristine"]  # the fixture, used by name

TEMPLATES = Path(__file__).resolve().parents[2] / "templates"
CONFIG = "/home/husarion/config/panther_controller/config"


def test_wheel_type_change_migrates_the_custom_controller(lab: Any, pristine: None, tmp_path: Path,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    name = robot_of(lab, "2.1.1")
    inv = str(lab.inventory_path)
    mine = tmp_path / "my_controller.yaml"
    text = (TEMPLATES / "config/panther-2.1/panther_controller/config/WH01_controller.yaml").read_text()
    mine.write_text(text.replace("max_velocity: 2.0 # m/s", "max_velocity: 0.8 # slow indoors"))
    code, doc, _, _ = run_cli(capsys, "-i", inv, "config", "push", str(mine), "--as", "controller", "-r", name,
                              "--yes", "--settle", "2", "--json")
    assert code == 0, doc
    code, doc, _, _ = run_cli(capsys, "-i", inv, "config", "set", "wheel_type", "WH02", "-r", name, "--yes",
                              "--settle", "2", "--json")
    assert code == 0, doc
    result = doc["robots"][0]
    assert result["outcome"] == "changed", result
    assert any(d["path"] == f"{CONFIG}/WH02_controller.yaml" for d in result["diffs"])  # in the same plan
    migrated = yaml.safe_load(lab.read(name, f"{CONFIG}/WH02_controller.yaml"))
    params = migrated["/**"]["drive_controller"]["ros__parameters"]
    assert params["wheel_radius"] == 0.1016 and params["wheel_separation_x"] == 0.44
    assert params["linear"]["x"]["max_velocity"] == 0.8  # the user's limit, within WH02's 1.1
    assert params["angular"]["z"]["max_velocity"] == 2.2  # WH02's default, not WH01's 4.0
    state = driver_state(lab, name)
    mounts = {m["Destination"]: m["Source"] for m in state["Mounts"]}
    assert mounts["/config/panther_controller/config/WH02_controller.yaml"] == f"{CONFIG}/WH02_controller.yaml"
    assert "/config/panther_controller/config/my_controller.yaml" not in mounts  # unused: unmounted (finding 9)
    assert "my_controller.yaml" not in lab.read(name, COMPOSE)
    cmd = state["Config"]["Cmd"]
    assert "wheel_type:=WH02" in cmd
    assert "controller_config_path:=/config/panther_controller/config/WH02_controller.yaml" in cmd
    assert state["State"]["Status"] == "running" and state["RestartCount"] == 0
    inside = lab.docker(name, "exec", state["Name"].lstrip("/"), "cat",
                        "/config/panther_controller/config/WH02_controller.yaml", check=True).stdout
    assert "wheel_radius: 0.1016" in inside


def test_a_refused_push_leaves_the_robot_as_it_was(lab: Any, pristine: None, tmp_path: Path,
                                                    capsys: pytest.CaptureFixture[str]) -> None:
    name = robot_of(lab, "2.1.1")
    before = lab.read_bytes(name, COMPOSE)
    listing = lab.sh(name, "find /home/husarion -xdev | sort").stdout
    bad = tmp_path / "hosts.yaml"
    bad.write_text('hosts:\n  - ip: "10.15.20.5; touch x"\n    username: husarion\n    port: 70000\n')
    code, _, _, err = run_cli(capsys, "-i", str(lab.inventory_path), "config", "push", str(bad), "--as",
                              "shutdown-hosts", "-r", name, "--yes")
    assert code == 2, err
    assert "'10.15.20.5; touch x' is not an IP address or host name" in err
    assert lab.read_bytes(name, COMPOSE) == before
    assert lab.sh(name, "find /home/husarion -xdev | sort").stdout == listing


def test_the_gamepad_runs_upstreams_bash_c_and_takes_a_pushed_file(lab: Any, pristine: None, tmp_path: Path,
                                                                     capsys: pytest.CaptureFixture[str]) -> None:
    """The gamepad of husarion/panther-docker@2.1.1:demo/compose.minimal-setup.yaml runs `bash -c "ros2 launch
    ... joy2twist_params_file:=$(ros2 pkg prefix joy2twist)/share/..."`; `config push --as joy2twist` edits the
    argument inside the script, and the check after the recreate reads the script's words."""
    name = robot_of(lab, "2.1.1")
    before = containers(lab, name)["gamepad_controller"]
    assert before["cmd"][:2] == ["bash", "-c"] and before["state"] == "running" and before["restarts"] == 0
    launched = lab.docker(name, "logs", "gamepad_controller", check=True).stdout
    assert ("joy2twist_params_file:=/ros2_ws/install/joy2twist/share/joy2twist/config/joy2twist_panther.yaml "
            "namespace:=panther") in launched  # the shell expanded $(ros2 pkg prefix joy2twist): the file exists
    mine = tmp_path / "pad.yaml"
    mine.write_text(JOY2TWIST)
    code, doc, _, _ = run_cli(capsys, "-i", str(lab.inventory_path), "config", "push", str(mine), "--as",
                              "joy2twist", "-r", name, "--yes", "--settle", "2", "--json")
    assert code == 0, doc
    assert doc["robots"][0]["outcome"] == "changed", doc
    after = containers(lab, name)["gamepad_controller"]
    assert after["cmd"][:2] == ["bash", "-c"]
    assert "joy2twist_params_file:=/config/joy2twist/config/pad.yaml" in after["cmd"][2].split()
    assert after["mounts"]["/config/joy2twist/config/pad.yaml"] == "/home/husarion/config/joy2twist/config/pad.yaml"
    assert after["state"] == "running" and after["restarts"] == 0
    inside = lab.docker(name, "exec", "gamepad_controller", "cat", "/config/joy2twist/config/pad.yaml",
                        check=True).stdout
    assert inside == JOY2TWIST


def test_pull_joy2twist_reads_the_images_file_through_its_symlink(lab: Any, pristine: None,
                                                                  capsys: pytest.CaptureFixture[str]) -> None:
    """panther_ros 2.1.1 (issue 24, finding 9): the gamepad uses its image's joy2twist_panther.yaml, which
    husarion/joy2twist's --symlink-install build links from /ros2_ws/install/joy2twist/share/... to
    /ros2_ws/src/joy2twist/config/; `config pull joy2twist` reads it from the running container."""
    name = robot_of(lab, "2.1.1")
    inside = lab.docker(name, "exec", "gamepad_controller", "cat",
                        "/ros2_ws/src/joy2twist/config/joy2twist_panther.yaml", check=True).stdout
    link = lab.docker(name, "exec", "gamepad_controller", "readlink",
                      "/ros2_ws/install/joy2twist/share/joy2twist/config/joy2twist_panther.yaml", check=True).stdout
    assert link.strip() == "/ros2_ws/src/joy2twist/config/joy2twist_panther.yaml"
    code, _, out, err = run_cli(capsys, "-i", str(lab.inventory_path), "config", "pull", "joy2twist", "-r", name)
    assert code == 0, err
    assert out == inside
    note = " ".join(err.split())
    assert ("/ros2_ws/install/joy2twist/share/joy2twist/config/joy2twist_panther.yaml (-> "
            "/ros2_ws/src/joy2twist/config/joy2twist_panther.yaml) in gamepad_controller (the image's default)") in note
