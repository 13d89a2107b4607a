"""The deployed manager keeps the stock safety behaviours, on lab robots (issue 11, findings 11 and 13).

* The deployed archive, run by an interpreter without site-packages (no paramiko, as in the
  robots' driver images), shuts a User Computer stand-in down over SSH with the OpenSSH client,
  against its real sshd, strict host keys, the key of the hosts' login; the computer's power-off
  stand-in records ``sudo shutdown now`` and goes silent (nothing is powered off for real).
* `manager deploy` (ROS 2 mode) on a robot whose image has neither paramiko nor ssh is refused
  (exit 2) naming what would be lost; nothing is written.
* `lights test` calls the service of the robot's stack, under its namespace, on 2.0, 2.1, 2.2 and 2.3.2,
  and judges the lights controller's answer (the lab's driver stand-in answers only its release's
  service name and type, from the image's /version.txt, as the real controller does).

Every address is a lab address (10.200.x.y).
"""

from __future__ import annotations

import json
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from panther_ops.core.manager_ops.bundle import build_bundle
from tests.clirun import run_cli
from tests.lab.computers import ComputerSpec, is_silent
from tests.lab.pyimage import restore_driver_image, use_python_image
from tests.labtools import COMPOSE, robot_of

pytestmark = pytest.mark.lab

HOSTS_22 = "/home/husarion/config/husarion_ugv_manager/config/shutdown_hosts.yaml"
COMPUTER = "uc13"


@pytest.fixture
def user_computer(lab: Any) -> Iterator[Any]:
    """A User Computer stand-in on the lab bridge: sshd, husarion with the manual's sudo rule."""
    if COMPUTER not in lab.computer_names:
        lab.add_computers([ComputerSpec(COMPUTER, sudo_rule=True)])
    computer = lab.computer(COMPUTER)
    assert set(lab.standins(COMPUTER)) >= {"/sbin/shutdown", "/sbin/poweroff", "/sbin/reboot"}
    yield computer
    lab.power_on(COMPUTER)


_DRIVER = r"""
import importlib.util, json, sys
sys.path.insert(0, sys.argv[1])
assert importlib.util.find_spec("paramiko") is None, "paramiko must not be importable here"
from panther_ops.manager.__main__ import hosts_warnings
from panther_ops.manager.clock import MonotonicClock
from panther_ops.manager.shutdown_executor import ShutdownBackends, load_shutdown_hosts, run_all, ssh_method
hosts = load_shutdown_hosts(sys.argv[2])
backends = ShutdownBackends.real(known_hosts=sys.argv[3], key_filename=sys.argv[4])
try:
    results = run_all(hosts.hosts, MonotonicClock(), backends)
finally:
    backends.close()
print(json.dumps({"method": ssh_method(), "backend": type(backends.ssh).__name__,
                  "warnings": hosts_warnings(sys.argv[2], sys.argv[3]),
                  "results": [{"state": r.state.value, "message": r.message} for r in results]}))
"""


def test_deployed_archive_without_paramiko_shuts_a_user_computer_down_over_ssh(
        lab: Any, user_computer: Any, tmp_path: Path) -> None:
    pyz = tmp_path / "panther_ops_manager.pyz"
    pyz.write_bytes(build_bundle().data)  # the very archive `manager deploy` uploads
    hosts = tmp_path / "shutdown_hosts.yaml"
    hosts.write_text(f"hosts:\n  - ip: {user_computer.ip}\n    username: husarion\n    timeout: 10.0\n")
    assert user_computer.ip.startswith("10.200.")
    calls_before = len(lab.power_calls(COMPUTER))
    # -I -S: no site-packages at all (no paramiko, no PyYAML C loader): the archive alone, as on a robot
    cp = subprocess.run([sys.executable, "-I", "-S", "-c", _DRIVER, str(pyz), str(hosts),
                         str(lab.computers_known_hosts_path), str(lab.dir / "id_ed25519")],
                        capture_output=True, text=True, timeout=60, check=False)
    assert cp.returncode == 0, cp.stderr
    doc = json.loads(cp.stdout)
    assert doc["method"] == "openssh" and doc["backend"] == "OpenSshShutdown" and doc["warnings"] == []
    assert doc["results"] == [{"state": "SUCCESS", "message": doc["results"][0]["message"]}], doc
    calls = lab.power_calls(COMPUTER)[calls_before:]
    assert len(calls) == 1 and calls[0]["sudo_user"] == "husarion", calls  # sudo shutdown now, as husarion
    assert calls[0]["action"] in ("shutdown", "poweroff"), calls
    assert is_silent(lab, COMPUTER)  # "powered off" as the network sees it (the stand-in)


def test_deployed_archive_refuses_an_unknown_host_key_of_a_user_computer(
        lab: Any, user_computer: Any, tmp_path: Path) -> None:
    pyz = tmp_path / "panther_ops_manager.pyz"
    pyz.write_bytes(build_bundle().data)
    hosts = tmp_path / "shutdown_hosts.yaml"
    hosts.write_text(f"hosts:\n  - ip: {user_computer.ip}\n    username: husarion\n    timeout: 5.0\n")
    empty = tmp_path / "known_hosts"
    empty.write_text("")
    calls_before = len(lab.power_calls(COMPUTER))
    cp = subprocess.run([sys.executable, "-I", "-S", "-c", _DRIVER, str(pyz), str(hosts), str(empty),
                         str(lab.dir / "id_ed25519")], capture_output=True, text=True, timeout=60, check=False)
    assert cp.returncode == 0, cp.stderr
    doc = json.loads(cp.stdout)
    result = doc["results"][0]
    assert result["state"] == "FAILURE" and "Host key verification failed" in result["message"], result
    assert doc["warnings"] == [f"no host key in {empty} for husarion@{user_computer.ip}:22: their SSH shutdown "
                               "will fail (unknown host keys are refused)"]  # said at start, too
    assert lab.power_calls(COMPUTER)[calls_before:] == []
    assert empty.read_text() == ""


@pytest.fixture
def python_22(lab: Any) -> Iterator[str]:
    """The 2.2.2 robot on the Python stand-in image (python3; no paramiko, no ssh, no dbus-send)."""
    name = robot_of(lab, "2.2.2")
    compose, hosts = lab.read(name, COMPOSE), lab.read(name, HOSTS_22)
    use_python_image(lab, name)
    yield name
    lab.write(name, HOSTS_22, hosts)
    lab.write(name, COMPOSE, compose)
    restore_driver_image(lab, name)
    lab.compose(name, "up", "-d")


def test_deploy_is_refused_where_the_image_cannot_shut_user_computers_down(
        lab: Any, python_22: str, capsys: pytest.CaptureFixture[str]) -> None:
    name = python_22
    # an SSH-era entry is not a 2.2.2 hosts file (2.2.1+ shuts computers down over HTTP): the hosts
    # file's one validator refuses it before the image is even asked (nothing runs, nothing written)
    lab.write(name, HOSTS_22, "hosts:\n  - ip: 10.200.250.3\n    username: husarion\n")
    before = lab.read_bytes(name, COMPOSE)
    code, _doc, out, err = run_cli(capsys, "-i", str(lab.inventory_path), "manager", "deploy", "-r", name,
                                   "--ros2", "--yes", "--settle", "2")
    text = out + err
    assert code == 2, text
    assert "shuts computers down over HTTP" in text and "Traceback" not in text
    assert lab.read_bytes(name, COMPOSE) == before
    # an HTTP entry (a lab address, never contacted): the image still cannot power the robot itself off
    lab.write(name, HOSTS_22, "hosts:\n  - ip: 10.200.250.3\n    port: 3003\n    secret: a-long-shared-secret-for-the-nuc\n")
    code, _doc, out, err = run_cli(capsys, "-i", str(lab.inventory_path), "manager", "deploy", "-r", name,
                                   "--ros2", "--yes", "--settle", "2")
    text = out + err
    assert code == 2, text
    assert "would lose what the stock manager does on husarion_ugv 2.2.2" in text
    assert "powering the robot itself off (ssh ...): no ssh in the image" in text
    assert "Traceback" not in text
    assert lab.read_bytes(name, COMPOSE) == before
    assert lab.sh(name, "test -e /home/husarion/panther-ops").returncode != 0
    # the same robot, simulation mode (drives nothing on the robot): not refused by the check
    code, _doc, out, err = run_cli(capsys, "-i", str(lab.inventory_path), "manager", "deploy", "-r", name,
                                   "--sim", "--dry-run")
    assert code == 0, out + err


@pytest.mark.parametrize(("version", "service", "srv_type"), [
    ("2.0.4", "/panther/lights/controller/set/animation", "panther_msgs/srv/SetLEDAnimation"),
    ("2.1.1", "/panther/lights/set_animation", "panther_msgs/srv/SetLEDAnimation"),
    ("2.2.2", "/panther/lights/set_animation", "husarion_ugv_msgs/srv/SetLEDAnimation"),
    # husarion_ugv_ros@2.3.2:husarion_ugv_lights/src/lights_controller_node.cpp: 2.2's service, on Jazzy
    ("2.3.2", "/panther/lights/set_animation", "husarion_ugv_msgs/srv/SetLEDAnimation"),
])
def test_lights_test_calls_the_stacks_service_under_its_namespace(
        request: pytest.FixtureRequest, capsys: pytest.CaptureFixture[str], version: str, service: str,
        srv_type: str) -> None:
    lab = request.getfixturevalue("jazzy_lab" if version == "2.3.2" else "lab")
    name = robot_of(lab, version)
    robot = lab.robot(name)
    code, doc, out, err = run_cli(capsys, "-i", str(lab.inventory_path), "lights", "test", "9", "--repeating",
                                  "-r", name, "--json")
    assert code == 0, out + err
    res = doc["robots"][0]
    assert res["outcome"] == "changed" and res["message"] == f"animation 9 requested on {service}", res
    argv = res["data"]["argv"]
    assert argv[:5] == ["ros2", "service", "call", service, srv_type]
    assert "SetLEDAnimation_Response(success=True" in res["data"]["response"]  # the controller's answer
    log = lab.docker(name, "exec", robot.driver_container, "cat", "/var/log/ros2-standin.log").stdout
    assert f"ros2 service call {service} {srv_type}" in log  # what ran in the driver container
    # an animation the release does not have: the controller's own refusal, not a change
    code, doc, out, err = run_cli(capsys, "-i", str(lab.inventory_path), "lights", "test", "21", "-r", name,
                                  "--json")
    res = doc["robots"][0]
    assert code != 0 and res["outcome"] == "failed", out + err
    assert f"{service} refused animation 21: No animation with ID: 21" in res["message"]
    # the other releases' service names are never answered on this one (the real CLI waits)
    for other in {"/panther/lights/controller/set/animation", "/panther/lights/set_animation"} - {service}:
        cp = lab.docker(name, "exec", robot.driver_container, "/ros_entrypoint.sh", "timeout", "2", "ros2", "service",
                        "call", other, srv_type, "{animation: {id: 9, param: ''}, repeating: false}")
        assert cp.returncode != 0 and "response:" not in cp.stdout, cp.stdout


def test_lights_test_knows_the_animations_only_2_3_2_has(jazzy_lab: Any, capsys: pytest.CaptureFixture[str]) -> None:
    """16 GOAL_FAILED and 17 FLOOD_LIGHT are stock animations from husarion_ugv 2.3.2 on
    (husarion_ugv_ros@2.3.2:husarion_ugv_lights/config/panther_animations.yaml): the 2.3.2 robot's
    controller plays 16, the 2.2.2 robot's refuses it."""
    humble, jazzy = robot_of(jazzy_lab, "2.2.2"), robot_of(jazzy_lab, "2.3.2")
    code, doc, out, err = run_cli(capsys, "-i", str(jazzy_lab.inventory_path), "lights", "test", "16", "-r", humble,
                                  "-r", jazzy, "--json")
    by = {r["robot"]: r for r in doc["robots"]}
    assert code == 3, out + err
    assert by[jazzy]["outcome"] == "changed", by[jazzy]
    assert by[humble]["outcome"] == "failed" and "No animation with ID: 16" in by[humble]["message"]
