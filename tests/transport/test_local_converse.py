"""LocalTransport.run in its conversational mode (until/answer) and its limits: a command may ask
back once; one that ends without asking is not answered; big outputs and timeouts."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from panther_ops.errors import TransportError
from panther_ops.transport.base import Command
from panther_ops.transport.local import LocalTransport

MARK = b"@@ask@@\n"
pytestmark = pytest.mark.timeout(60)  # a hang fails one test, not the session
ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def robot(tmp_path: Path) -> LocalTransport:
    root = tmp_path / "robot"
    (root / "home" / "husarion").mkdir(parents=True)
    return LocalTransport("r1", root)


class Answers:
    def __init__(self, reply: bytes) -> None:
        self.reply = reply
        self.asked: list[bytes] = []

    def __call__(self, out: bytes) -> bytes:
        self.asked.append(out)
        return self.reply


def test_a_command_is_answered_with_everything_it_printed(robot: LocalTransport) -> None:
    script = 'printf "hello\\n"; head -c 5 > got-stdin; printf "@@ask@@\\n"; read -r x; printf "got %s\\n" "$x"; exit 6'
    answer = Answers(b"yes\n")
    res = robot.run(Command.sh(script), stdin=b"12345", until=MARK, answer=answer)
    assert answer.asked == [b"hello\n" + MARK]
    assert res.exit_status == 6
    assert res.raw_stdout == b"hello\n" + MARK + b"got yes\n"
    assert (robot.root / "got-stdin").read_bytes() == b"12345", "stdin arrives before the question"


def test_the_input_closes_after_the_answer(robot: LocalTransport) -> None:
    script = 'printf "@@ask@@\\n"; read -r x; rest=$(cat); printf "[%s][%s]\\n" "$x" "$rest"'
    res = robot.run(Command.sh(script), until=MARK, answer=Answers(b"line\n"), timeout=20)
    assert res.exit_status == 0
    assert res.stdout == "@@ask@@\n[line][]\n", "cat saw the end of the input at once"


def test_a_command_that_ends_before_asking_is_not_answered(robot: LocalTransport) -> None:
    answer = Answers(b"go\n")
    res = robot.run(Command.sh('head -c 3; echo; echo out; echo err >&2; exit 7'), stdin=b"abc",
                    until=MARK, answer=answer, timeout=20)
    assert answer.asked == []
    assert (res.exit_status, res.stdout, res.stderr) == (7, "abc\nout\n", "err\n")


def test_a_command_that_asks_but_does_not_read_the_answer(robot: LocalTransport) -> None:
    answer = Answers(b"go\n" * 100_000)  # more than a pipe holds: the write must not hang or raise
    res = robot.run(Command.sh('printf "@@ask@@\\n"; exit 3'), until=MARK, answer=answer, timeout=20)
    assert answer.asked == [MARK]
    assert res.exit_status == 3


def test_without_answer_until_is_ignored(robot: LocalTransport) -> None:
    res = robot.run(Command.sh('printf "@@ask@@\\n"; read -r x || x=eof; echo "$x"'), until=MARK, timeout=20)
    assert res.stdout == "@@ask@@\neof\n"


@pytest.mark.parametrize("converse", [True, False])
def test_big_stderr_does_not_deadlock(robot: LocalTransport, converse: bool) -> None:
    size = 200 * 1024  # over 128 KiB: more than the stderr pipe holds
    script = f'head -c {size} /dev/zero | tr "\\0" e >&2; printf "@@ask@@\\n"; read -r x || x=eof; echo "$x"'
    answer = Answers(b"fine\n")
    kw = {"until": MARK, "answer": answer} if converse else {}
    res = robot.run(Command.sh(script), timeout=30, **kw)  # type: ignore[arg-type]
    assert res.exit_status == 0
    assert res.stderr == "e" * size
    assert res.stdout == "@@ask@@\n" + ("fine\n" if converse else "eof\n")
    assert answer.asked == ([MARK] if converse else [])


def test_big_stdout_and_stdin_around_the_question(robot: LocalTransport) -> None:
    blob = bytes(range(256)) * 1024  # 256 KiB, read by the command before it prints
    script = (f'head -c {len(blob)} > in.bin; head -c 1048576 /dev/zero | tr "\\0" o; printf "@@ask@@\\n"; '
              'read -r x; printf "%s\\n" "$x"')
    answer = Answers(b"ok\n")
    res = robot.run(Command.sh(script), stdin=blob, until=MARK, answer=answer, timeout=30)
    assert res.exit_status == 0
    assert (robot.root / "in.bin").read_bytes() == blob
    assert len(answer.asked) == 1 and answer.asked[0] == b"o" * 1048576 + MARK
    assert res.raw_stdout == b"o" * 1048576 + MARK + b"ok\n"


@pytest.mark.parametrize("converse", [True, False])
def test_a_command_that_outlives_its_timeout_raises(robot: LocalTransport, converse: bool) -> None:
    answer = Answers(b"go\n")
    kw = {"until": MARK, "answer": answer} if converse else {}
    with pytest.raises(TransportError, match="timed out"):
        robot.run(Command.sh("sleep 3"), timeout=1, **kw)  # type: ignore[arg-type]
    assert answer.asked == []


# -- timeouts, big inputs, failing answers, kept commands ---------------------------------------


@pytest.mark.parametrize("converse", [True, False])
def test_the_timeout_is_enforced_promptly(robot: LocalTransport, converse: bool) -> None:
    kw = {"until": MARK, "answer": Answers(b"go\n")} if converse else {}
    start = time.monotonic()
    with pytest.raises(TransportError, match="timed out"):
        robot.run(Command.sh("sleep 6"), timeout=1, **kw)  # type: ignore[arg-type]
    assert time.monotonic() - start < 4


def run_child(code: str, limit: float) -> tuple[str, bool]:
    """Run a Python snippet in its own process group; (stdout, whether it had to be killed)."""
    proc = subprocess.Popen([sys.executable, "-c", textwrap.dedent(code)], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, cwd=ROOT, start_new_session=True, text=True)
    try:
        out, _ = proc.communicate(timeout=limit)
        return out, False
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, _ = proc.communicate()
        return out, True


def test_big_stdin_to_a_command_that_echoes_it(tmp_path: Path) -> None:
    out, killed = run_child(f"""
        from pathlib import Path
        from panther_ops.transport.base import Command
        from panther_ops.transport.local import LocalTransport
        root = Path({str(tmp_path)!r})
        (root / "home" / "husarion").mkdir(parents=True)
        data = b"x" * (1 << 20)
        res = LocalTransport("r1", root).run(Command.of("cat"), stdin=data, timeout=3)
        print("same" if res.raw_stdout == data else f"differs {{len(res.raw_stdout)}}")
        """, limit=10)
    assert not killed, f"hung: {out}"
    assert out.strip() == "same"


def test_an_answer_that_raises_still_ends_the_command(tmp_path: Path) -> None:
    out, killed = run_child(f"""
        import time
        from pathlib import Path
        from panther_ops.transport.base import Command
        from panther_ops.transport.local import LocalTransport
        root = Path({str(tmp_path)!r})
        (root / "home" / "husarion").mkdir(parents=True)
        flag = root / "flag"
        def answer(out):
            raise RuntimeError("operator interrupted")
        script = 'printf "@@ask@@\\\\n"; read -r x || x=eof; echo "$x" > "$1"'
        try:
            LocalTransport("r1", root).run(Command.sh(script, str(flag)), until=b"@@ask@@\\n", answer=answer,
                                          timeout=30)
        except RuntimeError as exc:
            print("raised", exc)
        deadline = time.monotonic() + 3
        while not flag.exists() and time.monotonic() < deadline:
            time.sleep(0.05)
        print(flag.read_text().strip() if flag.exists() else "still waiting")
        """, limit=20)
    assert not killed, out
    assert out.split("\n")[:2] == ["raised operator interrupted", "eof"]


def test_a_session_waits_past_its_timeout(robot: LocalTransport) -> None:
    """A write session waits for its caller (the rest of the fleet being planned, the operator)
    without its time limit running; staging and the go-ahead are limited."""
    from panther_ops.transport.session import FileWrite, stage_input

    (robot.root / "home" / "husarion" / "a.txt").write_bytes(b"old\n")
    session = robot.session(timeout=1)
    time.sleep(1.3)  # opened beside the read, before the plan is known
    session.stage(stage_input("/home/husarion/.panther-ops/backups/b", {}, "",
                              [FileWrite("/home/husarion/a.txt", b"old\n", b"new\n")], "t"))
    assert session.wait_staged() is None
    time.sleep(1.3)  # the operator reads the plan
    res = session.go()
    assert (res.exit_status, res.stderr) == (0, "")
    assert (robot.root / "home" / "husarion" / "a.txt").read_bytes() == b"new\n"


def test_a_session_closed_at_once_lets_its_stderr_reader_finish_first(robot: LocalTransport,
                                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    """Closing a command's pipe waits for the thread that reads its stderr to reach the end
    before the descriptor is closed: else the thread reads a closed (or reused) descriptor.
    The reader is made late on purpose (its reads wait 0.3 s), so the order is not left to chance."""
    import os
    import threading

    real_read = os.read

    def late_read(fd: int, n: int) -> bytes:
        if threading.current_thread().name.endswith("stderr"):
            time.sleep(0.3)
        return real_read(fd, n)

    failures: list[BaseException | None] = []
    monkeypatch.setattr(threading, "excepthook", lambda args: failures.append(args.exc_value))
    monkeypatch.setattr(os, "read", late_read)
    (robot.root / "home/husarion/compose.yaml").write_bytes(b"services: {}\n")
    session = robot.session(read="~/compose.yaml")
    assert session.read().stdout.endswith("services: {}\n")  # after the home directory
    session.close()
    for thread in threading.enumerate():  # a reader still running now would fail after the test
        if thread.name.endswith("stderr"):
            thread.join(timeout=2)
    assert failures == []
