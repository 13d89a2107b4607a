"""The manual's nodes, tick by tick (CallSetBool/Trigger/SetLedAnimation, SignalShutdown,
TickAfterTimeout, ShutdownSingleHost, ShutdownHostsFromFile, ExecuteCommand)."""

from __future__ import annotations

from concurrent.futures import Future
from pathlib import Path
from typing import Any

import py_trees
import pytest
import yaml
from py_trees.common import Status

from panther_ops.manager.clock import ManualClock
from panther_ops.manager.nodes.base import PyProgram, Ref
from panther_ops.manager.nodes.decorators import Guard, TickAfterTimeout
from panther_ops.manager.nodes.services import (
    CallSetBoolService,
    CallSetLedAnimationService,
    CallTriggerService,
)
from panther_ops.manager.nodes.shutdown import (
    ExecuteCommand,
    ShutdownHostsFromFile,
    ShutdownSingleHost,
    SignalShutdown,
)
from panther_ops.manager.robot_io import ServiceResult
from panther_ops.manager.shutdown_executor.backends import CommandOutcome
from tests.manager.doubles import FakeLocalRunner, FakeRobotIO, fake_backends, make_ctx, tick

S, F, R = Status.SUCCESS, Status.FAILURE, Status.RUNNING


def test_call_set_bool_service_sends_then_reads_the_response(io: FakeRobotIO, clock: ManualClock) -> None:
    node = CallSetBoolService("EnableFan", make_ctx(io, clock), data="true",
                              service_name="hardware/fan_enable")
    assert tick(node) == R
    assert io.requests == ["hardware/fan_enable(data=True)"]
    assert tick(node) == S
    assert tick(node) == R and len(io.calls) == 2  # a new run sends a new request


def test_a_refused_request_fails(io: FakeRobotIO, clock: ManualClock) -> None:
    io.answer = ServiceResult(False, "driver busy")
    node = CallTriggerService("EStop", make_ctx(io, clock), service_name="hardware/e_stop_trigger")
    assert tick(node) == R and io.requests == ["hardware/e_stop_trigger()"]
    assert tick(node) == F and "driver busy" in node.feedback_message


def test_no_response_within_the_service_timeout_fails_and_cancels(io: FakeRobotIO,
                                                                  clock: ManualClock) -> None:
    io.answer = None
    node = CallTriggerService("EStop", make_ctx(io, clock), service_name="hardware/e_stop_trigger")
    assert tick(node) == R
    clock.advance(0.9)
    assert tick(node) == R
    clock.advance(0.2)
    assert tick(node) == F and io.calls[0][1].cancelled


def test_halting_a_waiting_call_cancels_it(io: FakeRobotIO, clock: ManualClock) -> None:
    io.answer = None
    node = CallSetBoolService("Aux", make_ctx(io, clock), data=False,
                              service_name="hardware/aux_power_enable")
    assert tick(node) == R
    node.stop(Status.INVALID)
    assert io.calls[0][1].cancelled


def test_led_animation_ports_read_the_blackboard(io: FakeRobotIO, clock: ManualClock) -> None:
    ctx = make_ctx(io, clock, {"CHARGING_BATTERY_ANIM_ID": 9, "battery_percent_round": "0.700000"})
    node = CallSetLedAnimationService("Charging", ctx, id=Ref("CHARGING_BATTERY_ANIM_ID"),
                                      param=Ref("battery_percent_round"), repeating="true",
                                      service_name="lights/set_animation")
    assert tick(node) == R and tick(node) == S
    assert io.requests == ["lights/set_animation(id=9, param='0.700000', repeating=True)"]
    plain = CallSetLedAnimationService("Low", ctx, id="6", service_name="lights/set_animation")
    tick(plain)
    assert io.requests[-1] == "lights/set_animation(id=6, param='', repeating=False)"
    negative = CallSetLedAnimationService("Bad", ctx, id=-1, service_name="lights/set_animation")
    assert tick(negative) == F and "unsigned" in negative.feedback_message


def test_signal_shutdown_sets_the_flag_and_reason_under_both_port_names(io: FakeRobotIO,
                                                                        clock: ManualClock) -> None:
    ctx = make_ctx(io, clock, {"signal_shutdown": (False, "")})
    assert tick(SignalShutdown("Dead", ctx, reason="Battery dead")) == S
    assert ctx.blackboard.get("signal_shutdown") == (True, "Battery dead")
    assert tick(SignalShutdown("Seed", ctx, message="From the manual's port name")) == S
    assert ctx.blackboard.get("signal_shutdown") == (True, "From the manual's port name")


class Count(py_trees.behaviour.Behaviour):
    def __init__(self, status: Status) -> None:
        super().__init__("count")
        self.result, self.ticks = status, 0

    def update(self) -> Status:
        self.ticks += 1
        return self.result


def test_tick_after_timeout_waits_from_setup_and_restarts_only_on_success(io: FakeRobotIO,
                                                                        clock: ManualClock) -> None:
    ctx = make_ctx(io, clock, {"PERIOD": 10.0})
    child = Count(S)
    node = TickAfterTimeout("period", child, ctx, timeout=Ref("PERIOD"))
    node.setup_with_descendants()
    clock.advance(9.9)
    assert tick(node) is None and child.ticks == 0
    clock.advance(0.1)
    assert tick(node) == S and child.ticks == 1
    clock.advance(5)
    assert tick(node) is None
    clock.advance(5)
    child.result = F
    assert tick(node) == F
    clock.advance(0.1)
    assert tick(node) == F and child.ticks == 3   # a failure does not restart the timer


def test_tick_after_timeout_is_not_restarted_by_a_skipped_child(io: FakeRobotIO,
                                                               clock: ManualClock) -> None:
    ctx = make_ctx(io, clock)
    child = Count(S)
    state = {"skip": True}
    node = TickAfterTimeout("period", Guard(child, ctx, skip_if=PyProgram("s", lambda e: state["skip"])),
                            ctx, timeout=5.0)
    node.setup_with_descendants()
    clock.advance(5)
    assert tick(node) is None
    clock.advance(0.1)
    state["skip"] = False
    assert tick(node) == S and child.ticks == 1  # still due: the skip did not restart it
    clock.advance(0.1)
    assert tick(node) is None


def host_ports(**extra: Any) -> dict[str, Any]:
    return {"ip": "192.0.2.3", "username": "husarion", **extra}


def test_shutdown_single_host_walks_its_states(io: FakeRobotIO, clock: ManualClock) -> None:
    backends = fake_backends(clock, up={"192.0.2.3": True}, down_after=0.5)
    node = ShutdownSingleHost("NUC", make_ctx(io, clock, backends=backends), **host_ports())
    seen = []
    for _ in range(20):
        status = tick(node)
        seen.append(node.work.state.value if node.work else None)
        if status != R:
            break
        clock.advance(0.1)
    assert status == S
    assert seen[:4] == ["IDLE", "COMMAND_EXECUTED", "RESPONSE_RECEIVED", "PINGING"]
    assert seen[-1] == "SUCCESS"
    assert backends.ssh.requests[0].command == "sudo shutdown now"  # type: ignore[attr-defined]


def test_shutdown_single_host_outcomes(io: FakeRobotIO, clock: ManualClock) -> None:
    down = fake_backends(clock, up={})
    node = ShutdownSingleHost("gone", make_ctx(io, clock, backends=down), **host_ports())
    assert tick(node) == R and tick(node) == S  # not answering ping: skipped counts as done
    assert node.work is not None and node.work.state.value == "SKIPPED"

    refused = fake_backends(clock, up={"192.0.2.3": True},
                            outcomes={"192.0.2.3": CommandOutcome(False, error="Connection refused")})
    node = ShutdownSingleHost("refused", make_ctx(io, clock, backends=refused), **host_ports())
    assert [tick(node) for _ in range(3)] == [R, R, F]
    assert "Connection refused" in node.feedback_message

    quick = fake_backends(clock, up={"192.0.2.3": True}, down_after=None)
    node = ShutdownSingleHost("quick", make_ctx(io, clock, backends=quick),
                              **host_ports(ping_for_success="false"))
    assert [tick(node) for _ in range(4)] == [R, R, R, S]

    stubborn = fake_backends(clock, up={"192.0.2.3": True}, down_after=None)
    node = ShutdownSingleHost("stubborn", make_ctx(io, clock, backends=stubborn),
                              **host_ports(timeout=2.0))
    status, started = R, clock.now()
    while status == R and clock.now() - started < 10:
        status = tick(node)
        clock.advance(0.1)
    assert status == F and "Timeout exceeded" in node.feedback_message
    assert 2.0 < clock.now() - started < 2.5


def write_hosts(path: Path, hosts: list[dict[str, Any]]) -> str:
    path.write_text(yaml.safe_dump({"hosts": hosts}))
    return str(path)


def test_shutdown_hosts_from_file_runs_hosts_side_by_side(io: FakeRobotIO, clock: ManualClock,
                                                          tmp_path: Path) -> None:
    hosts = write_hosts(tmp_path / "hosts.yaml", [
        {"ip": "192.0.2.3", "username": "husarion"},
        {"ip": "192.0.2.4", "username": "root"},
        {"ip": "192.0.2.12", "username": "pi", "timeout": 40,
         "command": "/home/pi/my_long_shutdown_sequence.sh"},
        {"ip": "192.0.2.3", "username": "husarion"},  # duplicate
    ])
    backends = fake_backends(clock, up={"192.0.2.3": True, "192.0.2.12": True}, down_after=0.3)
    node = ShutdownHostsFromFile("hosts", make_ctx(io, clock, {"PATH": hosts}, backends),
                                 shutdown_hosts_file=Ref("PATH"))
    assert tick(node) == R
    assert node.work is not None and len(node.work.machines) == 3
    assert tick(node) == R
    states = [m.state.value for m in node.work.machines]
    assert states == ["COMMAND_EXECUTED", "SKIPPED", "COMMAND_EXECUTED"]  # same tick, both hosts
    status = R
    while status == R:
        clock.advance(0.1)
        status = tick(node)
    assert status == S
    commands = [h.command for h in backends.ssh.requests]  # type: ignore[attr-defined]
    assert commands == ["sudo shutdown now", "/home/pi/my_long_shutdown_sequence.sh"]


def test_shutdown_hosts_from_file_fails_if_one_host_fails_or_nothing_to_do(
        io: FakeRobotIO, clock: ManualClock, tmp_path: Path) -> None:
    hosts = write_hosts(tmp_path / "hosts.yaml", [{"ip": "192.0.2.3", "username": "husarion"},
                                                  {"ip": "192.0.2.4", "port": 3003}])
    backends = fake_backends(clock, up={"192.0.2.3": True, "192.0.2.4": True},
                             outcomes={"192.0.2.4": CommandOutcome(False, error="HTTP 403")})
    node = ShutdownHostsFromFile("hosts", make_ctx(io, clock, backends=backends),
                                 shutdown_host_file=hosts)  # the manual's spelling
    status = R
    for _ in range(50):
        status = tick(node)
        if status != R:
            break
        clock.advance(0.1)
    assert status == F and "FAILURE" in node.feedback_message
    empty = write_hosts(tmp_path / "empty.yaml", [])
    node = ShutdownHostsFromFile("none", make_ctx(io, clock, backends=backends),
                                 shutdown_hosts_file=empty)
    assert tick(node) == F and "no hosts" in node.feedback_message
    node = ShutdownHostsFromFile("missing", make_ctx(io, clock, backends=backends),
                                 shutdown_hosts_file=str(tmp_path / "nope.yaml"))
    assert tick(node) == F and "cannot read" in node.feedback_message


class PendingDispatcher:
    """Test double: jobs never finish."""

    def submit(self, fn: Any) -> Future[Any]:
        return Future()

    def close(self) -> None:
        return None


def test_execute_command(io: FakeRobotIO, clock: ManualClock) -> None:
    backends = fake_backends(clock)
    runner: FakeLocalRunner = backends.local  # type: ignore[assignment]
    node = ExecuteCommand("off", make_ctx(io, clock, backends=backends), command="sudo shutdown now")
    assert tick(node) == S and runner.commands == ["sudo shutdown now"]
    runner.outcome = CommandOutcome(False, error="permission denied")
    assert tick(node) == F and "permission denied" in node.feedback_message
    backends.dispatcher = PendingDispatcher()
    slow = ExecuteCommand("slow", make_ctx(io, clock, backends=backends), command="x", timeout=1.0)
    assert tick(slow) == R
    clock.advance(1.5)
    assert tick(slow) == F and "Timeout" in slow.feedback_message


@pytest.mark.parametrize("node_class", [ShutdownSingleHost, ShutdownHostsFromFile, ExecuteCommand])
def test_shutdown_nodes_fail_cleanly_without_backends(io: FakeRobotIO, clock: ManualClock,
                                                      node_class: Any) -> None:
    ports = {ShutdownSingleHost: host_ports(), ShutdownHostsFromFile: {"shutdown_hosts_file": "x"},
             ExecuteCommand: {"command": "true"}}[node_class]
    node = node_class("n", make_ctx(io, clock), **ports)
    assert tick(node) == F and "no shutdown backends" in node.feedback_message
