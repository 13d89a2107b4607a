"""A plan's read of compose.yaml kept open to carry the write: one session per robot per change."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from panther_ops.cli.app import main
from panther_ops.core.config.read import read_and_plan_args
from panther_ops.core.fleet.inventory_file import load_inventory
from panther_ops.core.fleet.pipeline import ApplyOptions, apply_plan
from panther_ops.core.fleet.runner import Connections, RobotContext
from panther_ops.transport import scripts_apply
from panther_ops.transport.base import Command
from panther_ops.transport.local import LocalTransport

MARK = b"@@mark@@\n"


@pytest.fixture
def robot(tmp_path: Path) -> LocalTransport:
    root = tmp_path / "robot"
    (root / "home" / "husarion").mkdir(parents=True)
    return LocalTransport("r", root)


def test_kept_command_waits_for_input_and_resumes(robot: LocalTransport) -> None:
    res = robot.run_kept(Command.sh('printf "first\\n@@mark@@\\n"; read -r x; printf "got %s\\n" "$x"; exit 7'),
                         MARK, "k")
    assert res.exit_status == 0 and res.raw_stdout == b"first\n"
    later = robot.resume("k", b"hello\n")
    assert later is not None
    assert later.exit_status == 7 and later.raw_stdout == b"got hello\n"
    assert robot.resume("k", b"again\n") is None, "a kept command is resumed once"


def test_a_kept_command_advances_from_mark_to_mark(robot: LocalTransport) -> None:
    script = ('head -c 4 > /dev/null; printf "one\\n@@mark@@\\n"; read -r a; printf "two %s\\n@@mark@@\\n" "$a"; '
              'read -r b; printf "three %s\\n" "$b"; exit 5')
    first = robot.run_kept(Command.sh(script), MARK, "k", stdin=b"skip")
    assert first.raw_stdout == b"one\n" and robot.kept("k")
    second = robot.advance("k", b"A\n", MARK)
    assert second is not None and second.exit_status == 0 and second.raw_stdout == b"two A\n"
    assert robot.kept("k"), "still kept: it printed the mark again"
    last = robot.resume("k", b"B\n")
    assert last is not None and (last.exit_status, last.raw_stdout) == (5, b"three B\n")
    assert not robot.kept("k")
    assert robot.advance("k", b"x\n", MARK) is None


def test_a_command_that_ends_instead_of_asking_again_is_no_longer_kept(robot: LocalTransport) -> None:
    robot.run_kept(Command.sh('printf "@@mark@@\\n"; read -r a; echo "done $a"; echo why >&2; exit 3'), MARK, "k")
    res = robot.advance("k", b"x\n", MARK)
    assert res is not None and (res.exit_status, res.stdout, res.stderr) == (3, "done x\n", "why\n")
    assert not robot.kept("k")


def test_command_that_ends_before_the_mark_is_not_kept(robot: LocalTransport) -> None:
    res = robot.run_kept(Command.sh('echo nope; echo bad >&2; exit 44'), MARK, "k")
    assert (res.exit_status, res.stdout, res.stderr) == (44, "nope\n", "bad\n")
    assert robot.resume("k", b"x\n") is None


def test_dropping_and_closing_end_the_kept_command(robot: LocalTransport, tmp_path: Path) -> None:
    flag = tmp_path / "ended"
    script = 'printf "@@mark@@\\n"; read -r x || : ; echo "${x:-eof}" > "$1"'
    robot.run_kept(Command.sh(script, str(flag)), MARK, "k")
    robot.drop_kept("k")
    assert flag.read_text() == "eof\n", "its input closed: the command saw the end and finished"
    robot.run_kept(Command.sh(script, str(flag) + "2"), MARK, "k")
    robot.close()
    assert (tmp_path / "ended2").read_text() == "eof\n"


def test_read_kept_then_apply_in_the_same_session(robot: LocalTransport) -> None:
    import hashlib
    import json

    home = robot.root / "home" / "husarion"
    (home / "compose.yaml").write_bytes(b"old\n")
    (home / "compose.yaml").chmod(0o640)
    mark = "@@m@@"
    res = robot.run_kept(Command.sh(scripts_apply.READ_KEPT, "~/compose.yaml", mark), f"{mark}\n".encode(),
                         scripts_apply.WRITE_KEY)
    first, _, tar = res.raw_stdout.partition(b"\n")
    assert first == b"/home/husarion"
    got = scripts_apply.read_archive(tar)
    assert (got.data, got.mode) == (b"old\n", 0o640)

    w = "/home/husarion/.panther-ops/backups/b1"
    staged = "/home/husarion/.compose.yaml.panther-ops.x"
    payload = scripts_apply.archive([
        scripts_apply.Member(w, None, 0o700), scripts_apply.Member(f"{w}/files", None, 0o700),
        scripts_apply.Member(f"{w}/manifest.json", json.dumps({"id": "b1"}).encode(), 0o600),
        scripts_apply.Member(f"{w}/files/0", b"old\n", got.mode),
        scripts_apply.Member(staged, b"new\n", got.mode),
    ])
    argv = [w, "applied", str(len(payload)), "-",
            "/home/husarion/compose.yaml", hashlib.sha256(b"old\n").hexdigest(), staged, "0"]
    asked: list[bytes] = []

    def answer(out: bytes) -> bytes:
        asked.append(out)
        assert (home / "compose.yaml").read_bytes() == b"old\n", "nothing renamed before the go-ahead"
        assert (robot.root / staged.lstrip("/")).read_bytes() == b"new\n", "staged beside the target"
        return b"go\n"

    done = robot.resume(scripts_apply.WRITE_KEY, scripts_apply.apply_request(argv) + payload,
                        until=scripts_apply.STAGED_MARK, answer=answer)
    assert done is not None and done.exit_status == 0, done
    assert asked == [scripts_apply.STAGED_MARK]
    assert (home / "compose.yaml").read_bytes() == b"new\n"
    assert (home / "compose.yaml").stat().st_mode & 0o777 == 0o640
    backup = home / ".panther-ops" / "backups" / "b1"
    assert (backup / "files" / "0").read_bytes() == b"old\n"
    assert (backup / "files" / "0").stat().st_mode & 0o777 == 0o640
    assert json.loads((backup / "manifest.json").read_text()) == {"id": "b1"}
    assert (backup / "status").read_text() == "applied\n"
    assert backup.stat().st_mode & 0o777 == 0o700


def test_read_archive_refuses_what_is_not_one_file() -> None:
    with pytest.raises(ValueError):
        scripts_apply.read_archive(b"not a tar")
    with pytest.raises(ValueError):
        scripts_apply.read_archive(scripts_apply.archive([scripts_apply.Member("/d", None, 0o755)]))


def test_apply_request_refuses_newlines() -> None:
    with pytest.raises(ValueError):
        scripts_apply.apply_request(["a\nb"])


class Counting(LocalTransport):
    """The demo transport, counting the sessions it starts (run, run_kept) and continues (advance, resume)."""

    def __init__(self, inner: LocalTransport) -> None:
        super().__init__(inner.name, inner.root, inner.user)
        self.calls: list[str] = []

    def run(self, command: Command, **kw: Any) -> Any:  # type: ignore[override]
        self.calls.append("run")
        return super().run(command, **kw)

    def run_kept(self, command: Command, until: bytes, key: str, **kw: Any) -> Any:  # type: ignore[override]
        self.calls.append("run_kept")
        return super().run_kept(command, until, key, **kw)

    def advance(self, key: str, stdin: bytes, until: bytes) -> Any:
        self.calls.append("advance")
        return super().advance(key, stdin, until)

    def resume(self, key: str, stdin: bytes, **kw: Any) -> Any:  # type: ignore[override]
        self.calls.append("resume")
        return super().resume(key, stdin, **kw)


@pytest.fixture
def demo_ctx(tmp_path: Path) -> Iterator[RobotContext]:
    assert main(["demo", "init", "--dest", str(tmp_path / "demo")]) == 0
    inv = load_inventory(str(tmp_path / "demo"))
    robot = inv.robots["panther-01"]
    with Connections(inv) as conns:
        base = conns.get(robot)
        assert isinstance(base, LocalTransport)
        yield RobotContext(robot, Counting(base), inv)


def test_a_change_costs_one_session(demo_ctx: RobotContext) -> None:
    plan = read_and_plan_args(demo_ctx, {"wheel_type": "WH04"}, [])
    assert plan.edits
    result = apply_plan(demo_ctx, plan, ApplyOptions(restart=False, command="t"))
    assert result.outcome.value == "changed", result.message
    # the plan's read, kept; the staging request on it; the go-ahead: one session
    assert demo_ctx.transport.calls == ["run_kept", "advance", "resume"]  # type: ignore[attr-defined]
    compose = plan.edits[0].path
    assert b"wheel_type:=WH04" in (demo_ctx.transport.root / compose.lstrip("/")).read_bytes()  # type: ignore[attr-defined]


def test_without_a_kept_read_the_write_opens_its_own_session(demo_ctx: RobotContext) -> None:
    plan = read_and_plan_args(demo_ctx, {"wheel_type": "WH04"}, [])
    demo_ctx.transport.drop_kept(scripts_apply.WRITE_KEY)
    result = apply_plan(demo_ctx, plan, ApplyOptions(restart=False, command="t"))
    assert result.outcome.value == "changed", result.message
    # nothing kept to advance: the write starts its own session and keeps it for the go-ahead
    assert demo_ctx.transport.calls == ["run_kept", "advance", "run_kept", "resume"]  # type: ignore[attr-defined]
