"""`panther-ops teleop` without a lab: the command run in the driver container, the rate floor,
exactly one robot, a demo robot skipped."""

from __future__ import annotations

import shlex
from pathlib import Path

import pytest

from panther_ops.cli.app import main
from panther_ops.core.remote.teleop.keyboard import teleop_command


def test_teleop_command_is_the_manuals_with_repeat_rate_on_the_robots_cmd_vel() -> None:
    cmd = teleop_command("panther_ros", "/panther", 10.0)
    assert shlex.split(cmd.render(reveal=True)) == [
        "docker", "exec", "-it", "panther_ros", "/ros_entrypoint.sh", "ros2", "run", "teleop_twist_keyboard",
        "teleop_twist_keyboard", "--ros-args", "-p", "repeat_rate:=10", "-r", "cmd_vel:=/panther/cmd_vel"]
    assert "cmd_vel:=/cmd_vel" in teleop_command("c", "/", 12.5).render(reveal=True)


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
    assert "exactly one robot, 3 chosen" in capsys.readouterr().err
    # a demo robot is skipped with why (exit 0), as `estop trigger` and `driver logs` skip it
    assert main(["-i", demo, "teleop", "-r", "panther-01"]) == 0
    err = capsys.readouterr().err
    assert "panther-01: skipped: demo robot: no driver to drive (teleop needs a real robot)" in err
    assert "error" not in err
