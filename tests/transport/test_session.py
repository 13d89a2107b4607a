"""The write session (transport/session.py over scripts_apply.APPLY): stage, then go or stop.

Every test runs on both the demo transport (LocalTransport: the real shell script on a temp
robot root) and the FakeTransport (the fake robot's Python rendering of the same script), so
the two keep agreeing on each rule: a stale file is refused, a rollback restores, a stop
leaves nothing, a dropped session is recorded as abandoned.
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from panther_ops.cli.app import main
from panther_ops.core.config.read import read_and_plan_args
from panther_ops.core.fleet.inventory_file import load_inventory
from panther_ops.core.fleet.pipeline import ApplyOptions, apply_plan
from panther_ops.core.fleet.runner import Connections, RobotContext
from panther_ops.errors import OpsError
from panther_ops.testing import FakeRobot, FakeTransport
from panther_ops.transport import scripts, scripts_apply
from panther_ops.transport.base import Command
from panther_ops.transport.conversation import Conversing
from panther_ops.transport.local import LocalTransport
from panther_ops.transport.session import FileWrite, Session, SessionClosed, stage_input

HOME = "/home/husarion"
TARGET = f"{HOME}/compose.yaml"
BACKUP = f"{HOME}/.panther-ops/backups/b1"


class Robot:
    """One robot under test, whichever transport reaches it: its files by absolute path."""

    def __init__(self, kind: str, tmp_path: Path) -> None:
        self.kind = kind
        if kind == "local":
            self.root = tmp_path / "robot"
            (self.root / HOME.lstrip("/")).mkdir(parents=True)
            self.transport: Conversing = LocalTransport("r", self.root)
        else:
            self.fake = FakeRobot()
            self.transport = FakeTransport(self.fake, "r")

    def put(self, path: str, data: bytes, mode: int = 0o644) -> None:
        if self.kind == "local":
            p = self.root / path.lstrip("/")
            p.parent.mkdir(parents=True, exist_ok=True)
            p.write_bytes(data)
            p.chmod(mode)
        else:
            self.fake.put(path, data)
            self.fake.files[path].mode = mode

    def get(self, path: str) -> bytes | None:
        if self.kind == "local":
            p = self.root / path.lstrip("/")
            return p.read_bytes() if p.is_file() else None
        return self.fake.get(path)

    def mode(self, path: str) -> int:
        if self.kind == "local":
            return (self.root / path.lstrip("/")).stat().st_mode & 0o7777
        return self.fake.files[path].mode

    def files(self) -> dict[str, bytes]:
        if self.kind == "local":
            return {"/" + p.relative_to(self.root).as_posix(): p.read_bytes()
                    for p in sorted(self.root.rglob("*")) if p.is_file()}
        return {p: f.data for p, f in sorted(self.fake.files.items())}


@pytest.fixture(params=["local", "fake"])
def robot(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[Robot]:
    r = Robot(request.param, tmp_path)
    r.put(TARGET, b"old\n", 0o640)
    yield r
    r.transport.close()


def write(before: bytes | None, after: bytes | None, backup: str = BACKUP, status: str = "applied") -> bytes:
    return stage_input(backup, {"id": backup.rsplit("/", 1)[-1]}, status, [FileWrite(TARGET, before, after)], "t1")


def leftovers(robot: Robot) -> list[str]:
    return [p for p in robot.files() if ".panther-ops.t1" in p]


def test_stage_then_go_renames_and_keeps_the_backup(robot: Robot) -> None:
    session = robot.transport.session()
    session.stage(write(b"old\n", b"new\n"))
    assert session.wait_staged() is None, "everything staged, waiting for the go-ahead"
    assert robot.get(TARGET) == b"old\n", "nothing renamed before the go-ahead"
    assert robot.get(f"{HOME}/.compose.yaml.panther-ops.t1") == b"new\n", "staged beside its target"
    res = session.go()
    assert res.exit_status == 0, res
    assert robot.get(TARGET) == b"new\n" and robot.mode(TARGET) == 0o640, "the file keeps its mode"
    assert robot.get(f"{BACKUP}/files/0") == b"old\n" and robot.mode(f"{BACKUP}/files/0") == 0o640
    assert robot.get(f"{BACKUP}/status") == b"applied\n"
    assert leftovers(robot) == []
    assert session.ended and session.go() is res, "a session goes ahead once"


def test_a_file_changed_since_it_was_read_is_refused(robot: Robot) -> None:
    session = robot.transport.session()
    session.stage(write(b"old\n", b"new\n"))
    assert session.wait_staged() is None
    robot.put(TARGET, b"theirs\n", 0o640)  # another writer, between the read and the go-ahead
    res = session.go()
    assert res.exit_status == scripts_apply.CHANGED_EXIT
    assert res.stderr.strip() == f"{TARGET} changed on the robot since it was read"
    assert robot.get(TARGET) == b"theirs\n", "their write stays"
    assert leftovers(robot) == [] and not any("/backups/" in p for p in robot.files()), "nothing left behind"


def test_a_file_that_must_not_exist_but_appeared_is_refused(robot: Robot) -> None:
    new = f"{HOME}/new.yaml"
    session = robot.transport.session()
    session.stage(stage_input(BACKUP, {}, "applied", [FileWrite(new, None, b"mine\n")], "t1"))
    robot.put(new, b"theirs\n")
    res = session.go()
    assert res.exit_status == scripts_apply.CHANGED_EXIT and "appeared on the robot" in res.stderr
    assert robot.get(new) == b"theirs\n"


def test_a_rollback_restores_what_the_change_replaced(robot: Robot) -> None:
    change = robot.transport.session()
    change.stage(write(b"old\n", b"new\n"))
    assert change.go().ok
    undo = robot.transport.session()  # the change in reverse, compared with what it wrote
    undo.stage(write(b"new\n", b"old\n", backup=f"{BACKUP}/rollback", status=""))
    assert undo.go().ok
    assert robot.get(TARGET) == b"old\n" and robot.mode(TARGET) == 0o640
    assert robot.get(f"{BACKUP}/rollback/files/0") == b"new\n", "what the rollback replaced is kept"


def test_a_rollback_never_overwrites_a_later_write(robot: Robot) -> None:
    change = robot.transport.session()
    change.stage(write(b"old\n", b"new\n"))
    assert change.go().ok
    robot.put(TARGET, b"later\n", 0o640)
    undo = robot.transport.session()
    undo.stage(write(b"new\n", b"old\n", backup=f"{BACKUP}/rollback", status=""))
    assert undo.go().exit_status == scripts_apply.CHANGED_EXIT
    assert robot.get(TARGET) == b"later\n"


def test_stop_without_go_leaves_nothing(robot: Robot) -> None:
    before = robot.files()
    session = robot.transport.session()
    session.stage(write(b"old\n", b"new\n"))
    res = session.stop()
    assert res.exit_status == scripts_apply.ABANDONED_EXIT
    assert robot.files() == before, "staged files and the backup removed, nothing renamed"


def test_a_dropped_session_renames_nothing_and_records_the_attempt(robot: Robot) -> None:
    session = robot.transport.session()
    session.stage(write(b"old\n", b"new\n"))
    assert session.wait_staged() is None
    session.close()  # the connection went away before the go-ahead
    assert robot.get(TARGET) == b"old\n" and leftovers(robot) == []
    status = robot.get(f"{BACKUP}/status") or b""
    assert status == b"abandoned: no go-ahead (connection closed)\n"


def test_a_session_closed_before_its_write_makes_nothing(robot: Robot) -> None:
    before = robot.files()
    robot.transport.session().close()  # opened beside a read whose plan changes nothing
    assert robot.files() == before


def test_closing_the_transport_drops_its_open_sessions(robot: Robot) -> None:
    session = robot.transport.session()
    session.stage(write(b"old\n", b"new\n"))
    assert session.wait_staged() is None
    robot.transport.close()
    assert session.ended and robot.get(TARGET) == b"old\n" and leftovers(robot) == []


def test_a_write_for_a_session_the_transport_dropped_is_refused_as_an_error_of_the_run(robot: Robot) -> None:
    """Ctrl-C closes the run's connections while a robot may still be planning: its write then
    meets a dropped session. That is the robot's failure (an OpsError: a result, no traceback),
    not a bug, and nothing is made (seen as an internal error in test_interrupt.py under load)."""
    session = robot.transport.session()
    before = robot.files()
    robot.transport.close()
    with pytest.raises(SessionClosed, match="nothing was written") as caught:
        session.stage(write(b"old\n", b"new\n"))
    assert isinstance(caught.value, OpsError)
    assert robot.files() == before


def test_go_after_a_refused_staging_reports_the_refusal(robot: Robot) -> None:
    session = robot.transport.session()
    session.stage(scripts_apply.request([BACKUP, "", "10", "-", TARGET, "-", "-", "0"]) + b"not a tar!")
    res = session.go()  # the command already ended: the go-ahead is not sent, its end is read
    assert res.exit_status == 1 and "cannot unpack the upload" in res.stderr
    assert robot.get(TARGET) == b"old\n" and not any("/backups/" in p for p in robot.files())


def test_a_session_stages_one_write(robot: Robot) -> None:
    session = robot.transport.session()
    session.stage(write(b"old\n", b"new\n"))
    with pytest.raises(RuntimeError):
        session.stage(write(b"old\n", b"new\n"))
    session.stop()


ODD = b"@@read\n@@home 0 /x\n@@staged\n\x00\xff no newline at the end"
"""A file holding the session's own marks, a NUL and no last newline: read back byte for byte."""


@pytest.mark.parametrize("path", [TARGET, "~/compose.yaml"])
def test_a_session_reads_its_file_first_as_a_plain_read_would(robot: Robot, path: str) -> None:
    robot.put(TARGET, ODD, 0o640)
    plain = robot.transport.run(Command.sh(scripts.READ_WITH_HOME, path))
    session = robot.transport.session(read=path)
    res = session.read()
    assert (res.exit_status, res.raw_stdout) == (plain.exit_status, plain.raw_stdout) == (0, f"{HOME}\n".encode() + ODD)
    assert session.read() is res, "read once"
    session.stage(write(ODD, b"new\n"))
    assert session.go().exit_status == 0, "then the write, on the same command"
    assert robot.get(TARGET) == b"new\n" and robot.get(f"{BACKUP}/files/0") == ODD


def test_a_session_reading_a_missing_file_says_so_and_can_still_create_it(robot: Robot) -> None:
    new = f"{HOME}/new.yaml"
    session = robot.transport.session(read=new)
    res = session.read()
    assert (res.exit_status, res.raw_stdout) == (scripts.MISSING_EXIT, f"{HOME}\n".encode())
    session.stage(stage_input(BACKUP, {}, "applied", [FileWrite(new, None, b"mine\n")], "t1"))
    assert session.go().exit_status == 0 and robot.get(new) == b"mine\n"


def test_a_session_that_read_and_is_dropped_renames_nothing(robot: Robot) -> None:
    session = robot.transport.session(read=TARGET)
    assert session.read().ok
    session.close()
    assert robot.get(TARGET) == b"old\n" and not any("/.panther-ops/" in p for p in robot.files())
    with pytest.raises(SessionClosed):
        session.stage(write(b"old\n", b"new\n"))


def test_a_session_made_to_read_nothing_has_no_read(robot: Robot) -> None:
    session = robot.transport.session()
    with pytest.raises(RuntimeError):
        session.read()
    session.close()


def test_the_request_refuses_newlines() -> None:
    with pytest.raises(ValueError):
        scripts_apply.request(["a\nb"])


def test_stage_input_names_the_sha_of_what_was_read() -> None:
    data = stage_input(BACKUP, {}, "", [FileWrite(TARGET, b"old\n", b"new\n"), FileWrite("/x", None, None)], "s")
    count, *rest = data.split(b"\n", 13)
    assert count == b"12"
    assert rest[4:12] == [TARGET.encode(), hashlib.sha256(b"old\n").hexdigest().encode(),
                          f"{HOME}/.compose.yaml.panther-ops.s".encode(), b"1", b"/x", b"-", b"-", b"0"]


class Counting(LocalTransport):
    """The demo transport, counting the commands (run) and write sessions (session) it starts."""

    def __init__(self, inner: LocalTransport) -> None:
        super().__init__(inner.name, inner.root, inner.user)
        self.calls: list[str] = []

    def run(self, command: Command, **kw: Any) -> Any:  # type: ignore[override]
        self.calls.append("run")
        return super().run(command, **kw)

    def session(self, *, timeout: float | None = None, read: str | None = None) -> Session:
        self.calls.append("session" if read is None else f"session reading {read}")
        return super().session(timeout=timeout, read=read)


@pytest.fixture
def demo_ctx(tmp_path: Path) -> Iterator[RobotContext]:
    assert main(["demo", "init", "--dest", str(tmp_path / "demo")]) == 0
    inv = load_inventory(str(tmp_path / "demo"))
    robot = inv.robots["panther-01"]
    with Connections(inv) as conns:
        base = conns.get(robot)
        assert isinstance(base, LocalTransport)
        counting = Counting(base)
        yield RobotContext(robot, counting, inv)
        counting.close()


def test_a_change_costs_one_read_and_one_session(demo_ctx: RobotContext) -> None:
    plan = read_and_plan_args(demo_ctx, {"wheel_type": "WH04"}, [])
    assert plan.edits
    result = apply_plan(demo_ctx, plan, ApplyOptions(restart=False, command="t"))
    assert result.outcome.value == "changed", result.message
    assert demo_ctx.transport.calls == ["run", "session"]  # type: ignore[attr-defined]
    compose = plan.edits[0].path
    assert b"wheel_type:=WH04" in (demo_ctx.transport.root / compose.lstrip("/")).read_bytes()  # type: ignore[attr-defined]


def test_the_transport_has_nine_members() -> None:
    from panther_ops.transport.base import Transport

    members = {n for n in vars(Transport) if not n.startswith("_")} | set(Transport.__annotations__)
    assert members == {"name", "connect", "run", "read_file", "exists", "home", "docker", "session", "close"}


def test_a_change_without_a_question_costs_one_command_on_the_robot(demo_ctx: RobotContext) -> None:
    """Under --yes the write session made while the robot is planned reads compose.yaml for the
    plan: the read and the write are one command (one sshd exec session on a real robot)."""
    from panther_ops.core.fleet.changes import apply_fleet, plan_fleet
    from panther_ops.core.fleet.runner import RunOptions
    from panther_ops.transport.base import Transport

    robot, inv, transport = demo_ctx.robot, demo_ctx.inventory, demo_ctx.transport

    class Counted(Connections):
        def get(self, robot: object) -> Transport:
            return transport

    apply = ApplyOptions(restart=False, command="t")
    conns = Counted(inv)
    fp = plan_fleet("t", inv, [robot], lambda ctx: read_and_plan_args(ctx, {"wheel_type": "WH04"}, []),
                    conns, RunOptions(forks=1), stage=apply)
    assert fp.staged and not fp.usage_errors
    result = apply_fleet(fp, inv, [robot], conns, RunOptions(forks=1), apply)
    assert [r.outcome.value for r in result.results] == ["changed"], result.results
    assert transport.calls == [f"session reading {robot.compose_file}"]  # type: ignore[attr-defined]
    compose = fp.plans[robot.name].edits[0].path
    assert b"wheel_type:=WH04" in (transport.root / compose.lstrip("/")).read_bytes()  # type: ignore[attr-defined]
