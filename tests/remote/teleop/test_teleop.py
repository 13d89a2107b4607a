"""`panther-ops teleop` without a lab: the command run in the driver container (the keyboard
program, run here on the lab's rclpy stand-in), what the container must have, the rate floor,
exactly one robot, a demo robot skipped."""

from __future__ import annotations

import os
import shlex
import sys
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest

from panther_ops.cli.app import main
from panther_ops.core.remote.estop.answers import Section
from panther_ops.core.remote.teleop.keyboard import missing_for_keyboard, prepare, teleop_command
from panther_ops.core.remote.teleop.program import BANNER, PROGRAM
from panther_ops.errors import RemoteStateError
from panther_ops.transport.base import CommandResult
from tests.ux.termrun import keys_on_pty

RCLPY_STANDIN = Path(__file__).resolve().parents[2] / "lab" / "data" / "rclpy-standin"


def test_teleop_command_runs_the_keyboard_program_not_a_package_the_images_lack() -> None:
    """No package.xml of panther_ros 2.0.4/2.1.1 or husarion_ugv_ros 2.2.0/2.2.2 depends on
    teleop_twist_keyboard, and the images are ros-core plus rosdep's picks: the command runs
    python3 with rclpy (what every ROS 2 image has) through the image's entrypoint."""
    cmd = teleop_command("panther_ros", "/panther", 10.0)
    assert shlex.split(cmd.render(reveal=True)) == [
        "docker", "exec", "-it", "panther_ros", "/ros_entrypoint.sh", "python3", "-c", PROGRAM, "/panther/cmd_vel", "10",
        "plain"]
    assert "teleop_twist_keyboard" not in cmd.render(reveal=True)
    assert shlex.split(teleop_command("c", "/", 12.5).render(reveal=True))[-3:] == ["/cmd_vel", "12.5", "plain"]
    # husarion_ugv 2.3.2: stamped twists on the twist mux's manual input (husarion_ugv_ros@2.3.2:ROS_API.md)
    jazzy = teleop_command("husarion_ugv_ros", "/panther", 10.0, mux=True)
    assert shlex.split(jazzy.render(reveal=True))[-3:] == ["/panther/manual/cmd_vel", "10", "stamped"]


def _run_program(tmp_path: Path, keys: list[tuple[bytes, float]], args: tuple[str, ...] = ("/panther/cmd_vel", "10"),
                 registry: str = "cmd_vel") -> tuple[int, str, list[list[str]], list[str]]:
    """PROGRAM on a pseudo-terminal with the lab's rclpy stand-in: (exit, output, published rows,
    publishers registered at the end)."""
    state = tmp_path / "ros2-standin"
    env = {**os.environ, "PYTHONPATH": str(RCLPY_STANDIN), "ROS2_STANDIN_STATE": str(state),
           "ROBOT_NAMESPACE": "panther", "PYTHONDONTWRITEBYTECODE": "1"}
    code, out = keys_on_pty([sys.executable, "-c", PROGRAM, *args], keys, ready=BANNER, timeout=20, env=env)
    log = state / f"{registry}.log"
    rows = [line.split() for line in log.read_text().splitlines()] if log.exists() else []
    left = sorted(p.name for p in (state / registry).iterdir()) if (state / registry).is_dir() else []
    return code, out, rows, left


def test_keyboard_program_on_jazzy_publishes_stamped_twists_on_the_manual_input(tmp_path: Path) -> None:
    """husarion_ugv 2.3.2's twist mux subscribes TwistStamped on manual/cmd_vel (priority 100): the
    program publishes there, the keys' velocities in the stamped message's twist; a zero at the end."""
    code, out, rows, left = _run_program(tmp_path, [(b"i", 1.0), (b"k", 0.5), (b"\x03", 0.5)],
                                         ("/panther/manual/cmd_vel", "10", "stamped"), "manual_cmd_vel")
    assert code == 0, out
    assert f"{BANNER} /panther/manual/cmd_vel at 10 Hz" in out
    moves = [(float(r[1]), float(r[2])) for r in rows]
    assert (0.5, 0.0) in moves and moves[-1] == (0.0, 0.0) and len(rows) >= 10
    assert left == [] and not (tmp_path / "ros2-standin" / "cmd_vel.log").exists()


def test_keyboard_program_publishes_the_keys_at_the_rate_and_stops_the_robot_at_the_end(tmp_path: Path) -> None:
    code, out, rows, left = _run_program(tmp_path, [(b"i", 1.5), (b"j", 1.0), (b"q", 0.3), (b"k", 0.5),
                                                      (b"\x03", 0.5)])
    assert code == 0, out
    assert f"{BANNER} /panther/cmd_vel at 10 Hz" in out
    times = [float(r[0]) for r in rows]
    moves = [(float(r[1]), float(r[2])) for r in rows]
    span = times[-1] - times[0]
    assert span > 2.5 and len(rows) >= 9 * span, f"{len(rows)} messages in {span:.2f} s"  # ~10 Hz
    seen = [m for i, m in enumerate(moves) if i == 0 or m != moves[i - 1]]
    assert (0.5, 0.0) in seen and (0.0, 1.0) in seen and seen.index((0.5, 0.0)) < seen.index((0.0, 1.0))
    assert (0.0, 1.1) in seen  # q: both speeds +10 %, applied to the current move
    assert moves[-1] == (0.0, 0.0)  # k stopped it, and the last message is a stop
    assert left == []  # the publisher is gone once it ended


def test_missing_for_keyboard_names_what_the_container_lacks() -> None:
    assert missing_for_keyboard(None) is None
    assert missing_for_keyboard(Section("keyboard", "", 0)) is None
    assert missing_for_keyboard(Section("keyboard", "timeout: can't execute 'python3': No such file or directory",
                                        127)) == "python3"
    tb = "Traceback (most recent call last):\n  File \"<string>\", line 1\nModuleNotFoundError: No module named 'rclpy'"
    assert missing_for_keyboard(Section("keyboard", tb, 1)) == "rclpy"


def _frame(data: bytes) -> bytes:
    return bytes([1, 0, 0, 0]) + len(data).to_bytes(4, "big") + data


class DriverAnswers:
    """A robot's transport answering the driver container's checks (E-stop, cmd_vel, keyboard)."""

    def __init__(self, keyboard: str, status: int, publishers: str | None = None) -> None:
        publishers = publishers or ("@@publishers\nType: geometry_msgs/msg/Twist\n\nPublisher count: 0\n\n"
                                    "Subscription count: 1\n@@exit 0\n")
        self.text = ("@@ns /panther\n@@status\ndata: false\n---\n@@exit 0\n" + publishers +
                     f"@@keyboard\n{keyboard}\n@@exit {status}\n")
        self.commands: list[str] = []

    def run(self, command: Any, **_kw: Any) -> CommandResult:
        self.commands.append(command.render(reveal=True))
        return CommandResult("x", 0, "", "@@container panther_ros\n", raw_stdout=_frame(self.text.encode()))


def test_refused_before_it_starts_when_the_driver_image_lacks_python3_or_rclpy() -> None:
    for answer, status, missing in (("sh: python3: not found", 127, "has no python3"),
                                    ("ModuleNotFoundError: No module named 'rclpy'", 1, "has no rclpy")):
        transport = DriverAnswers(answer, status)
        ctx: Any = SimpleNamespace(robot=SimpleNamespace(name="r1", transport="ssh", namespace=None),
                                   transport=transport)
        with pytest.raises(RemoteStateError) as exc:
            prepare(ctx, 10.0)
        assert f"the driver container panther_ros {missing}" in str(exc.value) and "nothing was started" in str(exc.value)
        assert len(transport.commands) == 1 and "keyboard" in transport.commands[0]  # one round trip, checked first
    ok = prepare(SimpleNamespace(robot=SimpleNamespace(name="r1", transport="ssh", namespace=None),  # type: ignore[arg-type]
                                 transport=DriverAnswers("", 0)), 10.0)
    assert ok.container == "panther_ros" and ok.namespace == "/panther"
    assert list(ok.command.argv[-3:]) == ["/panther/cmd_vel", "10", "plain"]


def _info(kind: str, publishers: list[str]) -> str:
    nodes = "".join(f"Node name: {p}\nNode namespace: /panther\nTopic type: {kind}\nEndpoint type: PUBLISHER\n\n"
                    for p in publishers)
    return (f"Type: {kind}\n\nPublisher count: {len(publishers)}\n\n{nodes}Subscription count: 1\n\n"
            f"Node name: twist_mux_controller\nNode namespace: /panther\nTopic type: {kind}\n"
            "Endpoint type: SUBSCRIPTION\n")


def test_on_a_jazzy_robot_it_drives_the_twist_mux_manual_input() -> None:
    """husarion_ugv 2.3.2 (twist_mux_controller subscribes cmd_vel): stamped twists on manual/cmd_vel,
    and the gamepad's joy2twist already there is named in the warning."""
    kind = "geometry_msgs/msg/TwistStamped"
    pubs = (f"@@publishers\n{_info(kind, [])}@@exit 0\n@@publishers_manual\n{_info(kind, ['joy2twist_node'])}"
            f"@@exit 0\n@@publishers_autonomous\n{_info(kind, [])}@@exit 0\n")
    ctx: Any = SimpleNamespace(robot=SimpleNamespace(name="r1", transport="ssh", namespace=None),
                               transport=DriverAnswers("", 0, pubs))
    plan = prepare(ctx, 10.0)
    assert list(plan.command.argv[-3:]) == ["/panther/manual/cmd_vel", "10", "stamped"]
    assert plan.warnings and "/panther/joy2twist_node on /panther/manual/cmd_vel" in plan.warnings[0]


def test_rate_below_10_hz_one_robot_and_demo_skipped(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    demo = str(tmp_path / "demo")
    assert main(["demo", "init", "--dest", demo]) == 0
    capsys.readouterr()
    assert main(["-i", demo, "teleop", "-r", "panther-01", "--rate", "5"]) == 2
    assert "below 10 Hz" in capsys.readouterr().err
    for bad in ("nan", "inf", "9.99"):  # refused by the option itself: exit 2 before the inventory is loaded
        assert main(["-i", demo, "teleop", "-r", "panther-01", "--rate", bad]) == 2
        err = capsys.readouterr().err
        assert bad in err and "--rate" in err and "inventory:" not in err
    assert main(["-i", demo, "teleop", "-r", "panther-0*"]) == 2
    assert "exactly one robot, 4 chosen" in capsys.readouterr().err
    # a demo robot is skipped with why (exit 0), as `estop trigger` and `driver logs` skip it
    assert main(["-i", demo, "teleop", "-r", "panther-01"]) == 0
    err = capsys.readouterr().err
    assert "panther-01: skipped: demo robot: no driver to drive (teleop needs a real robot)" in err
    assert "error" not in err
