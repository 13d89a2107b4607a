"""Issue 25 on the lab: a husarion_ugv 2.2.2 robot (real sshd + dockerd + compose v2; the driver
is the lab's ros2 stand-in) with customised controller limits, gamepad, components, user
animations and shutdown hosts is migrated with `driver update jazzy-2.3.2-... --canary 1`.

Without a 2.3.2 image on the robot (no network in the lab) the new driver cannot start: the
migration rolls back, every file byte for byte, the 2.2.2 driver running again. With the
stand-in tagged as 2.3.2 on the robot's engine the migration goes through: each customisation
in its 2.3 form, the unchanged files byte-identical, a second run changes nothing, and
`driver update humble-2.2.2-...` restores the migration's backup byte for byte."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest
from ruamel.yaml import YAML

from tests.clirun import run_cli
from tests.labtools import COMPOSE, containers, robot_of, robots_put_back

pytestmark = pytest.mark.lab

HUMBLE = "husarion/husarion-ugv:humble-2.2.2-20250702"
JAZZY_TAG = "jazzy-2.3.2-20260622"
JAZZY = f"husarion/husarion-ugv:{JAZZY_TAG}"
CFG = "/home/husarion/config"


def files(lab: Any, name: str) -> dict[str, bytes]:
    """compose.yaml and every file of ~/config, by path."""
    listed = lab.sh(name, f"find {CFG} -type f | sort").stdout.split()
    return {p: lab.read_bytes(name, p) for p in [COMPOSE, *listed]}


def customise(lab: Any, name: str) -> None:
    ctrl = f"{CFG}/husarion_ugv_controller/config/WH01_controller.yaml"
    text = lab.read(name, ctrl)
    lab.write(name, ctrl, text.replace("max_velocity: 2.0", "max_velocity: 1.3", 1))
    joy = f"{CFG}/husarion_ugv_bringup/config/joy2twist_panther.yaml"
    lab.write(name, joy, lab.read(name, joy).replace("fast: 1.0", "fast: 0.8"))
    lab.write(name, f"{CFG}/husarion_ugv_description/config/components.yaml",
              "components:\n  - type: LDR06\n    parent_link: cover_link\n    device_namespace: front_lidar\n")
    user = f"{CFG}/husarion_ugv_lights/config/user_animations.yaml"
    lab.write(name, user, lab.read(name, user) + "# the operator's\n")
    hosts = f"{CFG}/husarion_ugv_manager/config/shutdown_hosts.yaml"
    lab.write(name, hosts, lab.read(name, hosts) + "# kept as written\n")
    lab.sh(name, f"chown -R husarion: {CFG}")


@pytest.fixture
def robot(lab: Any) -> Iterator[str]:
    """A 2.2.2 robot, customised; the lab put back afterwards (files, backups, containers, tags)."""
    name = robot_of(lab, "2.2.2")
    with robots_put_back(lab):
        customise(lab, name)
        try:
            yield name
        finally:
            lab.docker(name, "rmi", JAZZY)


def no_teleop_dir(lab: Any, name: str) -> bool:
    """The migration's husarion_ugv_teleop/ (2.3.2's gamepad file) is not left behind, not even empty."""
    return lab.sh(name, f"test -e {CFG}/husarion_ugv_teleop && echo left || echo gone").stdout.strip() == "gone"


def migrate(lab: Any, capsys: pytest.CaptureFixture[str], name: str, tag: str) -> tuple[int, dict[str, Any]]:
    code, doc, _, _ = run_cli(capsys, "-i", str(lab.inventory_path), "driver", "update", tag, "-r", name, "--yes",
                              "--canary", "1", "--settle", "2", "--json")
    return code, doc


def test_failing_new_driver_rolls_back_byte_for_byte(lab: Any, robot: str,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    lab.docker(robot, "rmi", JAZZY)  # no 2.3.2 image on this robot (the lab loads its 2.3.2 stand-in everywhere)
    before = files(lab, robot)
    code, doc = migrate(lab, capsys, robot, JAZZY_TAG)
    assert code == 3, doc
    (res,) = doc["robots"]
    assert res["outcome"] == "rolled-back" and "restored backup" in res["message"]
    assert files(lab, robot) == before and no_teleop_dir(lab, robot)
    ctr = containers(lab, robot)["husarion_ugv_ros"]
    assert ctr["image"] == HUMBLE and ctr["state"] == "running"


def test_migration_second_run_and_way_back(lab: Any, robot: str, capsys: pytest.CaptureFixture[str]) -> None:
    lab.docker(robot, "tag", HUMBLE, JAZZY, check=True)  # the stand-in driver as 2.3.2 (no network here)
    before = files(lab, robot)
    code, doc = migrate(lab, capsys, robot, JAZZY_TAG)
    assert code == 0, doc
    (res,) = doc["robots"]
    assert res["outcome"] == "changed" and res["data"]["stack_to"] == "husarion_ugv 2.3.2"
    after = files(lab, robot)
    load = YAML(typ="safe", pure=True).load
    ctrl = load(after[f"{CFG}/husarion_ugv_controller/config/WH01_controller.yaml"])
    x = ctrl["/**"]["drive_controller"]["ros__parameters"]["linear"]["x"]
    assert (x["max_velocity"], x["min_velocity"]) == (1.3, -1.3) and "has_velocity_limits" not in x
    joy = load(after[f"{CFG}/husarion_ugv_teleop/config/joy2twist_panther.yaml"])
    params = joy["/**"]["ros__parameters"]
    assert params["cmd_vel_topic"] == "manual/cmd_vel" and params["cmd_vel_stamped"] is True
    assert params["linear_velocity_factor"]["fast"] == 0.8
    assert f"{CFG}/husarion_ugv_bringup/config/joy2twist_panther.yaml" not in after
    comp = load(after[f"{CFG}/husarion_ugv_description/config/components.yaml"])
    assert comp["components"][0]["name"] == "front_lidar"
    for rel in ("husarion_ugv_lights/config/user_animations.yaml", "husarion_ugv_manager/config/shutdown_hosts.yaml",
                "husarion_ugv_lights/config/panther_animations.yaml",
                "husarion_ugv_manager/behavior_trees/LightsBT.btproj"):
        assert after[f"{CFG}/{rel}"] == before[f"{CFG}/{rel}"]
    ctr = containers(lab, robot)["husarion_ugv_ros"]
    assert ctr["image"] == JAZZY and ctr["state"] == "running"

    code, doc = migrate(lab, capsys, robot, JAZZY_TAG)
    assert code == 0 and doc["robots"][0]["outcome"] == "ok"
    assert files(lab, robot) == after

    code, doc = migrate(lab, capsys, robot, "humble-2.2.2-20250702")
    assert code == 0, doc
    assert doc["robots"][0]["data"]["backup_restored"] == res["data"]["backup"]
    assert files(lab, robot) == before and no_teleop_dir(lab, robot)
    ctr = containers(lab, robot)["husarion_ugv_ros"]
    assert ctr["image"] == HUMBLE and ctr["state"] == "running"
