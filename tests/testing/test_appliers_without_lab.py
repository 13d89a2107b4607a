"""Appliers tested end to end on a fake robot (panther_ops.testing.FakeTransport), no lab:
read (a plain run) -> pure plan -> write session: stage with backup -> go-ahead -> compare-and-rename.

Each test drives the same functions the CLI calls (``read_and_plan_*`` then the applier) and
checks the robot's files, its backup and what the robot was asked, byte for byte."""

from __future__ import annotations

import json
from collections.abc import Callable

from panther_ops.core.config.read import read_and_plan_args
from panther_ops.core.fleet.history import list_history, read_backup
from panther_ops.core.fleet.pipeline import BACKUP_ROOT, ApplyOptions, apply_plan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.gps.apply import apply_gps
from panther_ops.core.gps.plan import GpsOptions
from panther_ops.core.gps.read import read_and_plan_disable, read_and_plan_enable
from panther_ops.results import Outcome
from panther_ops.transport import scripts, scripts_apply
from tests.testing.conftest import fake_of

COMPOSE = "/home/husarion/compose.yaml"
Make = Callable[..., RobotContext]


def backups(ctx: RobotContext) -> dict[str, bytes]:
    return {p: d for p, d in fake_of(ctx).tree().items() if "/.panther-ops/backups/" in p}


def test_config_set_writes_the_argument_and_keeps_a_backup(fake_ctx: Make) -> None:
    ctx = fake_ctx("panther-01")
    robot = fake_of(ctx)
    before = robot.get(COMPOSE)
    assert before is not None and b"wheel_type" not in before

    plan = read_and_plan_args(ctx, {"publish_robot_state": False}, [])
    result = apply_plan(ctx, plan, ApplyOptions(command="config set publish_robot_state=False"))

    assert result.outcome is Outcome.CHANGED, result.message
    after = robot.get(COMPOSE)
    assert after is not None and b"publish_robot_state:=False" in after
    assert [d.path for d in plan.diffs] == [COMPOSE]
    # no docker engine on the fake robot: nothing recreated, said so
    assert any("no docker engine" in w for w in result.warnings)
    # the backup: the old bytes by edit index, the manifest, the status
    bid = result.data["backup"]
    wdir = f"/home/husarion/.panther-ops/backups/{bid}"
    files = backups(ctx)
    assert files[f"{wdir}/files/0"] == before
    manifest = json.loads(files[f"{wdir}/manifest.json"])
    assert manifest["command"] == "config set publish_robot_state=False"
    assert manifest["files"][0]["path"] == COMPOSE
    assert files[f"{wdir}/status"] == b"applied\n"
    assert not [p for p in robot.tree() if ".panther-ops." in p], "no staged file left"
    # one plain read, then one write session (its arguments on its input, none on the command line)
    assert [c.script for c in robot.calls][:2] == [scripts.READ_WITH_HOME, scripts_apply.APPLY]
    assert robot.calls[1].argv == ()
    # history reads the backup back through the same fake
    (entry,) = [b for b in list_history(ctx) if b["id"] == bid]
    assert entry["summary"] == plan.summary and entry["status"] == files[f"{wdir}/status"].decode().strip()
    assert read_backup(ctx, f"{bid}/files/0") == before


def test_config_set_refused_when_the_file_changed_since_it_was_read(fake_ctx: Make) -> None:
    ctx = fake_ctx("panther-01")
    robot = fake_of(ctx)
    plan = read_and_plan_args(ctx, {"publish_robot_state": False}, [])
    theirs = (robot.get(COMPOSE) or b"") + b"# another operator\n"

    def meanwhile(name: str) -> None:  # between staging and the go-ahead
        robot.put(COMPOSE, theirs)

    result = apply_plan(ctx, plan, ApplyOptions(on_staged=meanwhile))
    assert result.outcome is Outcome.FAILED
    assert result.message.startswith(f"{COMPOSE} changed on the robot since it was read; nothing written")
    assert robot.get(COMPOSE) == theirs, "their write stays"
    assert backups(ctx) == {}, "nothing left behind: backup and staged files removed"
    assert not [p for p in robot.tree() if ".panther-ops." in p]


def test_config_set_refused_by_the_robots_compose(fake_ctx: Make) -> None:
    ctx = fake_ctx("panther-01", compose_check=lambda data: "services.x: additional property y")
    robot = fake_of(ctx)
    before = robot.tree(backups=False)
    plan = read_and_plan_args(ctx, {"publish_robot_state": False}, [])
    # a value-only edit is not asked (pipeline._values_only); a new service key is
    plan.edits[0] = plan.edits[0].__class__(plan.edits[0].path, plan.edits[0].before,
                                            (plan.edits[0].after or b"") + b"x: {}\n", plan.edits[0].mode)
    result = apply_plan(ctx, plan, ApplyOptions())
    assert result.outcome is Outcome.FAILED
    assert "docker compose refuses" in result.message and "additional property y" in result.message
    assert robot.tree(backups=False) == before
    (status,) = [d for p, d in backups(ctx).items() if p.endswith("/status")]
    assert status == b"refused: services.x: additional property y\n"


def test_gps_enable_then_disable_on_2_0_restores_the_bytes(fake_ctx: Make) -> None:
    ctx = fake_ctx("panther-02")  # panther_ros 2.0.4: the manual's nmea-gps service
    robot = fake_of(ctx)
    before = robot.tree(backups=False)

    plan = read_and_plan_enable(ctx, GpsOptions())
    result = apply_gps(ctx, plan, ApplyOptions(command="gps enable"))
    assert result.outcome is Outcome.CHANGED, result.message
    compose = (robot.get(COMPOSE) or b"").decode()
    assert "  nmea-gps:\n    image: husarion/nmea-gps:humble-2.0.1-20240617\n" in compose
    assert "robot_namespace:=panther" in compose

    again = read_and_plan_enable(ctx, GpsOptions())
    assert not again.edits and "already" in (again.noop or "")

    plan = read_and_plan_disable(ctx)
    assert plan.data.get("remove_service") == "nmea-gps"
    result = apply_gps(ctx, plan, ApplyOptions(command="gps disable"))
    assert result.outcome is Outcome.CHANGED, result.message
    assert robot.tree(backups=False) == before, "disable gives back the bytes enable changed"
    assert any("container was not removed" in w for w in result.warnings), "no engine: said, not hidden"
    assert len({p.split("/")[5] for p in backups(ctx)}) == 2, "one backup per write"


def test_gps_enable_dry_run_writes_nothing(fake_ctx: Make) -> None:
    ctx = fake_ctx("panther-03")  # husarion_ugv 2.2.2: the launch argument
    robot = fake_of(ctx)
    before = robot.tree()
    plan = read_and_plan_enable(ctx, GpsOptions())
    result = apply_gps(ctx, plan, ApplyOptions(dry_run=True))
    assert result.outcome is Outcome.CHANGED and result.data["dry_run"] is True
    assert "launch_nmea_gps:=true" in plan.diffs[0].unified
    ctx.transport.close()
    assert robot.tree() == before
    assert f"{BACKUP_ROOT}" not in json.dumps(list(robot.tree()))
