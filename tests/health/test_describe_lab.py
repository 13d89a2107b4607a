"""`panther-ops describe ROBOT` on a lab robot (issue 26): real sshd, real dockerd with compose v2;
the containers it shows are the ones the robot's engine runs, read over one SSH connection."""

from __future__ import annotations

import json
import time
from typing import Any

import pytest

from tests.clirun import run, run_cli

pytestmark = pytest.mark.lab


def engine_containers(lab: Any, name: str) -> dict[str, tuple[str, str]]:
    """The robot's containers as its own engine lists them (not through panther-ops): name -> (state, image)."""
    cp = lab.docker(name, "ps", "-a", "--format", "{{json .}}", check=True)
    rows = [json.loads(line) for line in cp.stdout.splitlines() if line.strip()]
    return {r["Names"]: (r["State"], r["Image"]) for r in rows}


def test_describe_shows_the_real_containers_over_one_connection(lab: Any, capsys: pytest.CaptureFixture[str]) -> None:
    robot = lab.robots[2]  # husarion_ugv 2.2.2 in the default cycle
    before = lab.sshd_connections(robot.name)
    code, doc, _, err = run_cli(capsys, "-i", str(lab.inventory_path), "describe", robot.name, "--json")
    assert code == 0, err
    assert doc["command"] == "describe" and doc["exit_code"] == 0
    data = doc["robots"][0]["data"]
    status = data["status"]
    assert status["driver_image"] == robot.image and status["hostname"] == robot.name
    real = engine_containers(lab, robot.name)
    assert {c["name"]: (c["state"], c["image"]) for c in status["containers"]} == real
    assert real[robot.driver_container] == ("running", robot.image)
    # the E-stop from the driver container's ROS API (the lab image's ros2 stand-in); doctor's checks
    assert data["estop"]["data"]["namespace"] == "/panther"
    checks = {f["check"]: f["state"] for f in data["doctor"]["data"]["findings"]}
    assert checks["docker"] == "ok" and checks["compose v2"] == "ok" and "default password" not in checks
    assert "verdict" in data["gps"]["data"]  # nothing sends NMEA in this lab: read, with its verdict
    deadline = time.monotonic() + 3
    while lab.sshd_connections(robot.name) == before and time.monotonic() < deadline:
        time.sleep(0.05)
    assert lab.sshd_connections(robot.name) - before == 1

    code, out, err = run(capsys, "-i", str(lab.inventory_path), "describe", robot.name)
    assert code == 0, err
    lines = out.splitlines()
    at = next(i for i, line in enumerate(lines) if line.startswith("containers"))
    shown = " ".join(" ".join(lines[at:at + 2 * len(real) + 1]).split())
    for name, (state, image) in real.items():
        assert name in shown and state in shown and image in shown, (name, out)
    assert f"{robot.driver_container} (driver): running" in shown

