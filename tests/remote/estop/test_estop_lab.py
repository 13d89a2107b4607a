"""Issue-14 E-stop acceptance on the lab: `estop status|trigger|reset` on real sshd + dockerd +
compose v2 robots, asked inside the driver container (the lab image's `ros2` stand-in answers
hardware/e_stop, the trigger/reset services and `topic info -v cmd_vel` with its state in a
file of the container; `ros2 topic pub` registers a cmd_vel publisher while it runs).

The fleet of 30 robots cycles the stacks 2.0.4 (namespace from the launch argument), 2.1.1
(ROBOT_NAMESPACE in compose.yaml), 2.2.2 (ROBOT_NAMESPACE from the env_file) and 2.3.2 (ROS 2 Jazzy:
the twist mux's inputs, and the driver's reset refused while the last velocity command is not zero)."""

from __future__ import annotations

import json
import subprocess
import sys
import time
from typing import Any

import pytest

from panther_ops.cli.app import main
from tests.clirun import run_cli

pytestmark = pytest.mark.lab

STATE = "/var/lib/ros2-standin"
FLEET = 30


@pytest.fixture(scope="module")
def fleet(lab_factory: Any) -> Any:
    return lab_factory(FLEET, docker=True, images=("2.0", "2.1.1", "2.2", "2.3.2"))


def cli(capsys: pytest.CaptureFixture[str], lab: Any, *argv: str) -> tuple[int, dict[str, Any]]:
    code, doc, _, _ = run_cli(capsys, "-i", str(lab.inventory_path), *argv)
    return code, doc


def e_stop_file(lab: Any, name: str) -> str:
    """The stand-in's own record of the E-stop (not through panther-ops)."""
    robot = lab.robot(name)
    cp = lab.docker(name, "exec", robot.driver_container, "sh", "-c", f"cat {STATE}/e_stop 2>/dev/null || echo unset")
    return str(cp.stdout.strip())


def start_publisher(lab: Any, name: str, topic: str = "/panther/cmd_vel", kind: str = "geometry_msgs/msg/Twist",
                    message: str = "{linear: {x: 0.1}}") -> str:
    """`ros2 topic pub` on ``topic`` in the driver container; returns its node name."""
    robot = lab.robot(name)
    registry = f"{STATE}/{topic.removeprefix('/panther/').replace('/', '_')}"
    before = _registered(lab, name, registry)
    lab.docker(name, "exec", "-d", robot.driver_container, "ros2", "topic", "pub", "--rate", "10",
               topic, kind, message, check=True)
    deadline = time.monotonic() + 5
    while time.monotonic() < deadline:
        new = _registered(lab, name, registry) - before
        if new:
            return new.pop()
        time.sleep(0.1)
    raise AssertionError(f"{name}: the publisher on {topic} did not start")


def _registered(lab: Any, name: str, registry: str) -> set[str]:
    cp = lab.docker(name, "exec", lab.robot(name).driver_container, "sh", "-c", f"ls {registry} 2>/dev/null")
    return set(cp.stdout.split())


REGISTRIES = " ".join(f"{STATE}/{r}/*" for r in ("cmd_vel", "manual_cmd_vel", "autonomous_cmd_vel"))


def stop_publishers(lab: Any, name: str) -> None:
    robot = lab.robot(name)
    lab.docker(name, "exec", robot.driver_container, "sh", "-c",
               f"for f in {REGISTRIES}; do [ -f \"$f\" ] && kill $(cat \"$f\"); done; true", check=True)
    deadline = time.monotonic() + 5
    while time.monotonic() < deadline:
        cp = lab.docker(name, "exec", robot.driver_container, "sh", "-c", f"ls {REGISTRIES} 2>/dev/null")
        if not cp.stdout.strip():
            return
        time.sleep(0.1)
    raise AssertionError(f"{name}: the cmd_vel publishers did not stop")


def test_status_in_each_stack_namespace(fleet: Any, capsys: pytest.CaptureFixture[str]) -> None:
    names = [r.name for r in fleet.robots[:3]]  # 2.0.4, 2.1.1, 2.2.2
    code, doc = cli(capsys, fleet, "estop", "status", "-r", names[0], "-r", names[1], "-r", names[2], "--json")
    assert code == 0, doc
    for r in doc["robots"]:
        assert r["outcome"] == "ok", r
        # the driver starts with the E-stop triggered; nothing publishes on cmd_vel
        assert r["data"]["namespace"] == "/panther"
        assert r["data"]["e_stop"] is (e_stop_file(fleet, r["robot"]) in ("true", "unset"))
        assert r["data"]["cmd_vel_publishers"] == []


def test_trigger_all_30_at_once(fleet: Any, capsys: pytest.CaptureFixture[str]) -> None:
    """All 30 e-stopped by one `estop trigger --all`, the CLI run as an operator runs it (a fresh
    process, from start to exit); every run must trigger every robot, and the robots must have
    been worked on at once (wall far below the sum of the robots' times).

    The 1.5 s wall budget is a benchmark's to judge (bench/, on a quiet machine: the 30 robots'
    sshd, dockerd, containerd and runc share this machine's cores), not a timed test's."""
    argv = [sys.executable, "-m", "panther_ops.cli.app", "-i", str(fleet.inventory_path), "estop", "trigger",
            "--all", "--json"]
    for _ in range(2):  # reset, then trigger again: the second emergency works as the first
        code, doc = cli(capsys, fleet, "estop", "reset", "--all", "--yes", "--json")
        assert code == 0, doc
        assert {e_stop_file(fleet, r.name) for r in fleet.robots} == {"false"}
        cp = subprocess.run(argv, check=False, capture_output=True, text=True, timeout=60)
        assert cp.returncode == 0, cp.stderr
        doc = json.loads(cp.stdout)
        assert [r["outcome"] for r in doc["robots"]] == ["changed"] * FLEET
        assert all(r["data"]["success"] is True for r in doc["robots"])
        assert {e_stop_file(fleet, r.name) for r in fleet.robots} == {"true"}
        # all at once: one robot after the other would take the sum of their times
        assert doc["duration_s"] < sum(r["duration_s"] for r in doc["robots"]) / 5, doc["duration_s"]

    code, doc = cli(capsys, fleet, "estop", "status", "--all", "--json")
    assert code == 0 and [r["data"]["e_stop"] for r in doc["robots"]] == [True] * FLEET


PTH12X_REFUSAL = "refused: Cannot reset the E-stop: the last velocity commands are not zero"
"""panther_ros@2.1.1:panther_hardware_interfaces/src/panther_system/panther_system_e_stop.cpp EStopPTH12X::ResetEStop
(the lab's Panthers are 1.2: PANTHER_ROBOT_VERSION), husarion_ugv_ros@2.2.2:husarion_ugv_hardware_interfaces/src/
robot_system/system_e_stop.cpp EStop::ResetEStop."""


def test_reset_refused_while_cmd_vel_publisher_then_accepted(fleet: Any,
                                                              capsys: pytest.CaptureFixture[str]) -> None:
    """2.0.4: a node sending a moving command on cmd_vel: panther-ops names it and calls the reset,
    the driver refuses it (the reset of a 2.2.2 robot in the same run goes); once it stopped, the reset goes."""
    one, other = fleet.robots[0].name, fleet.robots[2].name  # 2.0.4 and 2.2.2
    code, _ = cli(capsys, fleet, "estop", "trigger", "-r", one, "-r", other, "--json")
    assert code == 0
    node = start_publisher(fleet, one)
    try:
        code, doc = cli(capsys, fleet, "estop", "status", "-r", one, "--json")
        assert doc["robots"][0]["data"]["cmd_vel_publishers"] == [f"/{node}"]

        code, doc = cli(capsys, fleet, "estop", "reset", "-r", one, "-r", other, "--yes", "--json")
        assert code == 3, doc
        by = {r["robot"]: r for r in doc["robots"]}
        assert by[one]["outcome"] == "failed"
        assert PTH12X_REFUSAL in by[one]["message"], by[one]
        assert f"stop /{node} on /panther/cmd_vel or make it send zero velocity" in by[one]["message"]
        assert by[other]["outcome"] == "changed" and by[other]["data"]["e_stop"] is False
        assert e_stop_file(fleet, one) == "true"  # the driver refused
        assert e_stop_file(fleet, other) == "false"
    finally:
        stop_publishers(fleet, one)

    code, doc = cli(capsys, fleet, "estop", "reset", "-r", one, "--yes", "--json")
    assert code == 0, doc
    assert doc["robots"][0]["outcome"] == "changed" and doc["robots"][0]["data"]["e_stop"] is False
    assert doc["robots"][0]["message"] == "E-stop reset"  # the driver's answer: success, no message
    assert e_stop_file(fleet, one) == "false"
    # a second reset has nothing to do
    code, doc = cli(capsys, fleet, "estop", "reset", "-r", one, "--yes", "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "ok" and "nothing to reset" in doc["robots"][0]["message"]


@pytest.mark.parametrize("index", [1, 2], ids=["2.1.1", "2.2.2"])
def test_a_zero_publisher_does_not_block_the_reset_a_moving_one_does(fleet: Any, index: int,
                                                                     capsys: pytest.CaptureFixture[str]) -> None:
    """panther_ros 2.1.1 and husarion_ugv 2.2.2 refuse a reset only while the last velocity command is not
    zero (the diff drive controller's output: the last cmd_vel message within cmd_vel_timeout, 0.5 s on 2.1.1,
    0.2 s on 2.2.2; the publishers here send at 10 Hz): a node sending zeros (an idle joy2twist) does not
    block it; a moving one does, and the refusal names the publishers to stop."""
    name = fleet.robots[index].name
    assert fleet.robot(name).stack.key == ("2.1.1", "2.2.2")[index - 1]
    assert cli(capsys, fleet, "estop", "trigger", "-r", name, "--json")[0] == 0
    zero = start_publisher(fleet, name, message="{linear: {x: 0.0}, angular: {z: 0.0}}")
    try:
        code, doc = cli(capsys, fleet, "estop", "reset", "-r", name, "--dry-run", "--json")
        assert code == 0 and f"/{zero} on /panther/cmd_vel" in doc["robots"][0]["message"], doc
        code, doc = cli(capsys, fleet, "estop", "reset", "-r", name, "--yes", "--json")
        r = doc["robots"][0]
        assert code == 0 and r["outcome"] == "changed" and r["message"] == "E-stop reset", doc
        assert e_stop_file(fleet, name) == "false"

        # the zero publisher stops, a moving one starts (both at once: the last command is whichever message
        # came last, as on the robot): the driver refuses, and the refusal names the publisher to stop
        assert cli(capsys, fleet, "estop", "trigger", "-r", name, "--json")[0] == 0
        _stop(fleet, name, zero)
        moving = start_publisher(fleet, name, message="{linear: {x: 0.2}}")
        code, doc = cli(capsys, fleet, "estop", "reset", "-r", name, "--yes", "--json")
        r = doc["robots"][0]
        assert code == 3 and r["outcome"] == "failed", doc
        assert PTH12X_REFUSAL in r["message"]
        assert f"stop /{moving} on /panther/cmd_vel or make it send zero velocity, then reset again" in r["message"]
        assert e_stop_file(fleet, name) == "true"

        # the moving one stopped: the reset goes
        _stop(fleet, name, moving)
        code, doc = cli(capsys, fleet, "estop", "reset", "-r", name, "--yes", "--json")
        assert code == 0 and doc["robots"][0]["outcome"] == "changed" and e_stop_file(fleet, name) == "false", doc
    finally:
        stop_publishers(fleet, name)


def _stop(lab: Any, name: str, node: str) -> None:
    """Stop the cmd_vel publisher ``node`` (its process killed, as Ctrl-C would) and wait until it is gone."""
    lab.docker(name, "exec", lab.robot(name).driver_container, "sh", "-c", f"kill $(cat {STATE}/cmd_vel/{node})",
               check=True)
    deadline = time.monotonic() + 5
    while node in _registered(lab, name, f"{STATE}/cmd_vel"):
        assert time.monotonic() < deadline, f"{name}: {node} did not stop"
        time.sleep(0.1)


def test_driver_refuses_reset_when_a_publisher_starts_after_the_check(fleet: Any,
                                                                      capsys: pytest.CaptureFixture[str]) -> None:
    """The driver itself refuses (its answer shown), e.g. a node started between check and reset."""
    from panther_ops.core.fleet.inventory_file import load_inventory
    from panther_ops.core.fleet.runner import run_fleet
    from panther_ops.core.remote.estop import calls

    name = fleet.robots[1].name  # 2.1.1
    assert cli(capsys, fleet, "estop", "trigger", "-r", name, "--json")[0] == 0
    start_publisher(fleet, name)
    try:
        inv = load_inventory(str(fleet.inventory_path))
        res = run_fleet("estop reset", inv, inv.select([name], [], False), calls.reset_task).results[0]
        assert res.outcome.value == "failed"
        assert PTH12X_REFUSAL in res.message
        assert "make every node publishing on /panther/cmd_vel stop or send zero velocity" in res.message
        assert e_stop_file(fleet, name) == "true"
    finally:
        stop_publishers(fleet, name)


def test_trigger_goes_on_where_a_robot_is_unreachable_or_its_driver_stopped(fleet: Any, tmp_path: Any) -> None:
    """An unreachable robot and a robot whose driver is not running never stop the others:
    each gets its own result, the rest are e-stopped, exit 3."""
    import yaml

    names = [r.name for r in fleet.robots[:6]]
    gone, stopped = names[0], names[1]
    doc = yaml.safe_load(fleet.inventory_path.read_text())
    doc["defaults"]["connect_timeout"] = 2
    inventory = tmp_path / "inventory.yaml"
    for key in ("ssh_config", "known_hosts"):
        doc["settings"][key] = str(fleet.dir / doc["settings"][key])
    doc["defaults"]["identity_file"] = str(fleet.dir / doc["defaults"]["identity_file"])
    inventory.write_text(yaml.safe_dump(doc))
    sel = [a for n in names for a in ("-r", n)]
    assert main(["-i", str(inventory), "estop", "reset", *sel, "--yes"]) == 0
    fleet.link_down(gone)
    cp = fleet.compose(stopped, "stop", fleet.robot(stopped).driver_container)
    assert cp.returncode == 0, cp.stderr
    try:
        argv = [sys.executable, "-m", "panther_ops.cli.app", "-i", str(inventory), "estop", "trigger",
                *sel, "--json"]
        start = time.monotonic()
        cp = subprocess.run(argv, check=False, capture_output=True, text=True, timeout=60)
        assert time.monotonic() - start < 10
        assert cp.returncode == 3, cp.stderr
        by = {r["robot"]: r for r in json.loads(cp.stdout)["robots"]}
        assert by[gone]["outcome"] == "unreachable"
        assert by[stopped]["outcome"] == "failed" and "not running" in by[stopped]["message"]
        for n in names[2:]:
            assert by[n]["outcome"] == "changed" and e_stop_file(fleet, n) == "true"
    finally:
        fleet.link_up(gone)
        assert fleet.compose(stopped, "start", fleet.robot(stopped).driver_container).returncode == 0


STAMPED = "geometry_msgs/msg/TwistStamped"


def test_jazzy_reset_refused_while_the_last_velocity_is_not_zero(fleet: Any,
                                                                 capsys: pytest.CaptureFixture[str]) -> None:
    """husarion_ugv 2.3.2 (fleet.robots[3]): the driver refuses a reset while the twist mux's last
    command is not zero (husarion_ugv_ros@2.3.2:husarion_ugv_hardware_interfaces/src/robot_system/
    system_e_stop.cpp), the mux forwarding its highest-priority live input; publishers of zero
    velocity do not block it. panther-ops names the publishers of the mux inputs, lets the driver
    judge, and on its refusal says which publishers to stop."""
    name = fleet.robots[3].name
    assert fleet.robot(name).stack.key == "2.3.2"
    assert cli(capsys, fleet, "estop", "trigger", "-r", name, "--json")[0] == 0
    manual = start_publisher(fleet, name, "/panther/manual/cmd_vel", STAMPED, "{twist: {linear: {x: 0.0}}}")
    try:
        code, doc = cli(capsys, fleet, "estop", "status", "-r", name, "--json")
        data = doc["robots"][0]["data"]
        assert code == 0 and data["cmd_vel_publishers"] == [], doc
        assert data["twist_mux_publishers"] == {"/panther/manual/cmd_vel": [f"/{manual}"],
                                                "/panther/autonomous/cmd_vel": [], "/panther/cmd_vel": []}
        code, _, out, _ = run_cli(capsys, "-i", str(fleet.inventory_path), "estop", "status", "-r", name)
        assert code == 0 and f"/{manual} (manual/cmd_vel)" in out, out  # the table names the mux input
        # a publisher of zero velocity (as joy2twist is, idle) does not block the reset
        code, doc = cli(capsys, fleet, "estop", "reset", "-r", name, "--yes", "--json")
        assert code == 0 and doc["robots"][0]["outcome"] == "changed", doc
        assert doc["robots"][0]["message"] == "E-stop reset" and e_stop_file(fleet, name) == "false"

        # a moving command on a lower input: the mux forwards manual/cmd_vel's zero, the reset goes
        assert cli(capsys, fleet, "estop", "trigger", "-r", name, "--json")[0] == 0
        moving = start_publisher(fleet, name, "/panther/autonomous/cmd_vel", STAMPED, "{twist: {linear: {x: 0.3}}}")
        code, doc = cli(capsys, fleet, "estop", "reset", "-r", name, "--yes", "--json")
        assert code == 0 and e_stop_file(fleet, name) == "false", doc

        # manual/cmd_vel stops: the mux forwards autonomous/cmd_vel's 0.3 m/s and the driver refuses
        assert cli(capsys, fleet, "estop", "trigger", "-r", name, "--json")[0] == 0
        fleet.docker(name, "exec", fleet.robot(name).driver_container, "sh", "-c",
                     f"kill $(cat {STATE}/manual_cmd_vel/{manual})", check=True)
        deadline = time.monotonic() + 5
        while manual in _registered(fleet, name, f"{STATE}/manual_cmd_vel") and time.monotonic() < deadline:
            time.sleep(0.1)
        code, doc = cli(capsys, fleet, "estop", "reset", "-r", name, "--yes", "--json")
        r = doc["robots"][0]
        assert code == 3 and r["outcome"] == "failed", doc
        assert "refused: Cannot reset the E-stop: the last velocity commands are not zero" in r["message"]
        assert f"stop /{moving} on /panther/autonomous/cmd_vel or make it send zero velocity" in r["message"]
        assert e_stop_file(fleet, name) == "true"
    finally:
        stop_publishers(fleet, name)

    code, doc = cli(capsys, fleet, "estop", "reset", "-r", name, "--yes", "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "changed" and e_stop_file(fleet, name) == "false", doc
