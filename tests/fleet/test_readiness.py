"""The readiness decision after a recreate (core/fleet/readiness.py): a pure function of
``docker inspect`` samples, and the watch that stops as soon as every service is ready."""

from __future__ import annotations

from typing import Any

from panther_ops.core.fleet import readiness
from panther_ops.core.fleet.pipeline import watch_services
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.readiness import FAILED, MIN_STABLE_S, READY, WAIT, Sample, judge, sample_of
from panther_ops.core.fleet.services import WORKING_DIR_LABEL

T0 = "2026-11-27T08:00:00.1Z"


def up(at: float, started: str = T0, **kw: Any) -> Sample:
    return Sample(at, "running", started_at=started, **kw)


def test_running_unrestarted_over_the_window_is_ready_and_not_before() -> None:
    assert judge([]) == (WAIT, "")
    assert judge([up(0.0), up(MIN_STABLE_S - 0.1)]) == (WAIT, "")
    assert judge([up(0.0), up(1.0), up(MIN_STABLE_S)]) == (READY, "")
    # the window runs from the first look that saw it running, not from the first look
    assert judge([Sample(0.0, "created"), up(1.0), up(1.0 + MIN_STABLE_S - 0.1)]) == (WAIT, "")
    assert judge([Sample(0.0, "created"), up(1.0), up(1.0 + MIN_STABLE_S)]) == (READY, "")
    assert judge([up(0.0), up(0.5)], min_stable_s=0.5) == (READY, "")


def test_a_crash_fails_whatever_the_window() -> None:
    exited = Sample(1.0, "exited", exit_code=1, started_at=T0)
    assert judge([up(0.0), exited]) == (FAILED, "container exited (exit code 1) after recreate")
    restarting = Sample(1.0, "restarting", restarting=True, exit_code=1, started_at=T0)
    assert judge([up(0.0), restarting])[0] == FAILED
    # restart: always brought it back between two looks: the count, or a new StartedAt, tells
    # (docker sets a container's ExitCode to 0 when it starts it again: a running look's says nothing)
    gone = "running again: its exit code is gone once docker starts it; `driver logs` shows why it stopped"
    assert judge([up(0.0), up(5.0, restart_count=1, exit_code=0)]) == (
        FAILED, f"container restarted 1 time(s) after recreate ({gone})")
    assert judge([up(0.0), up(5.0, started="2026-11-27T08:00:01.3Z", exit_code=0)]) == (
        FAILED, f"container started again after recreate ({gone})")
    # a look between two starts saw the crash's code: that one is named
    crashed = Sample(1.0, "restarting", restarting=True, restart_count=1, exit_code=1, started_at=T0)
    assert judge([up(0.0), crashed, up(2.0, restart_count=1, exit_code=0)]) == (
        FAILED, "container restarted 1 time(s) after recreate (exit code 1)")


def test_a_healthcheck_where_the_compose_has_one() -> None:
    assert judge([up(0.0, health="starting"), up(10.0, health="starting")]) == (WAIT, "")
    assert judge([up(0.0, health="healthy")]) == (READY, "")
    assert judge([up(0.0, health="unhealthy")]) == (FAILED, "container unhealthy after recreate")


def test_sample_of_reads_docker_inspect() -> None:
    attrs = {"RestartCount": 2, "State": {"Status": "running", "Running": True, "Restarting": False,
                                          "ExitCode": 0, "StartedAt": T0, "Health": {"Status": "healthy"}}}
    assert sample_of(attrs, 1.5) == Sample(1.5, "running", False, 2, T0, 0, "healthy")
    assert sample_of({"State": {"Status": "running"}}, 0.0).health is None


class _Engine:
    """docker-py's containers.list over a script of inspect documents (one per look): the
    engine's edge, as test_gamepad's client."""

    def __init__(self, states: list[dict[str, Any]]) -> None:
        self.containers, self.states, self.looks = self, states, 0

    def list(self, **_: object) -> list[Any]:
        state = self.states[min(self.looks, len(self.states) - 1)]
        self.looks += 1
        return [type("C", (), {"attrs": {"Config": {"Cmd": ["ros2", "launch"], "Labels": {WORKING_DIR_LABEL: "/home/husarion"}},
                                         "RestartCount": state.pop("n", 0), "State": state}})()]


def test_the_watch_ends_when_ready_and_fails_on_a_late_crash(monkeypatch: Any) -> None:
    monkeypatch.setattr(readiness, "MIN_STABLE_S", 0.2)
    monkeypatch.setattr(readiness, "POLL_S", 0.05)
    plan = RobotPlan("r01", "x", [], ("panther_ros",))
    engine = _Engine([{"Status": "running", "StartedAt": T0}])
    assert watch_services(engine, plan, 30.0, "/home/husarion") is None
    assert 4 <= engine.looks <= 8  # ended at the window, not at --settle (30 s)
    crash = [{"Status": "running", "StartedAt": T0}] * 2 + [{"Status": "running", "StartedAt": T0, "n": 1,
                                                               "ExitCode": 0}]  # started again between looks
    assert watch_services(_Engine([dict(s) for s in crash]), plan, 30.0, "/home/husarion") == (
        "service panther_ros: container restarted 1 time(s) after recreate (running again: its exit code is "
        "gone once docker starts it; `driver logs` shows why it stopped)")
