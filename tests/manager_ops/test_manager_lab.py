"""`manager deploy|remove|status|logs` on the lab (real sshd + dockerd + compose v2 robots).

Acceptance: `manager deploy` on a lab robot adds the service, sets disable_manager:=True, and
the manager container stays up; `manager remove` leaves compose.yaml byte-identical to before.

The robot's driver image is the lab's Python 3.10 stand-in (`tests/lab/pyimage.py`) on the
robot under test, so the manager runs on "the robot's own ROS image" as on a Panther, in
simulation mode (no ROS 2 in the lab). A robot still on the busybox stand-in shows the
rollback: no python3 there, the manager container crash-loops, everything is put back.
"""

from __future__ import annotations

import json
import time
from collections.abc import Iterator
from typing import Any

import pytest
import yaml

from panther_ops.core.manager_ops.bundle import build_bundle
from tests.clirun import run_cli
from tests.lab.pyimage import restore_driver_image, use_python_image
from tests.labtools import COMPOSE, robot_of

pytestmark = pytest.mark.lab

SERVICE = "panther_ops_manager"


def inspect(lab: Any, name: str, container: str) -> dict[str, Any] | None:
    cp = lab.docker(name, "inspect", "-f", "{{json .}}", container)
    return dict(json.loads(cp.stdout)) if cp.returncode == 0 else None


def _backups(lab: Any, name: str) -> set[str]:
    out = lab.sh(name, "ls -1 /home/husarion/.panther-ops/backups 2>/dev/null; true").stdout
    return set(out.split())


def _put_back(lab: Any, name: str, compose: str, backups: set[str]) -> None:
    lab.docker(name, "rm", "-f", SERVICE)
    lab.write(name, COMPOSE, compose)
    lab.sh(name, "rm -rf /home/husarion/panther-ops")
    for b in _backups(lab, name) - backups:
        lab.sh(name, f"rm -rf /home/husarion/.panther-ops/backups/{b}")
    if not backups:
        lab.sh(name, "rmdir /home/husarion/.panther-ops/backups /home/husarion/.panther-ops 2>/dev/null; true")


def lab_of(request: pytest.FixtureRequest, version: str) -> Any:
    """The lab with a robot on ``version``: the shared 5-robot lab, jazzy_lab for 2.3.2."""
    return request.getfixturevalue("jazzy_lab" if version == "2.3.2" else "lab")


@pytest.fixture
def python_robot(request: pytest.FixtureRequest) -> Iterator[str]:
    """A robot whose driver image is the Python stand-in; put back as found afterwards."""
    lab = lab_of(request, request.param)
    name = robot_of(lab, request.param)
    compose, backups = lab.read(name, COMPOSE), _backups(lab, name)
    use_python_image(lab, name)
    yield name
    _put_back(lab, name, compose, backups)
    restore_driver_image(lab, name)  # driver recreated on the busybox stand-in, Python image deleted
    lab.compose(name, "up", "-d")


@pytest.mark.parametrize("python_robot", ["2.1.1", "2.2.2", "2.3.2"], indirect=True)
def test_deploy_runs_the_manager_and_remove_restores_compose(request: pytest.FixtureRequest, python_robot: str,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    lab = lab_of(request, request.node.callspec.params["python_robot"])
    name, inv = python_robot, str(lab.inventory_path)
    robot = lab.robot(name)
    version = build_bundle().version
    flag = "disable_manager:=true" if robot.stack.ugv else "disable_manager:=True"
    before = lab.read_bytes(name, COMPOSE)

    code, doc, _, _ = run_cli(capsys, "-i", inv, "manager", "deploy", "-r", name, "--sim", "--yes", "--settle", "2",
                           "--json")
    assert code == 0, doc
    assert doc["robots"][0]["outcome"] == "changed", doc["robots"][0]["message"]
    compose = yaml.safe_load(lab.read(name, COMPOSE))
    svc = compose["services"][SERVICE]
    assert svc["image"] == robot.image and svc["restart"] == "always"  # the driver's image, the common merge
    assert flag in compose["services"][robot.driver_container]["command"]
    assert flag in inspect(lab, name, robot.driver_container)["Config"]["Cmd"]  # type: ignore[index]
    time.sleep(3)  # it stays up: running, never restarted
    ctr = inspect(lab, name, SERVICE)
    assert ctr is not None and ctr["State"]["Status"] == "running" and ctr["RestartCount"] == 0
    assert f"/opt/panther-ops/manager/{version}/panther_ops_manager.pyz" in ctr["Config"]["Cmd"]
    # what the stock manager of the release runs with (issue 24: fans 75/70 and 50/45, not the node defaults)
    params = lab.read(name, "/home/husarion/panther-ops/manager/config/manager.yaml")
    assert "cpu.temp.fan_on: 75.0" in params and "driver.temp.fan_off: 45.0" in params
    assert "# Intended differences from the stock manager of " in params
    assert doc["robots"][0]["data"]["parameters"]["origin"].startswith("the stock values of ")

    deadline = time.monotonic() + 30  # the first lines can take a while on a loaded machine
    while True:
        code, _, out, _ = run_cli(capsys, "-i", inv, "manager", "logs", "-r", name, "-n", "50")
        if code != 0 or "call lights/set_animation" in out or time.monotonic() > deadline:
            break
        time.sleep(1)
    assert code == 0
    assert f"panther_ops.manager {version}" in out and "Python 3.10." in out and "simulation mode" in out
    assert "call lights/set_animation" in out

    code, doc, _, _ = run_cli(capsys, "-i", inv, "manager", "status", "-r", name, "--json")
    r = doc["robots"][0]
    assert code == 0 and r["outcome"] == "ok", r
    assert r["data"]["state"] == "running" and r["data"]["version"] == version == r["data"]["running_version"]
    assert r["data"]["mode"] == "sim" and r["data"]["restart_count"] == 0

    code, doc, _, _ = run_cli(capsys, "-i", inv, "manager", "deploy", "-r", name, "--sim", "--yes", "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "ok"
    assert "already deployed" in doc["robots"][0]["message"]

    code, doc, _, _ = run_cli(capsys, "-i", inv, "manager", "remove", "-r", name, "--yes", "--settle", "2", "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "changed", doc["robots"][0]["message"]
    assert lab.read_bytes(name, COMPOSE) == before
    assert inspect(lab, name, SERVICE) is None
    assert lab.sh(name, "test -e /home/husarion/panther-ops").returncode != 0
    driver = inspect(lab, name, robot.driver_container)
    assert driver is not None and driver["State"]["Status"] == "running"
    assert not [a for a in driver["Config"]["Cmd"] if a.startswith("disable_manager")]


def test_deploy_without_python_in_the_image_rolls_back(lab: Any, capsys: pytest.CaptureFixture[str]) -> None:
    name = robot_of(lab, "2.0.4")  # busybox stand-in: no python3
    robot = lab.robot(name)
    compose, backups = lab.read(name, COMPOSE), _backups(lab, name)
    try:
        code, doc, _, _ = run_cli(capsys, "-i", str(lab.inventory_path), "manager", "deploy", "-r", name, "--sim",
                               "--yes", "--settle", "2", "--json")
        r = doc["robots"][0]
        assert code == 3 and r["outcome"] == "rolled-back", r
        assert "python3: not found" in r["message"]
        assert lab.read(name, COMPOSE) == compose
        assert inspect(lab, name, SERVICE) is None  # no orphan left behind
        assert lab.sh(name, "test -e /home/husarion/panther-ops").returncode != 0
        driver = inspect(lab, name, robot.driver_container)
        assert driver is not None and driver["State"]["Status"] == "running"
        assert "disable_manager:=True" not in driver["Config"]["Cmd"]
    finally:
        _put_back(lab, name, compose, backups)
        lab.compose(name, "up", "-d")


def test_dry_run_through_a_jump_host_writes_nothing(lab: Any, capsys: pytest.CaptureFixture[str]) -> None:
    hidden = lab.jump_robot
    assert hidden is not None
    before = lab.read_bytes(hidden.name, COMPOSE)
    code, _, out, _ = run_cli(capsys, "-i", str(lab.inventory_path), "manager", "deploy", "-r", hidden.name,
                           "--sim", "--dry-run")
    assert code == 0
    assert f"+  {SERVICE}:" in out and "disable_manager:=True" in out
    assert lab.read_bytes(hidden.name, COMPOSE) == before
    assert lab.sh(hidden.name, "test -e /home/husarion/panther-ops").returncode != 0
    # ROS 2 mode: the busybox image has no ssh client, so the stock manager's SSH power-off of the
    # robot would be lost: refused (exit 2), through the jump host too, nothing written
    code, _, out, _ = run_cli(capsys, "-i", str(lab.inventory_path), "manager", "deploy", "-r", hidden.name,
                           "--ros2", "--dry-run")
    assert code == 2
    assert lab.read_bytes(hidden.name, COMPOSE) == before
