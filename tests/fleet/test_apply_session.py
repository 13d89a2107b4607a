"""The write step as one shell session (scripts_apply.APPLY): check, back up, stage, then rename on
the go-ahead.

The script runs for real through the demo transport (LocalTransport's write session) on a
temp robot root; the command line and input are the ones pipeline.apply_plan builds, so these
tests hold whatever the argument layout. The robot's answer can be replaced (``stop``, or the
input just closing as when the connection dies) to exercise the paths the pipeline never takes
on its own.
"""

from __future__ import annotations

import hashlib
import json
import stat
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from panther_ops.core.config.read import read_and_plan_args
from panther_ops.core.fleet.inventory import Inventory
from panther_ops.core.fleet.inventory_file import load_inventory
from panther_ops.core.fleet.pipeline import ApplyOptions, apply_plan
from panther_ops.core.fleet.plan import FileEdit, RobotPlan
from panther_ops.core.fleet.runner import Connections, RobotContext
from panther_ops.errors import TransportError
from panther_ops.results import Outcome, RobotResult
from panther_ops.transport import scripts_apply
from panther_ops.transport.base import Command, CommandResult
from panther_ops.transport.conversation import Pipe
from panther_ops.transport.local import LocalTransport

HOME = "/home/husarion"


def sha(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


class Robot(LocalTransport):
    """The demo transport, keeping what each command printed before it asked for the go-ahead
    and how each ended.

    ``reply`` (when set) is sent instead of the pipeline's go-ahead: the answer a robot gets
    when the operator stops or the connection drops.
    """

    def __init__(self, name: str, root: Path) -> None:
        super().__init__(name, root)
        self.reply: Callable[[bytes], bytes] | None = None
        self.calls: list[str] = []
        self.asked: list[bytes] = []
        """What each write session printed before it asked for the go-ahead."""
        self.results: list[CommandResult] = []

    def _open(self, command: Command, timeout: float | None) -> Any:
        self.calls.append("start")
        return _Answering(self, super()._open(command, timeout))

    def result(self, command: Command, pipe: Pipe, status: int, out: bytes, err: bytes,
               start: float) -> CommandResult:
        res = super().result(command, pipe, status, out, err, start)
        self.results.append(res)
        return res

    @property
    def home_dir(self) -> Path:
        return self.root / "home" / "husarion"

    @property
    def backups(self) -> Path:
        return self.home_dir / ".panther-ops" / "backups"


class _Answering:
    """A command's pipe that answers the go-ahead with the robot's ``reply`` and notes the question."""

    def __init__(self, robot: Robot, pipe: Any) -> None:
        self.robot = robot
        self.pipe = pipe
        self.out = bytearray()

    def send(self, data: bytes) -> None:
        if data == scripts_apply.GO and self.robot.reply is not None:
            data = self.robot.reply(data)
        self.pipe.send(data)

    def recv(self) -> bytes:
        data: bytes = self.pipe.recv()
        self.out += data
        if not data and scripts_apply.STAGED_MARK in self.out:
            self.robot.asked.append(bytes(self.out).split(scripts_apply.STAGED_MARK, 1)[0])
        return data

    def __getattr__(self, name: str) -> Any:  # close_input, stderr, wait, close, the timeouts
        return getattr(self.pipe, name)


@pytest.fixture
def inventory(tmp_path: Path) -> Inventory:
    (tmp_path / "robots" / "r1" / "home" / "husarion").mkdir(parents=True)
    (tmp_path / "inv.yaml").write_text("robots:\n  r1: {transport: local, root: robots/r1}\n")
    return load_inventory(str(tmp_path / "inv.yaml"))


@pytest.fixture
def ctx(inventory: Inventory) -> Iterator[RobotContext]:
    robot = inventory.robots["r1"]
    assert robot.root is not None
    transport = Robot(robot.name, robot.root)
    yield RobotContext(robot, transport, inventory)
    transport.close()


def robot_of(ctx: RobotContext) -> Robot:
    assert isinstance(ctx.transport, Robot)
    return ctx.transport


def mode_of(p: Path) -> int:
    return stat.S_IMODE(p.stat().st_mode)


def write(p: Path, data: bytes, mode: int = 0o644) -> Path:
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_bytes(data)
    p.chmod(mode)
    return p


def temp_files(robot: Robot) -> list[Path]:
    return sorted(p for p in robot.root.rglob("*") if ".panther-ops." in p.name)


def snapshot(robot: Robot) -> dict[str, tuple[bytes, int]]:
    """Every file under the robot's home except the backups: contents and modes."""
    home = robot.home_dir
    return {str(p.relative_to(home)): (p.read_bytes(), mode_of(p)) for p in home.rglob("*")
            if p.is_file() and ".panther-ops" not in p.relative_to(home).parts}


def attempts(robot: Robot) -> list[Path]:
    """The backup directories on the robot (one per write that got past its checks)."""
    return sorted(robot.backups.iterdir()) if robot.backups.is_dir() else []


@pytest.fixture
def tree(ctx: RobotContext) -> dict[str, Path]:
    """An edited file (mode 0640), a file to remove (mode 0600) and an untouched neighbour."""
    home = robot_of(ctx).home_dir
    return {
        "edited": write(home / "config" / "edited.yaml", b"old: 1\n", 0o640),
        "gone": write(home / "gone.txt", b"remove me\n", 0o600),
        "other": write(home / "other.txt", b"leave me\n"),
    }


def standard_plan(**kw: Any) -> RobotPlan:
    return RobotPlan("r1", "edit, add two, remove one", [
        FileEdit("~/config/edited.yaml", b"old: 1\n", b"new: 2\nmore: 3\n"),
        FileEdit(f"{HOME}/new/deep/explicit.txt", None, b"explicit mode\n", 0o600),
        FileEdit("~/plain.txt", None, b"default mode\n"),
        FileEdit("~/gone.txt", b"remove me\n", None),
    ], **kw)


def apply(ctx: RobotContext, plan: RobotPlan, on_staged: Callable[[str], None] | None = None) -> RobotResult:
    return apply_plan(ctx, plan, ApplyOptions(restart=False, command="test change", on_staged=on_staged))


def test_go_renames_every_file_and_keeps_a_backup(ctx: RobotContext, tree: dict[str, Path]) -> None:
    robot = robot_of(ctx)
    home = robot.home_dir
    plan = standard_plan()
    staged: list[str] = []

    result = apply(ctx, plan, staged.append)

    assert result.outcome is Outcome.CHANGED, result.message
    assert staged == ["r1"], "on_staged: once, with the robot's name"
    assert robot.asked == [b""], "asked once, having printed nothing else"
    assert robot.results[-1].exit_status == 0
    # the edited file: new bytes, its own mode kept
    assert tree["edited"].read_bytes() == b"new: 2\nmore: 3\n"
    assert mode_of(tree["edited"]) == 0o640
    # new files: the explicit mode, or 0644; missing directories created
    explicit = home / "new" / "deep" / "explicit.txt"
    assert explicit.read_bytes() == b"explicit mode\n"
    assert mode_of(explicit) == 0o600
    plain = home / "plain.txt"
    assert plain.read_bytes() == b"default mode\n"
    assert mode_of(plain) == 0o644
    assert not tree["gone"].exists()
    assert tree["other"].read_bytes() == b"leave me\n"
    assert temp_files(robot) == []
    # the backup: the manifest as sent, old contents by edit index, the status
    backup_id = result.data["backup"]
    assert attempts(robot) == [robot.backups / backup_id]
    backup = robot.backups / backup_id
    raw = (backup / "manifest.json").read_bytes()
    manifest = json.loads(raw)
    assert raw == json.dumps(manifest, indent=2).encode(), "stored byte for byte as the pipeline sent it"
    assert (manifest["id"], manifest["robot"], manifest["command"], manifest["summary"]) == (
        backup_id, "r1", "test change", plan.summary)
    assert [(f["path"], f["backup"]) for f in manifest["files"]] == [
        ("~/config/edited.yaml", "files/0"), (f"{HOME}/new/deep/explicit.txt", None), ("~/plain.txt", None),
        ("~/gone.txt", "files/3")]
    assert [(f["sha256_before"], f["sha256_after"]) for f in manifest["files"]] == [
        (sha(b"old: 1\n"), sha(b"new: 2\nmore: 3\n")), (None, sha(b"explicit mode\n")),
        (None, sha(b"default mode\n")), (sha(b"remove me\n"), None)]
    assert sorted(p.name for p in (backup / "files").iterdir()) == ["0", "3"], "new files have no backup"
    assert (backup / "files" / "0").read_bytes() == b"old: 1\n"
    assert (backup / "files" / "3").read_bytes() == b"remove me\n"
    assert (backup / "status").read_text() == "applied\n"


def test_the_backup_keeps_each_files_mode(ctx: RobotContext, tree: dict[str, Path]) -> None:
    robot = robot_of(ctx)
    result = apply(ctx, standard_plan())  # FileEdit.mode None: the plan does not say the modes
    assert result.outcome is Outcome.CHANGED, result.message
    files = robot.backups / result.data["backup"] / "files"
    assert (mode_of(files / "0"), mode_of(files / "3")) == (0o640, 0o600), "as the files were"


def test_not_recreated_status_and_result(ctx: RobotContext, tree: dict[str, Path]) -> None:
    robot = robot_of(ctx)
    result = apply(ctx, standard_plan(recreate=("driver",)))
    assert result.outcome is Outcome.CHANGED
    assert "not recreated" in result.message
    assert (robot.backups / result.data["backup"] / "status").read_text() == "applied (not recreated)\n"
    assert [d.path for d in result.diffs] == [e.path for e in standard_plan().edits]


def test_explicit_mode_replaces_the_mode_of_an_existing_file(ctx: RobotContext, tree: dict[str, Path]) -> None:
    plan = RobotPlan("r1", "chmod too", [FileEdit("~/config/edited.yaml", b"old: 1\n", b"x\n", 0o600)])
    result = apply(ctx, plan)
    assert result.outcome is Outcome.CHANGED, result.message
    assert tree["edited"].read_bytes() == b"x\n"
    assert mode_of(tree["edited"]) == 0o600


@pytest.mark.parametrize(("reply", "reason"), [(b"later\n", "later"), (b"", "connection closed")])
def test_no_go_ahead_renames_nothing_and_records_the_attempt(ctx: RobotContext, tree: dict[str, Path], reply: bytes,
                                                           reason: str) -> None:
    robot = robot_of(ctx)
    robot.reply = lambda _: reply
    before = snapshot(robot)

    with pytest.raises(TransportError, match=f"exit {scripts_apply.ABANDONED_EXIT}"):
        apply(ctx, standard_plan())

    assert robot.results[-1].exit_status == scripts_apply.ABANDONED_EXIT
    assert robot.asked == [b""]
    assert snapshot(robot) == before, "nothing renamed, created or removed"
    assert temp_files(robot) == [], "the staged files are gone"
    [backup] = attempts(robot)
    status = (backup / "status").read_text()
    assert status.startswith("abandoned"), status
    assert f"({reason})" in status
    assert (backup / "files" / "0").read_bytes() == b"old: 1\n", "the backup is kept"


def test_stop_removes_everything_the_staging_made(ctx: RobotContext, tree: dict[str, Path]) -> None:
    robot = robot_of(ctx)
    robot.reply = lambda _: scripts_apply.STOP
    before = snapshot(robot)

    with pytest.raises(TransportError, match=f"exit {scripts_apply.ABANDONED_EXIT}"):
        apply(ctx, standard_plan())

    assert robot.asked == [b""]
    assert snapshot(robot) == before
    assert temp_files(robot) == []
    assert not (robot.home_dir / ".panther-ops").exists(), "no backup, not even the directories made for it"


def test_stop_leaves_earlier_backups_alone(ctx: RobotContext, tree: dict[str, Path]) -> None:
    robot = robot_of(ctx)
    first = apply(ctx, RobotPlan("r1", "one", [FileEdit("~/other.txt", b"leave me\n", b"changed\n")]))
    assert first.outcome is Outcome.CHANGED, first.message
    robot.reply = lambda _: scripts_apply.STOP
    with pytest.raises(TransportError, match=f"exit {scripts_apply.ABANDONED_EXIT}"):
        apply(ctx, standard_plan())
    assert attempts(robot) == [robot.backups / first.data["backup"]]
    assert temp_files(robot) == []


def test_go_without_its_newline_still_goes(ctx: RobotContext, tree: dict[str, Path]) -> None:
    robot = robot_of(ctx)
    robot.reply = lambda _: b"go"  # the input ends right after: `read` still takes the last line
    result = apply(ctx, standard_plan())
    assert result.outcome is Outcome.CHANGED, result.message
    assert tree["edited"].read_bytes() == b"new: 2\nmore: 3\n"


def test_a_file_changed_since_planning_writes_nothing(ctx: RobotContext, tree: dict[str, Path]) -> None:
    robot = robot_of(ctx)
    tree["gone"].write_bytes(b"someone edited me\n")  # the last file: the earlier ones pass their checks
    before = snapshot(robot)
    staged: list[str] = []

    result = apply(ctx, standard_plan(), staged.append)

    assert result.outcome is Outcome.FAILED
    assert "changed on the robot" in result.message
    assert robot.results[-1].exit_status == scripts_apply.CHANGED_EXIT
    assert "gone.txt changed on the robot" in robot.results[-1].stderr
    assert robot.asked == [b""] and staged == ["r1"], "staged, then checked after the go-ahead"
    assert "backup" not in result.data
    assert snapshot(robot) == before
    assert attempts(robot) == [], "no backup directory is left for the attempt"
    assert temp_files(robot) == []


def test_a_file_gone_since_planning_writes_nothing(ctx: RobotContext, tree: dict[str, Path]) -> None:
    robot = robot_of(ctx)
    tree["edited"].unlink()
    before = snapshot(robot)
    result = apply(ctx, standard_plan())
    assert result.outcome is Outcome.FAILED
    assert robot.results[-1].exit_status == scripts_apply.CHANGED_EXIT
    assert robot.asked == [b""]
    assert snapshot(robot) == before
    assert attempts(robot) == []
    assert temp_files(robot) == []


def test_a_file_that_must_not_exist_but_appeared(ctx: RobotContext, tree: dict[str, Path]) -> None:
    robot = robot_of(ctx)
    appeared = write(robot.home_dir / "plain.txt", b"created meanwhile\n")
    before = snapshot(robot)
    result = apply(ctx, standard_plan())
    assert result.outcome is Outcome.FAILED
    assert robot.results[-1].exit_status == scripts_apply.CHANGED_EXIT
    assert "appeared on the robot" in robot.results[-1].stderr
    assert robot.asked == [b""]
    assert appeared.read_bytes() == b"created meanwhile\n"
    assert snapshot(robot) == before
    assert attempts(robot) == []
    assert temp_files(robot) == []


def test_everything_is_staged_before_the_question(ctx: RobotContext, tree: dict[str, Path]) -> None:
    robot = robot_of(ctx)
    home = robot.home_dir
    seen: dict[str, Any] = {}

    def on_staged(_: str) -> None:  # called from inside the answer, while the session waits
        temps = {str(p.relative_to(home)).split(".panther-ops.")[0]: p for p in temp_files(robot)}
        seen["temps"] = sorted(temps)
        seen["staged"] = {k: (p.read_bytes(), mode_of(p)) for k, p in temps.items()}
        seen["beside"] = all(p.parent == (home / k).parent for k, p in temps.items())
        seen["targets"] = (tree["edited"].read_bytes(), (home / "new" / "deep" / "explicit.txt").exists(),
                           (home / "plain.txt").exists(), tree["gone"].read_bytes())
        [backup] = attempts(robot)
        seen["manifest"] = json.loads((backup / "manifest.json").read_bytes())["summary"]
        seen["backup"] = (backup / "files" / "0").read_bytes()
        seen["status"] = (backup / "status").exists()

    result = apply(ctx, standard_plan(), on_staged)

    assert result.outcome is Outcome.CHANGED, result.message
    assert seen["temps"] == sorted(["config/.edited.yaml", "new/deep/.explicit.txt", ".plain.txt"]), (
        "one temp file beside each new content, none for the removal")
    assert seen["beside"]
    assert seen["staged"] == {"config/.edited.yaml": (b"new: 2\nmore: 3\n", 0o640),
                              "new/deep/.explicit.txt": (b"explicit mode\n", 0o600),
                              ".plain.txt": (b"default mode\n", 0o644)}, "full contents, final modes"
    assert seen["targets"] == (b"old: 1\n", False, False, b"remove me\n"), "no target touched yet"
    assert seen["manifest"] == standard_plan().summary
    assert seen["backup"] == b"old: 1\n"
    assert seen["status"] is False
    assert temp_files(robot) == []


def test_binary_contents_round_trip(ctx: RobotContext) -> None:
    robot = robot_of(ctx)
    home = robot.home_dir
    old = bytes(range(255, -1, -1)) * 3 + b"\0"
    blob = bytes(range(256)) * 64  # NUL, newlines, 0xff, ...
    tricky = b"\0\0" + scripts_apply.STAGED_MARK + b"go\n\0"  # looks like the protocol, is only content
    write(home / "bin" / "old.bin", old, 0o755)
    plan = RobotPlan("r1", "binary", [FileEdit("~/bin/old.bin", old, blob), FileEdit("~/bin/tricky.bin", None, tricky),
                                      FileEdit("~/bin/empty.bin", None, b"")])
    result = apply(ctx, plan)
    assert result.outcome is Outcome.CHANGED, result.message
    assert (home / "bin" / "old.bin").read_bytes() == blob
    assert mode_of(home / "bin" / "old.bin") == 0o755
    assert (home / "bin" / "tricky.bin").read_bytes() == tricky
    assert (home / "bin" / "empty.bin").read_bytes() == b""
    assert (robot.backups / result.data["backup"] / "files" / "0").read_bytes() == old


def test_paths_with_spaces_dashes_and_shell_syntax(ctx: RobotContext) -> None:
    robot = robot_of(ctx)
    home = robot.home_dir
    write(home / "-dash dir" / "a b.txt", b"old\n")
    plan = RobotPlan("r1", "odd names", [FileEdit("~/-dash dir/a b.txt", b"old\n", b"new\n"),
                                         FileEdit("~/-dash dir/$(touch x) *", None, b"lit\n")])
    result = apply(ctx, plan)
    assert result.outcome is Outcome.CHANGED, result.message
    assert (home / "-dash dir" / "a b.txt").read_bytes() == b"new\n"
    assert (home / "-dash dir" / "$(touch x) *").read_bytes() == b"lit\n"
    assert not list(robot.root.rglob("x"))


@pytest.mark.parametrize("bad", ["~/a\nb.yaml", "~/a\tb.yaml"])
def test_a_path_with_a_newline_is_refused_before_anything_runs(ctx: RobotContext, bad: str) -> None:
    robot = robot_of(ctx)
    home = robot.home_dir
    write(home / "fine.yaml", b"x\n")
    plan = RobotPlan("r1", "bad path", [FileEdit("~/fine.yaml", b"x\n", b"y\n"), FileEdit(bad, None, b"z\n")])
    staged: list[str] = []
    with pytest.raises(TransportError, match="newline"):
        apply(ctx, plan, staged.append)
    assert robot.calls == [], "no command started"
    assert staged == []
    assert (home / "fine.yaml").read_bytes() == b"x\n"
    assert not (home / ".panther-ops").exists()


def test_dry_run_and_noop_plans_write_nothing(ctx: RobotContext) -> None:
    robot = robot_of(ctx)
    write(robot.home_dir / "a.yaml", b"a: old\n")
    plan = RobotPlan("r1", "edit a", [FileEdit("~/a.yaml", b"a: old\n", b"a: new\n")])
    dry = apply_plan(ctx, plan, ApplyOptions(dry_run=True))
    assert dry.outcome is Outcome.CHANGED and dry.data.get("dry_run") is True
    noop = apply_plan(ctx, RobotPlan("r1", "nothing", [], noop="already so"), ApplyOptions())
    assert noop.outcome is Outcome.OK and noop.message == "already so"
    assert robot.calls == []
    assert (robot.home_dir / "a.yaml").read_bytes() == b"a: old\n"


# -- a real planner on the demo fleet ----------------------------------------------------


def test_a_planned_change_applies_once_then_plans_as_noop(demo_connections: tuple[Inventory, Connections]) -> None:
    inv, conns = demo_connections
    robot = inv.robots["panther-01"]
    ctx = RobotContext(robot, conns.get(robot), inv)
    assert isinstance(ctx.transport, LocalTransport)
    plan = read_and_plan_args(ctx, {"wheel_type": "WH04"}, [])
    assert len(plan.edits) == 1
    compose = ctx.transport.local_path(plan.edits[0].path)
    before = compose.read_bytes()
    assert plan.edits[0].before == before
    staged: list[str] = []

    def on_staged(name: str) -> None:
        staged.append(name)
        assert compose.read_bytes() == before, "nothing renamed before the go-ahead"

    result = apply_plan(ctx, plan, ApplyOptions(restart=False, command="config set", on_staged=on_staged))
    assert staged == [robot.name]
    assert result.outcome is Outcome.CHANGED, result.message
    assert result.data["backup"]
    after = compose.read_bytes()
    assert after == plan.edits[0].after and b"wheel_type:=WH04" in after
    backup = ctx.transport.local_path(f"~/.panther-ops/backups/{result.data['backup']}")
    assert (backup / "files" / "0").read_bytes() == before
    assert (backup / "status").read_text() == "applied (not recreated)\n"
    assert not [p for p in compose.parent.iterdir() if ".panther-ops." in p.name]

    again = read_and_plan_args(ctx, {"wheel_type": "WH04"}, [])
    assert again.edits == []
    assert again.noop is not None and "wheel_type already WH04" in again.noop
    repeat = apply_plan(ctx, again, ApplyOptions(restart=False, on_staged=staged.append))
    assert repeat.outcome is Outcome.OK
    assert staged == [robot.name], "a no-op stages nothing"
    assert compose.read_bytes() == after
