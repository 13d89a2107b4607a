"""Issue-2 acceptance on the lab: real sshd, real dockerd with compose v2, per robot."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import pytest

from panther_ops.cli.app import main
from tests.clirun import run_cli

pytestmark = pytest.mark.lab


def by_robot(doc: dict[str, Any]) -> dict[str, dict[str, Any]]:
    return {r["robot"]: r for r in doc["robots"]}


def test_status_on_five_robots_with_three_stacks(lab: Any, capsys: pytest.CaptureFixture[str]) -> None:
    code, doc, _, _ = run_cli(capsys, "-i", str(lab.inventory_path), "status", "--all", "--json")
    assert code == 0, doc
    robots = by_robot(doc)
    assert len(robots) == len(lab.robots) >= 5
    seen_versions = set()
    for r in lab.robots:
        res = robots[r.name]
        assert res["outcome"] == "ok", res
        data = res["data"]
        assert data["reachable"] is True
        assert data["hostname"] == r.name
        expected = r.image.split(":", 1)[1].split("-")[1]  # humble-2.1.1-20240828 -> 2.1.1
        assert data["stack_version"] == expected
        assert data["driver_image"] == r.image
        assert data["driver_state"] == "running"
        assert data["driver_restart_count"] == 0
        assert data["robot_serial"]
        assert abs(data["clock_offset_s"]) < 1.0
        seen_versions.add(expected[:3])
    assert {"2.0", "2.1", "2.2"} <= seen_versions


def test_changed_host_key_is_refused_others_succeed(lab: Any, capsys: pytest.CaptureFixture[str]) -> None:
    victim = lab.robots[1].name
    old = lab.host_fingerprint(victim)
    lab.rotate_host_key(victim)
    try:
        new = lab.host_fingerprint(victim)
        code, doc, _, _err = run_cli(capsys, "-i", str(lab.inventory_path), "status", "--all", "--json")
        assert code == 3
        robots = by_robot(doc)
        assert robots[victim]["outcome"] == "unreachable"
        msg = robots[victim]["message"]
        assert "HOST KEY CHANGED" in msg and old in msg and new in msg
        assert all(r["outcome"] == "ok" for n, r in robots.items() if n != victim)
    finally:
        lab.restore_host_key(victim)


def test_link_down_is_unreachable_exit_3(lab: Any, capsys: pytest.CaptureFixture[str]) -> None:
    victim = lab.robots[2].name
    lab.link_down(victim)
    try:
        start = time.monotonic()
        code, doc, _, _ = run_cli(capsys, "-i", str(lab.inventory_path), "status", "--all", "--json")
        assert code == 3
        robots = by_robot(doc)
        assert robots[victim]["outcome"] == "unreachable"
        assert sum(r["outcome"] == "ok" for r in robots.values()) == len(robots) - 1
        assert time.monotonic() - start < 15
    finally:
        lab.link_up(victim)


def test_every_robot_unreachable_is_exit_4(lab: Any, capsys: pytest.CaptureFixture[str]) -> None:
    a, b = lab.robots[0].name, lab.robots[2].name
    lab.link_down(a)
    lab.link_down(b)
    try:
        code, doc, _, _ = run_cli(capsys, "-i", str(lab.inventory_path), "status", "-r", a, "-r", b, "--json")
        assert code == 4
        assert [r["outcome"] for r in doc["robots"]] == ["unreachable", "unreachable"]
    finally:
        lab.link_up(a)
        lab.link_up(b)


def test_jump_host_one_connection_docker_included(lab: Any, capsys: pytest.CaptureFixture[str]) -> None:
    behind = lab.jump_robot
    assert behind is not None and behind.jump
    before = lab.sshd_accepts(behind.name)
    code, doc, _, _ = run_cli(capsys, "-i", str(lab.inventory_path), "status", "-r", behind.name, "--json")
    assert code == 0, doc
    data = doc["robots"][0]["data"]
    assert data["driver_state"] == "running"
    assert data["containers"]
    deadline = time.monotonic() + 3
    while lab.sshd_accepts(behind.name) == before and time.monotonic() < deadline:
        time.sleep(0.05)
    assert lab.sshd_accepts(behind.name) - before == 1


def test_doctor_finds_clock_offset_and_default_password(lab: Any, capsys: pytest.CaptureFixture[str]) -> None:
    skewed, weak = lab.robots[3].name, lab.robots[4].name
    lab.clock_offset(skewed, 30)
    lab.password_login(weak)
    try:
        code, doc, _, _ = run_cli(capsys, "-i", str(lab.inventory_path), "doctor", "-r", skewed, "-r", weak, "--json")
        robots = by_robot(doc)
        checks = {n: {f["check"]: f for f in r["data"]["findings"]} for n, r in robots.items()}
        assert checks[skewed]["clock"]["state"] == "warn"
        assert "+30" in checks[skewed]["clock"]["detail"] or "+29" in checks[skewed]["clock"]["detail"]
        assert checks[weak]["default password"]["state"] == "warn"
        assert checks[skewed]["default password"]["state"] == "ok"
        assert checks[weak]["compose v2"]["state"] == "ok"
        assert doc["data"]["fleet_findings"][0]["state"] == "warn"
        assert code == 0
    finally:
        lab.clock_offset(skewed, 0)
        lab.password_login(weak, enabled=False)


@pytest.mark.parametrize("which", ["lab", "jazzy_lab"])  # r01 on 2.0.4; r02 on husarion_ugv 2.3.2
def test_trust_records_a_new_key(which: str, request: pytest.FixtureRequest, tmp_path: Path,
                                 capsys: pytest.CaptureFixture[str]) -> None:
    lab = request.getfixturevalue(which)
    robot = lab.robots[0] if which == "lab" else lab.robots[1]
    inv = tmp_path / "inv.yaml"
    kh = tmp_path / "kh"
    inv.write_text(
        f"settings: {{known_hosts: {kh}}}\nrobots:\n  {robot.name}: {{host: {robot.ip}, port: 22, "
        f"identity_file: {lab.identity_path}}}\n"
    )
    code, doc, _, _err = run_cli(capsys, "-i", str(inv), "status", "--json")
    assert code == 4 and "not in known_hosts" in doc["robots"][0]["message"]
    code, doc, _, err = run_cli(capsys, "-i", str(inv), "trust", robot.name, "--json")  # nobody to answer
    assert code == doc["exit_code"] == 2 and "pass --yes" in doc["error"]["message"], err
    capsys.readouterr()
    assert main(["-i", str(inv), "trust", robot.name, "--yes"]) == 0
    out = capsys.readouterr().out
    assert lab.host_fingerprint(robot.name) in out
    code, doc, _, _ = run_cli(capsys, "-i", str(inv), "trust", robot.name, "--json")
    assert code == doc["exit_code"] == 0 and doc["command"] == "trust"
    (key,) = doc["robots"]  # the change's envelope: one host key, nothing recorded this time
    assert key["robot"] == robot.name and key["outcome"] == "ok" and not key["diffs"]
    assert key["data"]["state"] == "known" and key["data"]["fingerprint"] == lab.host_fingerprint(robot.name)
    assert key["data"]["known_hosts_file"] == str(kh)
    code, doc, _, _ = run_cli(capsys, "-i", str(inv), "status", "--json")
    assert code == 0


def test_status_and_doctor_on_a_2_2_2_and_a_2_3_2_robot(jazzy_lab: Any, capsys: pytest.CaptureFixture[str]) -> None:
    """A husarion_ugv 2.3.2 (ROS 2 Jazzy) robot beside a 2.2.2 one: status reads its stack from the running
    driver's image, doctor says the Humble robot lacks the soft E-stop and battery-dead fixes (first in 2.3.2)."""
    lab = jazzy_lab
    humble, jazzy = lab.robots
    assert (humble.stack.key, jazzy.stack.key) == ("2.2.2", "2.3.2")
    code, doc, _, _ = run_cli(capsys, "-i", str(lab.inventory_path), "status", "--all", "--json")
    assert code == 0, doc
    robots = by_robot(doc)
    for r, version, generation in ((humble, "2.2.2", "2.2.1+"), (jazzy, "2.3.2", "2.3.2")):
        data = robots[r.name]["data"]
        assert robots[r.name]["outcome"] == "ok", robots[r.name]
        assert (data["stack_version"], data["stack_generation"]) == (version, generation)
        assert data["driver_image"] == r.image and data["driver_state"] == "running"
    assert robots[jazzy.name]["data"]["driver_image"] == "husarion/husarion-ugv:jazzy-2.3.2-20260622"
    # the stand-in runs as its release: /version.txt, ROS_DISTRO of the image (Dockerfile.hardware ARG ROS_DISTRO)
    seen = lab.docker(jazzy.name, "exec", "husarion_ugv_ros", "sh", "-c",
                      "echo $ROS_DISTRO; cat /version.txt; ls /opt/ros").stdout.split()
    assert seen == ["jazzy", "2.3.2", "jazzy"]
    code, doc, _, _ = run_cli(capsys, "-i", str(lab.inventory_path), "doctor", "--all", "--json")
    assert code == 0, doc
    checks = {n: {f["check"]: f for f in r["data"]["findings"]} for n, r in by_robot(doc).items()}
    assert checks[jazzy.name]["stack"] == {"check": "stack", "state": "ok", "detail": "husarion_ugv 2.3.2", "fix": None}
    assert checks[jazzy.name]["safety fixes"]["state"] == "ok"
    assert checks[jazzy.name]["compose v2"]["state"] == "ok"
    lacking = checks[humble.name]["safety fixes"]
    assert lacking["state"] == "warn" and "#606/#607" in lacking["detail"] and "#596/#603" in lacking["detail"]
    assert "first released in husarion_ugv 2.3.2" in lacking["detail"]
