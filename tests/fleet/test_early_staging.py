"""Writes staged while the fleet is still being planned (``--yes``), renamed only on the go-ahead.

Runs the real write scripts through the demo fleet's transport (local robot roots); see
core/changes.py for the design.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from panther_ops.cli.app import main
from panther_ops.core.config.read import read_and_plan_args
from panther_ops.core.fleet.changes import apply_fleet, plan_fleet, unstage_fleet
from panther_ops.core.fleet.inventory import Inventory
from panther_ops.core.fleet.pipeline import ApplyOptions
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import Connections, RobotContext, RunOptions
from panther_ops.errors import UsageError
from panther_ops.results import Outcome

OPTS = ApplyOptions(restart=False, command="config set wheel_type WH04")


def home(inv: Inventory, name: str) -> Path:
    root = inv.robots[name].root
    assert root is not None
    return root / "home" / "husarion"


def snapshot(inv: Inventory) -> dict[str, bytes]:
    """Every file of every robot (backups and temp files included)."""
    out = {}
    for name in inv.robots:
        base = home(inv, name)
        out.update({f"{name}/{p.relative_to(base)}": p.read_bytes() for p in base.rglob("*") if p.is_file()})
    return out


def staged_files(inv: Inventory, name: str) -> list[Path]:
    return sorted(p for p in home(inv, name).rglob("*") if ".panther-ops." in p.name)


def plan(ctx: RobotContext) -> RobotPlan:
    return read_and_plan_args(ctx, {"wheel_type": "WH04"}, [])


def test_staged_while_planning_renamed_on_the_go_ahead(demo_connections: tuple[Inventory, Connections]) -> None:
    inv, conns = demo_connections
    robots = list(inv.robots.values())
    before = {r.name: (home(inv, r.name) / "compose.yaml").read_bytes() for r in robots}

    fp = plan_fleet("t", inv, robots, plan, conns, RunOptions(), stage=OPTS)

    assert sorted(fp.staged) == sorted(fp.to_change) == sorted(before)
    for r in robots:  # staged beside its target, backup written, target untouched
        assert [p.name.split(".panther-ops.")[0] for p in staged_files(inv, r.name)] == [".compose.yaml"]
        assert (home(inv, r.name) / "compose.yaml").read_bytes() == before[r.name]
        assert conns.get(r).kept("write")
    result = apply_fleet(fp, inv, robots, conns, RunOptions(), OPTS)
    assert [x.outcome for x in result.results] == [Outcome.CHANGED] * len(robots), [x.message for x in result.results]
    for r in robots:
        assert b"wheel_type:=WH04" in (home(inv, r.name) / "compose.yaml").read_bytes()
        assert staged_files(inv, r.name) == []
        [backup] = (home(inv, r.name) / ".panther-ops" / "backups").iterdir()
        assert (backup / "status").read_text() == "applied (not recreated)\n"
        assert (backup / "files" / "0").read_bytes() == before[r.name]
    assert fp.staged == {}


def test_a_refused_plan_elsewhere_takes_every_staging_back(demo_connections: tuple[Inventory, Connections]) -> None:
    inv, conns = demo_connections
    robots = list(inv.robots.values())
    before = snapshot(inv)

    def planner(ctx: RobotContext) -> RobotPlan:
        if ctx.robot.name == robots[-1].name:
            raise UsageError("not on this robot's stack")
        return plan(ctx)

    fp = plan_fleet("t", inv, robots, planner, conns, RunOptions(), stage=OPTS)
    assert list(fp.usage_errors) == [robots[-1].name]
    assert len(fp.staged) == len(robots) - 1 and all(staged_files(inv, n) for n in fp.staged)

    unstage_fleet(fp, inv, robots, conns, RunOptions())

    assert fp.staged == {}
    assert snapshot(inv) == before, "every robot exactly as it was: no temp file, no backup"
    assert all(not (home(inv, r.name) / ".panther-ops").exists() for r in robots)


def test_a_failed_canary_takes_back_the_rest(demo_connections: tuple[Inventory, Connections]) -> None:
    inv, conns = demo_connections
    robots = list(inv.robots.values())
    canary = robots[0].name
    fp = plan_fleet("t", inv, robots, plan, conns, RunOptions(), stage=OPTS)
    compose = home(inv, canary) / "compose.yaml"
    compose.write_bytes(compose.read_bytes() + b"# edited on the robot meanwhile\n")
    before = snapshot(inv)

    result = apply_fleet(fp, inv, robots, conns, RunOptions(canary=1), OPTS)

    by = {x.robot: x for x in result.results}
    assert by[canary].outcome is Outcome.FAILED and "changed on the robot" in by[canary].message
    assert all(by[r.name].outcome is Outcome.SKIPPED for r in robots[1:])
    after = snapshot(inv)
    assert after.pop(f"{canary}/.panther-ops/write.lock") == b"", "the canary's check took the robot's write lock"
    assert after == {k: v for k, v in before.items() if ".panther-ops" not in k}, (
        "the canary's check failed after its go-ahead, the rest never got one: all staging gone")
    assert fp.staged == {}


def test_the_cli_stages_early_only_when_it_asks_nothing(demo_connections: tuple[Inventory, Connections],
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    inv, _ = demo_connections
    import panther_ops.core.fleet.changes as changes

    seen: list[object] = []
    real = changes.plan_fleet

    def spy(*args: object, **kw: object) -> object:
        seen.append(kw.get("stage"))
        return real(*args, **kw)  # type: ignore[arg-type]

    monkeypatch.setattr(changes, "plan_fleet", spy)
    base = ["-i", str(inv.path), "config", "set", "wheel_type", "WH04", "--all", "--no-restart"]
    assert main([*base, "--dry-run"]) == 0
    assert main([*base, "--yes"]) == 0
    assert seen[0] is None and isinstance(seen[1], ApplyOptions)
    assert all(b"wheel_type:=WH04" in (home(inv, n) / "compose.yaml").read_bytes() for n in inv.robots)
    assert all(staged_files(inv, n) == [] for n in inv.robots)


# -- going ahead as soon as every plan is known (go_early) ---------------------------------


def test_every_robot_goes_ahead_once_every_plan_is_known(demo_connections: tuple[Inventory, Connections]) -> None:
    inv, conns = demo_connections
    robots = list(inv.robots.values())
    planned: list[str] = []
    renamed_before_last_plan: list[str] = []

    def planner(ctx: RobotContext) -> RobotPlan:
        p = plan(ctx)
        planned.append(ctx.robot.name)
        if len(planned) == len(robots):  # the last plan: nobody may have gone ahead yet
            renamed_before_last_plan.extend(
                n for n in inv.robots if b"wheel_type:=WH04" in (home(inv, n) / "compose.yaml").read_bytes())
        return p

    fp = plan_fleet("t", inv, robots, planner, conns, RunOptions(forks=len(robots)), stage=OPTS, go_early=True)
    assert renamed_before_last_plan == []
    assert sorted(fp.applied) == sorted(r.name for r in robots) and fp.staged == {}
    assert all(b"wheel_type:=WH04" in (home(inv, r.name) / "compose.yaml").read_bytes() for r in robots), (
        "written during phase 1")
    result = apply_fleet(fp, inv, robots, conns, RunOptions(forks=len(robots)), OPTS)
    assert [x.outcome for x in result.results] == [Outcome.CHANGED] * len(robots)
    assert fp.applied == {}
    for r in robots:
        [backup] = (home(inv, r.name) / ".panther-ops" / "backups").iterdir()
        assert (backup / "status").read_text() == "applied (not recreated)\n"


def test_a_refused_plan_stops_every_early_go_ahead(demo_connections: tuple[Inventory, Connections]) -> None:
    inv, conns = demo_connections
    robots = list(inv.robots.values())
    before = snapshot(inv)

    def planner(ctx: RobotContext) -> RobotPlan:
        if ctx.robot.name == robots[1].name:
            raise UsageError("not on this robot's stack")
        return plan(ctx)

    fp = plan_fleet("t", inv, robots, planner, conns, RunOptions(forks=len(robots)), stage=OPTS, go_early=True)
    assert fp.applied == {} and fp.staged == {}, "nothing staged: every robot waited for every plan"
    assert snapshot(inv) == before
    unstage_fleet(fp, inv, robots, conns, RunOptions())
    assert snapshot(inv) == before


def test_the_go_ahead_rides_with_the_staging(demo_connections: tuple[Inventory, Connections],
                                             monkeypatch: pytest.MonkeyPatch) -> None:
    """Going ahead early, each robot's go-ahead is sent behind its staging, in the same input:
    what remains of the write is its end (no second message, one round trip fewer)."""
    from panther_ops.transport import scripts_apply

    inv, conns = demo_connections
    robots = list(inv.robots.values())
    sent: list[tuple[str, bytes]] = []
    for r in robots:
        t = conns.get(r)
        advance, resume = t.advance, t.resume

        def spy_advance(key: str, stdin: bytes, until: bytes, _a=advance, _n=r.name) -> object:  # type: ignore[no-untyped-def]
            sent.append((_n, stdin[-len(scripts_apply.GO):]))
            return _a(key, stdin, until)

        def spy_resume(key: str, stdin: bytes, _r=resume, _n=r.name, **kw: object) -> object:  # type: ignore[no-untyped-def]
            sent.append((_n, stdin))
            return _r(key, stdin, **kw)

        monkeypatch.setattr(t, "advance", spy_advance)
        monkeypatch.setattr(t, "resume", spy_resume)
    fp = plan_fleet("t", inv, robots, plan, conns, RunOptions(forks=len(robots)), stage=OPTS, go_early=True)
    assert sorted(fp.applied) == sorted(r.name for r in robots)
    assert [x.outcome for x in fp.applied.values()] == [Outcome.CHANGED] * len(robots)
    assert sorted(sent) == sorted([(r.name, scripts_apply.GO) for r in robots] + [(r.name, b"") for r in robots])


def test_an_unreachable_robot_does_not_hold_the_others(demo_connections: tuple[Inventory, Connections],
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    from panther_ops.errors import UnreachableError

    inv, conns = demo_connections
    robots = list(inv.robots.values())
    get = conns.get

    def flaky(robot: object) -> object:
        if getattr(robot, "name", None) == robots[0].name:
            raise UnreachableError(robots[0].name, "no route to host")
        return get(robot)  # type: ignore[arg-type]

    monkeypatch.setattr(conns, "get", flaky)
    fp = plan_fleet("t", inv, robots, plan, conns, RunOptions(forks=len(robots)), stage=OPTS, go_early=True)
    assert sorted(fp.applied) == sorted(r.name for r in robots[1:])
    assert fp.results.results[0].outcome is Outcome.UNREACHABLE


@pytest.mark.parametrize("opts", [RunOptions(forks=1), RunOptions(canary=1), RunOptions(max_fail_pct=50.0)])
def test_no_early_go_ahead_unless_every_robot_runs_at_once(demo_connections: tuple[Inventory, Connections],
                                                           opts: RunOptions) -> None:
    inv, conns = demo_connections
    robots = list(inv.robots.values())
    fp = plan_fleet("t", inv, robots, plan, conns, opts, stage=OPTS, go_early=True)
    assert fp.applied == {} and sorted(fp.staged) == sorted(r.name for r in robots)
    assert not any(b"wheel_type:=WH04" in (home(inv, r.name) / "compose.yaml").read_bytes() for r in robots)
    unstage_fleet(fp, inv, robots, conns, RunOptions())
