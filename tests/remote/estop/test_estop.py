"""`panther-ops estop` without a lab: the ROS 2 CLI texts parsed, the robot's command, and the
demo fleet answering from its recording (no driver is called on a demo robot)."""

from __future__ import annotations

import json
import shlex
from pathlib import Path
from typing import Any

import pytest

from panther_ops.cli.app import main
from panther_ops.core.remote.estop import answers, plan
from panther_ops.core.remote.estop.calls import CONTAINER_SCRIPT, command
from panther_ops.errors import RemoteStateError

INFO_TWO = """Type: geometry_msgs/msg/Twist

Publisher count: 2

Node name: teleop_twist_keyboard
Node namespace: /
Topic type: geometry_msgs/msg/Twist
Endpoint type: PUBLISHER
GID: 01.0f.a1
QoS profile:
  Reliability: RELIABLE

Node name: joy2twist_node
Node namespace: /panther
Topic type: geometry_msgs/msg/Twist
Endpoint type: PUBLISHER

Subscription count: 1

Node name: drive_controller
Node namespace: /panther
Topic type: geometry_msgs/msg/Twist
Endpoint type: SUBSCRIPTION
"""


# The drivers' refusals of a reset for a non-zero velocity command (panther_ros@2.1.1:panther_hardware_interfaces/
# src/panther_system/panther_system_e_stop.cpp EStopPTH12X/EStopPTH10X::ResetEStop; husarion_ugv_ros@2.2.2:
# husarion_ugv_hardware_interfaces/src/robot_system/system_e_stop.cpp EStop::ResetEStop has the PTH12X one)
PTH12X_REFUSAL = ("Cannot reset the E-stop: the last velocity commands are not zero. Ensure that the controller is "
                  "sending zero velocity commands or not sending any velocity commands before attempting to reset "
                  "the E-stop.")
PTH10X_REFUSAL = ("Can't reset E-stop - last velocity commands are different than zero. Make sure that your "
                  "controller sends zero commands before trying to reset E-stop.")


def _state(e_stop: str, info: str) -> plan.State:
    return plan.state_of(answers.Answers("/panther", {"status": answers.Section("status", e_stop, 0),
                                                      "publishers": answers.Section("publishers", info, 0)}))


def test_reset_planned_whoever_publishes_the_driver_judges() -> None:
    """Up to 2.2 a publisher on cmd_vel no longer refuses the reset in the plan: the driver refuses only
    while the last velocity command is not zero, and a node sending zeros (idle joy2twist) does not block
    it; the plan names the publishers."""
    got = plan.plan_reset("r1", _state("data: true\n---\n", INFO_TWO))
    assert [type(s).__name__ for s in got.steps] == ["ResetEstop"]
    assert "the driver refuses it while the last velocity command is not zero" in got.summary
    assert "/teleop_twist_keyboard on /panther/cmd_vel, /panther/joy2twist_node on /panther/cmd_vel" in got.summary
    assert got.data["cmd_vel_publishers"] == ["/teleop_twist_keyboard", "/panther/joy2twist_node"]
    none = "Type: geometry_msgs/msg/Twist\n\nPublisher count: 0\n\n" + INFO_TWO[INFO_TWO.index("Subscription count:"):]
    nobody = plan.plan_reset("r1", _state("data: true\n---\n", none))
    assert nobody.steps and "nobody publishes on /panther/cmd_vel" in nobody.summary
    # not triggered: nothing to do, the publishers named
    idle = plan.plan_reset("r1", _state("data: false\n---\n", INFO_TWO))
    assert not idle.steps and idle.noop is not None and "nothing to reset" in idle.noop
    assert "/teleop_twist_keyboard" in idle.noop
    with pytest.raises(RemoteStateError, match="no message on /panther/hardware/e_stop"):
        plan.plan_reset("r1", _state("waiting...", INFO_TWO))


def test_a_velocity_refusal_is_told_apart_and_names_the_publishers_to_stop() -> None:
    assert plan.refused_for_velocity(PTH12X_REFUSAL) and plan.refused_for_velocity(PTH10X_REFUSAL)
    assert not plan.refused_for_velocity("Can't reset E-stop - motors are not powered.")
    planned = _state("data: true\n---\n", INFO_TWO).to_json()
    assert plan.nonzero_hint(planned) == ("stop /teleop_twist_keyboard on /panther/cmd_vel, /panther/joy2twist_node on "
                                          "/panther/cmd_vel or make it send zero velocity, then reset again")
    assert plan.nonzero_hint({"namespace": "/panther", "cmd_vel_publishers": []}) == (
        "make every node publishing on /panther/cmd_vel stop or send zero velocity, then reset again")
    mux = {"namespace": "/panther", "cmd_vel_publishers": [],
           "twist_mux_publishers": {"/panther/manual/cmd_vel": ["/joy2twist"], "/panther/autonomous/cmd_vel": [],
                                    "/panther/cmd_vel": []}}
    assert plan.nonzero_hint(mux).startswith("stop /joy2twist on /panther/manual/cmd_vel or")
    mux["twist_mux_publishers"] = {}
    assert "/panther/manual/cmd_vel, /panther/autonomous/cmd_vel, /panther/cmd_vel stop" in plan.nonzero_hint(mux)


def test_publishers_are_the_publishing_nodes_only() -> None:
    assert answers.publishers(INFO_TWO) == ["/teleop_twist_keyboard", "/panther/joy2twist_node"]
    assert answers.publishers("Type: x\n\nPublisher count: 0\n\nSubscription count: 0\n") == []
    assert answers.publishers("Unknown topic '/panther/cmd_vel'") is None


def test_e_stop_state_and_trigger_response() -> None:
    assert answers.e_stop_state("data: true\n---\n") is True
    assert answers.e_stop_state("data: false\n---\n") is False
    assert answers.e_stop_state("waiting for service to become available...") is None
    text = ("requester: making request: std_srvs.srv.Trigger_Request()\n\nresponse:\n"
            "std_srvs.srv.Trigger_Response(success=False, message=\"Can't reset E-stop - last velocity commands are "
            "different than zero. Make sure that your controller sends zero commands before trying to reset E-stop.\")\n")
    assert answers.trigger_response(text) == (False, PTH10X_REFUSAL)
    assert answers.trigger_response("std_srvs.srv.Trigger_Response(success=True, message=\"it's done\")") == \
        (True, "it's done")
    assert answers.trigger_response("waiting for service to become available...") is None


def test_docker_stream_frames_and_errors() -> None:
    def frame(stream: int, data: bytes) -> bytes:
        return bytes([stream, 0, 0, 0]) + len(data).to_bytes(4, "big") + data

    raw = frame(1, b"@@ns /panther\n") + frame(2, b"waiting...\n") + frame(1, b"@@status\n")
    assert answers.docker_stream(raw) == ("@@ns /panther\n@@status\n", "waiting...\n")
    assert answers.docker_stream(b'{"message":"Container abc is not running"}') == \
        ("", '{"message":"Container abc is not running"}')
    assert answers.docker_stream(frame(1, b"data: true\n")[:-3]) == ("data: tr", "")


def test_split_sections_with_exit_status_and_a_cut_short_one() -> None:
    got = answers.split("@@ns /panther\n@@status\ndata: true\n---\n@@exit 0\n@@publishers\nType: x\n")
    assert got.namespace == "/panther"
    assert got.sections["status"] == answers.Section("status", "data: true\n---", 0)
    assert got.sections["publishers"].status is None and got.sections["publishers"].text == "Type: x"


def test_robot_command_quotes_everything_and_refuses_unknown_actions() -> None:
    cmd = command("panther; rm -rf /", ("status", "publishers"))
    words = shlex.split(cmd.render(reveal=True))
    assert words[:2] == ["sh", "-c"]
    assert words[5:] == ["husarion_ugv_ros", "/run/husarion/robot_config.env", "panther_ros",
                         "/run/husarion/panther_config.env"]
    # the exec's JSON: the container script and its arguments as one argv (no shell in between)
    assert json.loads(words[4]) == {"AttachStdout": True, "AttachStderr": True, "Cmd": [
        "/ros_entrypoint.sh", "sh", "-c", CONTAINER_SCRIPT, "sh", "10", "panther; rm -rf /", "status", "publishers"]}
    with pytest.raises(ValueError):
        command("", ("status", "rm"))


def _cli(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, dict[str, Any]]:
    capsys.readouterr()
    code = main(list(argv))
    out = capsys.readouterr().out
    return code, json.loads(out) if out.strip().startswith("{") else {}


def test_demo_fleet_answers_as_recorded(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    demo = str(tmp_path / "demo")
    assert main(["demo", "init", "--dest", demo]) == 0
    code, doc = _cli(capsys, "-i", demo, "estop", "status", "--all", "--json")
    assert code == 0
    data = {r["robot"]: r["data"] for r in doc["robots"]}
    assert data["panther-01"] == {"namespace": "/panther", "e_stop": True, "cmd_vel_publishers": [], "recorded": True}
    assert data["panther-02"]["cmd_vel_publishers"] == ["/teleop_twist_keyboard"]
    assert data["panther-03"]["e_stop"] is False

    code, doc = _cli(capsys, "-i", demo, "estop", "trigger", "--all", "--json")
    assert code == 0 and {r["outcome"] for r in doc["robots"]} == {"skipped"}

    # reset: the check runs on the recording (panther-03 has nothing to reset); a publisher does not refuse
    # it (the driver judges the last velocity command), and a demo robot has no driver to call
    code, doc = _cli(capsys, "-i", demo, "estop", "reset", "--all", "--yes", "--json")
    assert code == 0, doc
    by = {r["robot"]: r for r in doc["robots"]}
    assert by["panther-02"]["outcome"] == "skipped" and by["panther-02"]["message"] == "demo robot: no driver to call"
    assert by["panther-03"]["outcome"] == "ok" and "nothing to reset" in by["panther-03"]["message"]
    assert by["panther-01"]["outcome"] == "skipped"


def test_reset_without_yes_is_refused_when_not_interactive(tmp_path: Path,
                                                            capsys: pytest.CaptureFixture[str]) -> None:
    demo = str(tmp_path / "demo")
    assert main(["demo", "init", "--dest", demo]) == 0
    capsys.readouterr()
    assert main(["-i", demo, "estop", "reset", "-r", "panther-01"]) == 2
    assert "needs confirmation: pass --yes" in capsys.readouterr().err
    code, doc = _cli(capsys, "-i", demo, "estop", "reset", "-r", "panther-01", "--dry-run", "--json")
    assert code == 0 and doc["notes"] == ["dry run: would reset panther-01"]


def test_demo_recording_missing_is_a_failure_with_the_fix(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    demo = tmp_path / "demo"
    assert main(["demo", "init", "--dest", str(demo)]) == 0
    (demo / "robots" / "panther-01" / "var/lib/panther-ops-demo/ros.json").unlink()
    code, doc = _cli(capsys, "-i", str(demo), "estop", "status", "-r", "panther-01", "--json")
    assert code == 3 and doc["robots"][0]["outcome"] == "failed"
    assert "demo init --force" in doc["robots"][0]["data"]["hint"]


FAKE_CURL = r"""#!/bin/sh
# curl as the docker engine answers on its socket: $FAKE/exec_<container> (the exec's JSON or
# the engine's error), $FAKE/svc_<service> (the running containers of that compose service)
echo "curl $*" >> "$FAKE/log"
[ -e "$FAKE/down" ] && { echo "curl: (7) Couldn't connect to server" >&2; exit 7; }
svc=
for a in "$@"; do
    case $a in
        *com.docker.compose.service=*) svc=${a#*service=}; svc=${svc%%\"*} ;;
        http://docker/containers/json) cat "$FAKE/svc_$svc" 2>/dev/null || echo '[]' ;;
        http://docker/containers/*/exec)
            c=${a#http://docker/containers/}; c=${c%/exec}
            cat "$FAKE/exec_$c" 2>/dev/null || echo "{\"message\":\"No such container: $c\"}" ;;
        http://docker/exec/*/start) id=${a#http://docker/exec/}; echo "started ${id%/start}" ;;
    esac
done
"""


def _robot_script(tmp_path: Path, stack: str = "2.2", **engine: str) -> tuple[int, str, str, list[str]]:
    """ROBOT_SCRIPT run by sh against a stand-in of curl and the engine's answers, on a robot
    whose OS wrote the environment file of ``stack`` (2.2: robot_config.env, 2.1: panther_config.env)."""
    import os
    import subprocess

    from panther_ops.core.containers.driver_exec import ROBOT_SCRIPT

    fake = tmp_path / "engine"
    (fake / "bin").mkdir(parents=True, exist_ok=True)
    (fake / "bin" / "curl").write_text(FAKE_CURL)
    (fake / "bin" / "curl").chmod(0o755)
    (fake / ("robot_config.env" if stack == "2.2" else "panther_config.env")).write_text("")
    for name, answer in engine.items():
        (fake / name).write_text(answer + "\n")
    pairs = ["husarion_ugv_ros", str(fake / "robot_config.env"), "panther_ros", str(fake / "panther_config.env")]
    cp = subprocess.run(["sh", "-c", ROBOT_SCRIPT, "sh", '{"Cmd":["true"]}', *pairs],
                        check=False, capture_output=True, text=True, timeout=10,
                        env={**os.environ, "FAKE": str(fake), "PATH": f"{fake / 'bin'}:{os.environ['PATH']}"})
    log = (fake / "log").read_text().splitlines() if (fake / "log").exists() else []
    return cp.returncode, cp.stdout, cp.stderr, log


def test_robot_script_asks_for_the_stacks_own_driver_name_first(tmp_path: Path) -> None:
    """Two curl per robot (the exec made, then started), the name of the robot's stack asked
    for first: the other name is never looked up (no miss in the engine's log)."""
    code, out, err, log = _robot_script(tmp_path / "a", "2.1", exec_panther_ros='{"Id":"abc123"}')
    assert (code, out.strip(), err.strip()) == (0, "started abc123", "@@container panther_ros")
    assert len(log) == 2 and "/containers/panther_ros/exec" in log[0] and "husarion_ugv_ros" not in " ".join(log)

    code, out, err, log = _robot_script(tmp_path / "b", "2.2", exec_husarion_ugv_ros='{"Id":"def456"}')
    assert (code, out.strip(), err.strip()) == (0, "started def456", "@@container husarion_ugv_ros")
    assert len(log) == 2 and "panther_ros" not in " ".join(log)

    # the OS's file says 2.2 but the driver is still panther_ros: one more curl
    code, out, err, log = _robot_script(tmp_path / "c", "2.2", exec_panther_ros='{"Id":"0ld"}')
    assert (code, out.strip(), err.strip()) == (0, "started 0ld", "@@container panther_ros")
    assert len(log) == 3


def test_robot_script_compose_service_then_errors(tmp_path: Path) -> None:
    # neither name: the container of the compose service
    code, out, err, log = _robot_script(tmp_path / "a", svc_panther_ros='[{"Id":"c0ffee","Names":["/x"]}]',
                                        exec_c0ffee='{"Id":"e1"}')
    assert (code, out.strip(), err.strip()) == (0, "started e1", "@@container c0ffee")
    assert len(log) == 6  # each name, each service looked up, the exec, its start
    # a stopped driver: the engine's words, exit 3
    code, out, err, _ = _robot_script(tmp_path / "b", "2.1",
                                      exec_panther_ros='{"message":"Container 0a1b is not running"}')
    assert code == 3 and out == ""
    assert "no running driver container" in err and "Container 0a1b is not running" in err
    # no engine to talk to
    (tmp_path / "c" / "engine").mkdir(parents=True)
    (tmp_path / "c" / "engine" / "down").write_text("")
    code, _, err, _ = _robot_script(tmp_path / "c")
    assert code == 4 and "Couldn't connect" in err
