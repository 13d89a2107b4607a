"""The fake's own rules: scripted answers (and none: a loud failure, never a robot's error),
two connections to one robot writing the same file (the second write is refused), files."""

from __future__ import annotations

from collections.abc import Callable

import pytest

from panther_ops.core.config.read import read_and_plan_args
from panther_ops.core.fleet.pipeline import ApplyOptions, apply_plan, apply_staged, stage_plan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.errors import OpsError
from panther_ops.results import Outcome
from panther_ops.testing import FakeRobot, FakeTransport, Reply, UnscriptedCommand
from panther_ops.transport.base import Command
from tests.testing.conftest import fake_of

COMPOSE = "/home/husarion/compose.yaml"


def test_scripted_answers_first_match_and_input() -> None:
    robot = FakeRobot()
    robot.answer(("docker", "compose", "up"), Reply(1, "", "no such service: x\n"))
    robot.answer(("docker",), lambda call: Reply(0, f"got {call.stdin.decode()}"))
    t = FakeTransport(robot, "r")
    up = t.run(Command.of("docker", "compose", "up", "-d", login=True, cwd="~"))
    assert (up.exit_status, up.stderr) == (1, "no such service: x\n")
    other = t.run(Command.of("docker", "ps"), stdin=b"abc")
    assert (other.ok, other.stdout) == (True, "got abc")
    assert [c.argv[:2] for c in robot.calls] == [("docker", "compose"), ("docker", "ps")]


def test_an_unscripted_command_fails_the_test_not_the_robot() -> None:
    t = FakeTransport(FakeRobot(), "r")
    with pytest.raises(UnscriptedCommand) as exc:
        t.run(Command.of("snap", "list"))
    assert not isinstance(exc.value, OpsError)
    assert "snap list" in str(exc.value)


def test_files_read_and_exist() -> None:
    t = FakeTransport(FakeRobot({"~/a.yaml": "x: 1\n"}), "r")
    assert t.read_file("~/a.yaml") == b"x: 1\n" and t.exists("/home/husarion") and not t.exists("~/b")
    with pytest.raises(FileNotFoundError):
        t.read_file("~/missing")


def test_a_command_waiting_for_input_nobody_sends_fails_the_test() -> None:
    robot = FakeRobot()
    t = FakeTransport(robot, "r")
    with pytest.raises(UnscriptedCommand) as exc:
        t.run(Command.sh("read x"), until=b"never", answer=lambda out: b"")
    assert "it would hang" in str(exc.value)


def test_two_connections_one_robot_the_later_write_is_refused(fake_ctx: Callable[..., RobotContext]) -> None:
    first = fake_ctx("panther-01")
    robot = fake_of(first)
    second = RobotContext(first.robot, FakeTransport(robot, "panther-01"), first.inventory)
    plan_a = read_and_plan_args(first, {"publish_robot_state": False}, [])
    plan_b = read_and_plan_args(second, {"use_ekf": False}, [])
    staged = stage_plan(first, plan_a, ApplyOptions())  # A staged, waiting for its go-ahead
    done_b = apply_plan(second, plan_b, ApplyOptions())  # B writes meanwhile
    assert done_b.outcome is Outcome.CHANGED, done_b.message
    late = apply_staged(first, plan_a, ApplyOptions(), staged)  # A's go-ahead: its read is stale
    assert late.outcome is Outcome.FAILED and "changed on the robot since it was read" in late.message
    text = robot.get(COMPOSE) or b""
    assert b"use_ekf:=False" in text and b"publish_robot_state:=False" not in text
    second.transport.close()
