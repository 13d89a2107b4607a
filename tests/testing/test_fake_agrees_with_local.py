"""FakeTransport and the demo fleet's LocalTransport (which runs the real robot scripts in a
shell on a directory) agree: the same scenario on the same files gives the same results, the
same files with the same modes, the same backups and the same history.

This is what makes the fake faithful: a rule of the real write session (backup, staged files,
compare-and-rename under the write lock, stop, abandon, refusal of a changed file) that the
fake got wrong shows up here as a difference."""

from __future__ import annotations

import json
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from panther_ops.core.config.read import read_and_plan_args
from panther_ops.core.fleet.history import list_history
from panther_ops.core.fleet.inventory import Inventory
from panther_ops.core.fleet.pipeline import ApplyOptions, apply_plan, stage_plan, unstage
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.gps.apply import apply_gps
from panther_ops.core.gps.plan import GpsOptions
from panther_ops.core.gps.read import read_and_plan_enable
from panther_ops.errors import RemoteStateError
from panther_ops.testing import FakeRobot, FakeTransport
from panther_ops.transport.local import LocalTransport

COMPOSE = "/home/husarion/compose.yaml"
Tree = dict[str, tuple[bytes, int]]


def local_tree(root: Path) -> Tree:
    return {"/" + p.relative_to(root).as_posix(): (p.read_bytes(), p.stat().st_mode & 0o7777)
            for p in sorted(root.rglob("*")) if p.is_file()}


def fake_tree(robot: FakeRobot) -> Tree:
    return {p: (f.data, f.mode) for p, f in sorted(robot.files.items())}


def put_local(root: Path, path: str, data: bytes) -> None:
    (root / path.lstrip("/")).write_bytes(data)


def normalized(tree: Tree) -> Tree:
    """Backup ids (a time and a random part) as ``<id>``; a manifest without its creation time."""
    out: Tree = {}
    for path, (data, mode) in tree.items():
        key = re.sub(r"/backups/[0-9TZ]+-[0-9a-f]{4}", "/backups/<id>", path)
        content = data
        if key.endswith("/manifest.json"):
            doc = json.loads(data)
            doc.pop("created", None)
            doc["id"] = re.sub(r"^[0-9TZ]+-[0-9a-f]{4}", "<id>", doc["id"])
            content = json.dumps(doc, sort_keys=True).encode()
        out[key] = (content, mode)
    return out


Scenario = Callable[[RobotContext, Callable[[str, bytes], None]], dict[str, Any]]


def config_set(ctx: RobotContext, put: Callable[[str, bytes], None]) -> dict[str, Any]:
    plan = read_and_plan_args(ctx, {"publish_robot_state": False}, [])
    res = apply_plan(ctx, plan, ApplyOptions(command="config set"))
    return {"outcome": res.outcome, "message": res.message, "warnings": res.warnings,
            "history": [(h["summary"], h["status"]) for h in list_history(ctx)]}


def changed_meanwhile(ctx: RobotContext, put: Callable[[str, bytes], None]) -> dict[str, Any]:
    plan = read_and_plan_args(ctx, {"publish_robot_state": False}, [])
    edit = plan.edits[0]
    res = apply_plan(ctx, plan, ApplyOptions(on_staged=lambda _: put(COMPOSE, (edit.before or b"") + b"# theirs\n")))
    return {"outcome": res.outcome, "message": res.message, "history": list_history(ctx)}


def stopped(ctx: RobotContext, put: Callable[[str, bytes], None]) -> dict[str, Any]:
    plan = read_and_plan_args(ctx, {"publish_robot_state": False}, [])
    staged = stage_plan(ctx, plan, ApplyOptions())
    unstage(staged)
    res = staged.session.stop()  # ended: the same result again
    return {"exit": res.exit_status, "ended": staged.session.ended}


def abandoned(ctx: RobotContext, put: Callable[[str, bytes], None]) -> dict[str, Any]:
    plan = read_and_plan_args(ctx, {"publish_robot_state": False}, [])
    staged = stage_plan(ctx, plan, ApplyOptions(command="lost"))
    staged.session.wait_staged()
    staged.session.close()  # the connection went away before the go-ahead
    return {"history": [(h["command"], h["status"]) for h in list_history(ctx)]}


def gps_enable_twice(ctx: RobotContext, put: Callable[[str, bytes], None]) -> dict[str, Any]:
    first = apply_gps(ctx, read_and_plan_enable(ctx, GpsOptions()), ApplyOptions())
    second = read_and_plan_enable(ctx, GpsOptions())
    return {"first": (first.outcome, first.message), "second": (second.noop, len(second.edits))}


def no_compose(ctx: RobotContext, put: Callable[[str, bytes], None]) -> dict[str, Any]:
    with pytest.raises(RemoteStateError) as exc:
        read_and_plan_args(ctx, {"publish_robot_state": False}, [])
    return {"error": exc.value.message}


@pytest.mark.parametrize("scenario", [config_set, changed_meanwhile, stopped, abandoned, gps_enable_twice, no_compose])
@pytest.mark.parametrize("name", ["panther-01", "panther-02"])
def test_fake_and_local_agree(demo: Inventory, name: str, scenario: Scenario) -> None:
    robot = demo.robots[name]
    assert robot.root is not None
    root = robot.root
    if scenario is no_compose:
        (root / COMPOSE.lstrip("/")).unlink()
    fake = FakeRobot.from_directory(root)
    assert normalized(fake_tree(fake)) == normalized(local_tree(root))

    local_t = LocalTransport(robot.name, root)
    fake_t = FakeTransport(fake, robot.name)
    try:
        got_local = scenario(RobotContext(robot, local_t, demo), lambda p, d: put_local(root, p, d))
        got_fake = scenario(RobotContext(robot, fake_t, demo), fake.put)
    finally:
        local_t.close()
        fake_t.close()

    def plain(doc: dict[str, Any]) -> str:
        return re.sub(r"[0-9]{8}T[0-9]{6}Z-[0-9a-f]{4}", "<id>", json.dumps(doc, default=str, sort_keys=True))

    assert plain(got_fake) == plain(got_local)
    assert normalized(fake_tree(fake)) == normalized(local_tree(root))
