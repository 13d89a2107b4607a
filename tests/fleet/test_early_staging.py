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
        assert fp.staged[r.name].session.wait_staged() is None, "staging only sent: the robot answers later"
        assert [p.name.split(".panther-ops.")[0] for p in staged_files(inv, r.name)] == [".compose.yaml"]
        assert (home(inv, r.name) / "compose.yaml").read_bytes() == before[r.name]
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
    assert len(fp.staged) == len(robots) - 1
    assert all(st.session.wait_staged() is None and staged_files(inv, n) for n, st in fp.staged.items())

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


# -- planning never commits; each session opened beside its read ----------------------------


def test_planning_renames_nothing_even_when_every_robot_runs_at_once(
        demo_connections: tuple[Inventory, Connections]) -> None:
    inv, conns = demo_connections
    robots = list(inv.robots.values())
    fp = plan_fleet("t", inv, robots, plan, conns, RunOptions(forks=len(robots)), stage=OPTS)
    for r in robots:
        assert fp.staged[r.name].session.wait_staged() is None, "staged, waiting for the go-ahead"
    assert not any(b"wheel_type:=WH04" in (home(inv, r.name) / "compose.yaml").read_bytes() for r in robots)
    result = apply_fleet(fp, inv, robots, conns, RunOptions(forks=len(robots)), OPTS)
    assert [x.outcome for x in result.results] == [Outcome.CHANGED] * len(robots)


def test_each_robot_opens_its_session_to_make_its_read(demo_connections: tuple[Inventory, Connections],
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    """The write session is opened when planning starts and reads the compose file for the
    plan (no read of its own: one command per robot); a robot with nothing to write closes it
    unused."""
    from panther_ops.transport import scripts

    inv, conns = demo_connections
    robots = list(inv.robots.values())
    order: dict[str, list[str]] = {r.name: [] for r in robots}
    for r in robots:
        t = conns.get(r)
        session, run = t.session, t.run

        def spy_session(_s=session, _n=r.name, **kw: object) -> object:  # type: ignore[no-untyped-def]
            order[_n].append(f"session reading {kw['read']}" if kw.get("read") else "session")
            return _s(**kw)

        def spy_run(command: object, _r=run, _n=r.name, **kw: object) -> object:  # type: ignore[no-untyped-def]
            if getattr(command, "script", None) == scripts.READ_WITH_HOME:
                order[_n].append("read")
            return _r(command, **kw)

        monkeypatch.setattr(t, "session", spy_session)
        monkeypatch.setattr(t, "run", spy_run)
    fp = plan_fleet("t", inv, robots, plan, conns, RunOptions(), stage=OPTS)
    assert order == {r.name: [f"session reading {r.compose_file}"] for r in robots}
    unstage_fleet(fp, inv, robots, conns, RunOptions())
    again = plan_fleet("t", inv, robots, lambda ctx: RobotPlan(ctx.robot.name, "nothing", [], noop="so"), conns,
                       RunOptions(), stage=OPTS)
    assert again.staged == {} and all(not staged_files(inv, r.name) for r in robots)


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
    fp = plan_fleet("t", inv, robots, plan, conns, RunOptions(forks=len(robots)), stage=OPTS)
    assert sorted(fp.staged) == sorted(r.name for r in robots[1:])
    assert fp.results.results[0].outcome is Outcome.UNREACHABLE
    unstage_fleet(fp, inv, robots, conns, RunOptions())
