from __future__ import annotations

import threading
from pathlib import Path

import pytest

from panther_ops.core.demo.fleet import init_demo
from panther_ops.core.fleet.inventory import Inventory
from panther_ops.core.fleet.inventory_file import load_inventory
from panther_ops.core.fleet.runner import RobotContext, RunOptions, run_fleet
from panther_ops.errors import OpsError
from panther_ops.results import Outcome, RobotResult


def fleet_of(tmp: Path, n: int) -> Inventory:
    robots = "\n".join(f"  r{i:02d}: {{transport: local, root: robots/r{i:02d}}}" for i in range(n))
    (tmp / "inv.yaml").write_text(f"robots:\n{robots}\n")
    for i in range(n):
        (tmp / "robots" / f"r{i:02d}" / "home" / "husarion").mkdir(parents=True)
    return load_inventory(str(tmp / "inv.yaml"))


def test_failures_never_stop_the_others(tmp_path: Path) -> None:
    inv = fleet_of(tmp_path, 5)

    def task(ctx: RobotContext) -> RobotResult:
        if ctx.robot.name == "r01":
            raise OpsError("boom")
        if ctx.robot.name == "r02":
            raise ValueError("a bug")
        return RobotResult(ctx.robot.name, Outcome.CHANGED, "done")

    fleet = run_fleet("t", inv, list(inv.robots.values()), task, RunOptions(forks=3))
    assert [r.outcome for r in fleet.results] == [
        Outcome.CHANGED, Outcome.FAILED, Outcome.FAILED, Outcome.CHANGED, Outcome.CHANGED]
    assert fleet.results[1].message == "boom"
    assert "internal error" in fleet.results[2].message
    assert int(fleet.exit_code) == 3


def test_missing_local_robot_is_unreachable(tmp_path: Path) -> None:
    inv = fleet_of(tmp_path, 2)
    (tmp_path / "robots" / "r01" / "home" / "husarion").rmdir()
    fleet = run_fleet("t", inv, list(inv.robots.values()),
                      lambda c: RobotResult(c.robot.name, Outcome.OK, "x"))
    assert [r.outcome for r in fleet.results] == [Outcome.OK, Outcome.UNREACHABLE]


def test_parallelism_is_bounded(tmp_path: Path) -> None:
    inv = fleet_of(tmp_path, 8)
    active, peak, started = 0, 0, 0
    changed = threading.Condition()

    def task(ctx: RobotContext) -> RobotResult:
        nonlocal active, peak, started
        with changed:
            active += 1
            started += 1
            peak = max(peak, active)
            changed.notify_all()
            # hold the slot until 3 ran at once (or every task started): parallel, and no more
            assert changed.wait_for(lambda: peak >= 3 or started == 8, timeout=10)
            active -= 1
        return RobotResult(ctx.robot.name, Outcome.OK, "x")

    fleet = run_fleet("t", inv, list(inv.robots.values()), task, RunOptions(forks=3))
    assert [r.outcome for r in fleet.results] == [Outcome.OK] * 8
    assert peak == 3


def test_canary_failure_skips_the_rest(tmp_path: Path) -> None:
    inv = fleet_of(tmp_path, 5)
    seen: list[str] = []

    def task(ctx: RobotContext) -> RobotResult:
        seen.append(ctx.robot.name)
        bad = ctx.robot.name == "r01"
        return RobotResult(ctx.robot.name, Outcome.FAILED if bad else Outcome.OK, "x")

    fleet = run_fleet("t", inv, list(inv.robots.values()), task, RunOptions(forks=5, canary=2))
    assert sorted(seen) == ["r00", "r01"]
    assert [r.outcome for r in fleet.results[2:]] == [Outcome.SKIPPED] * 3
    assert "canary r01" in fleet.results[2].message
    assert fleet.notes


def test_max_fail_stops_starting_robots(tmp_path: Path) -> None:
    inv = fleet_of(tmp_path, 10)
    fleet = run_fleet("t", inv, list(inv.robots.values()),
                      lambda c: RobotResult(c.robot.name, Outcome.FAILED, "x"),
                      RunOptions(forks=1, max_fail_pct=20))
    outcomes = [r.outcome for r in fleet.results]
    assert outcomes.count(Outcome.FAILED) == 3  # budget 2 of 10; the third failure stops it
    assert outcomes[3:] == [Outcome.SKIPPED] * 7


def test_demo_fleet_status(tmp_path: Path) -> None:
    from panther_ops.core.health.status import status_task

    inv = load_inventory(str(init_demo(tmp_path / "demo")))
    fleet = run_fleet("status", inv, list(inv.robots.values()), status_task)
    assert [r.outcome for r in fleet.results] == [Outcome.OK] * 4
    by = {r.robot: r.data for r in fleet.results}
    assert by["panther-01"]["stack_version"] == "2.1.1"
    assert by["panther-02"]["stack_version"] == "2.0.4"
    assert by["panther-03"]["stack"] == "husarion_ugv"
    assert by["panther-03"]["robot_serial"] == "PTH0203"
    assert by["panther-01"]["hostname"] == "panther-01"
    assert by["panther-01"]["containers"] is None
    assert "no docker engine" in by["panther-01"]["docker_skipped"]
    assert abs(by["panther-01"]["clock_offset_s"]) < 1


def test_demo_refuses_to_overwrite(tmp_path: Path) -> None:
    init_demo(tmp_path / "d")
    with pytest.raises(OpsError, match="already exists"):
        init_demo(tmp_path / "d")
    init_demo(tmp_path / "d", force=True)


def test_an_interrupt_stops_the_run_at_once_and_names_where_each_robot_was(tmp_path: Path) -> None:
    """A Ctrl-C (SIGINT to this process, raised in the main thread) while one robot's task hangs:
    run_fleet raises FleetInterrupted at once, without waiting for the hanging worker; robots not
    yet started never start, and the hanging worker stops at its next phase."""
    import os
    import signal
    import time

    from panther_ops.core.fleet.interrupt import FleetInterrupted

    inv = fleet_of(tmp_path, 4)
    release, hanging = threading.Event(), threading.Event()
    after: list[str] = []

    def task(ctx: RobotContext) -> RobotResult:
        if ctx.robot.name == "r01":
            ctx.phase("write")
            hanging.set()
            release.wait(10)
            ctx.phase("verify")  # interrupted meanwhile: stops here
            after.append(ctx.robot.name)
        if ctx.robot.name == "r02":
            ctx.phase("plan")
            release.wait(10)
        return RobotResult(ctx.robot.name, Outcome.CHANGED, "done")

    def ctrl_c() -> None:
        hanging.wait(10)
        time.sleep(0.2)  # r00 is done by now, r02 hangs too, r03 waits for a fork
        os.kill(os.getpid(), signal.SIGINT)

    # Python's own Ctrl-C handler, as on a terminal: a process started in the background by a
    # non-interactive shell (a CI script's `cmd &`) inherits SIGINT ignored, and Python keeps that
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        threading.Thread(target=ctrl_c, daemon=True).start()
        start = time.monotonic()
        with pytest.raises(FleetInterrupted) as caught:
            run_fleet("t", inv, list(inv.robots.values()), task, RunOptions(forks=2))
        took = time.monotonic() - start
    finally:
        signal.signal(signal.SIGINT, previous)
    release.set()
    where = caught.value.where
    assert took < 0.2 + 0.5 + 1.0, took  # the hanging task alone would take 10 s
    assert [r.robot for r in where.finished] == ["r00"] and where.running == {"r01": "write", "r02": "plan"}
    assert where.not_started == ["r03"]
    assert int(caught.value.exit_code) == 130
    text = str(caught.value)
    assert "finished: r00 changed" in text and "being written: r01" in text and "cut short: r02 (plan)" in text
    assert "not started: r03" in text
    assert "old or its new content" in text
    time.sleep(0.2)
    assert after == []  # the worker went no further than its next phase
