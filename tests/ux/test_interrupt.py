"""Ctrl-C answers at once in every phase of a fleet command (issue 26, finding 2).

The real ``panther-ops`` process gets a SIGINT: while a robot hangs in connect (a loopback
TCP listener that accepts and never says a word of SSH, so the connect would take its whole
10 s timeout), and while a demo robot's write waits for the robot's write lock (held here,
as another change on the robot would hold it). Each time it must end within 0.5 s with exit
130, say which robots finished and which were being written, keep the partial recap on a
terminal, and show no traceback; the file being written ends as its old or its new content.
"""

from __future__ import annotations

import fcntl
import re
import socket
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from .termrun import interrupted, plain

ANSWER_S = 0.5


class Silent:
    """A TCP listener on loopback that accepts every connection and never answers (an SSH
    server that hangs before its banner); ``accepted`` is set at the first connection."""

    def __init__(self) -> None:
        self.sock = socket.create_server(("127.0.0.1", 0))
        self.port = int(self.sock.getsockname()[1])
        self.accepted = threading.Event()
        self.conns: list[socket.socket] = []
        threading.Thread(target=self._serve, daemon=True).start()

    def _serve(self) -> None:
        while True:
            try:
                conn, _ = self.sock.accept()
            except OSError:  # closed: the test is over
                return
            self.conns.append(conn)
            self.accepted.set()

    def close(self) -> None:
        self.sock.close()
        for c in self.conns:
            c.close()


@pytest.fixture
def silent() -> Iterator[Silent]:
    s = Silent()
    yield s
    s.close()


@pytest.fixture
def fleet(demo: Path, silent: Silent) -> Path:
    """The demo fleet plus two robots behind the silent listener."""
    inv = demo / "inventory.yaml"
    text = inv.read_text()
    hanging = "".join(f"  hang-0{i}:\n    host: 127.0.0.1\n    port: {silent.port}\n" for i in (1, 2))
    inv.write_text(text.replace("robots:\n", "robots:\n" + hanging, 1))
    return demo


def _no_traceback(text: str) -> None:
    assert "Traceback" not in text and "internal error" not in text, text


def _in_connect(silent: Silent) -> bool:
    return silent.accepted.is_set()


def test_ctrl_c_while_robots_hang_in_connect_ends_at_once_with_the_partial_recap(fleet: Path,
                                                                                 silent: Silent) -> None:
    got = interrupted(["-i", str(fleet), "status", "--all"],  # the local robots done, the others hanging
                      lambda out: _in_connect(silent) and "4/6 robots done" in out)
    shown = plain(got.run.err)
    assert got.run.code == 130, shown
    assert got.after_s < ANSWER_S, f"{got.after_s:.2f} s after the SIGINT"
    _no_traceback(shown)
    assert "interrupted (Ctrl-C)" in shown
    assert re.search(r"finished: panther-01 \w+, panther-02 \w+, panther-03 \w+, panther-04 \w+", shown), shown
    assert "cut short: hang-01 (connect), hang-02 (connect)" in shown
    recap = shown[shown.index("recap (interrupted)"):]
    assert re.search(r"^hang-01\s+interrupted\s+connect \d+\.\d s", recap, re.M), recap
    assert re.search(r"^panther-01\s+ok\s+connect", recap, re.M), recap


def test_ctrl_c_in_connect_piped_says_where_each_robot_was(fleet: Path, silent: Silent) -> None:
    got = interrupted(["-i", str(fleet), "config", "set", "wheel_type", "WH04", "--all", "--yes"],
                      lambda _out: _in_connect(silent), on_terminal=False)
    assert got.run.code == 130, got.run.err
    assert got.after_s < ANSWER_S, f"{got.after_s:.2f} s after the SIGINT"
    _no_traceback(got.run.err + got.run.out)
    assert "interrupted (Ctrl-C): no new work was started" in got.run.err
    assert "hang-01 (connect)" in got.run.err and "hang-02 (connect)" in got.run.err
    for robot in ("panther-01", "panther-02", "panther-03"):  # planned, or waiting for the others' plans
        assert robot in got.run.err
    assert "\x1b[" not in got.run.err  # piped: no live view, no recap
    for robot in ("panther-01", "panther-02"):  # nothing was written anywhere
        assert not list((fleet / "robots" / robot / "home/husarion").glob(".panther-ops/backups/*/status"))


def _r01_changed_r02_waits(shown: str) -> bool:
    """After the plan (its diffs shown: the writes began), the live view: panther-01 changed and
    panther-02 in its write for 0.2 s or more (waiting for its lock). Under load panther-01 can
    still be writing when panther-02 has waited 0.2 s: the Ctrl-C waits for both."""
    _, plan, applying = shown.partition("\nplan: ")
    return bool(plan) and re.search(r"panther-02\s+write\s+(0\.[2-9]|[1-9]\d*\.\d) s\n1/2 robots done", applying) \
        is not None


def test_ctrl_c_during_a_write_ends_at_once_and_the_file_is_old_or_new(demo: Path) -> None:
    home = demo / "robots/panther-02/home/husarion"
    compose = home / "compose.yaml"
    before = compose.read_bytes()
    (home / ".panther-ops").mkdir(exist_ok=True)
    with open(home / ".panther-ops/write.lock", "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # another writer holds the robot's lock: the write waits
        got = interrupted(["-i", str(demo), "config", "set", "wheel_type", "WH04", "-r", "panther-01",
                           "-r", "panther-02", "--yes"],
                          _r01_changed_r02_waits)
        fcntl.flock(lock, fcntl.LOCK_UN)
    shown = plain(got.run.err)
    assert got.run.code == 130, shown
    assert got.after_s < ANSWER_S, f"{got.after_s:.2f} s after the SIGINT"
    _no_traceback(shown)
    assert "finished: panther-01 changed" in shown
    assert re.search(r"being written: panther-02 \(.*renamed into place.*old or .*new", shown, re.S), shown
    recap = shown[shown.index("recap (interrupted)"):]
    assert re.search(r"^panther-02\s+interrupted\s+.*write \d+\.\d s", recap, re.M), recap
    # the robot's side finishes on its own: the file is the old or the new, no staged copy left
    new = before.replace(b"namespace:=panther\n", b"namespace:=panther wheel_type:=WH04\n")
    assert new != before
    for _ in range(100):
        if not list(home.glob(".compose.yaml.panther-ops.*")):
            break
        time.sleep(0.05)
    assert not list(home.glob(".compose.yaml.panther-ops.*"))
    assert compose.read_bytes() in (before, new)


def test_ctrl_c_at_the_confirmation_says_nothing_was_written_and_exits_130(demo: Path) -> None:
    compose = demo / "robots/panther-01/home/husarion/compose.yaml"
    before = compose.read_bytes()
    got = interrupted(["-i", str(demo), "config", "set", "wheel_type", "WH04", "-r", "panther-01"],
                      lambda out: "[y/N]" in out, at_question=True)
    shown = plain(got.run.err)
    assert got.run.code == 130, shown
    assert got.after_s < ANSWER_S, f"{got.after_s:.2f} s after the SIGINT"
    _no_traceback(shown)
    assert "interrupted at the confirmation (Ctrl-C): nothing was changed (no robot written)" in shown, shown
    assert compose.read_bytes() == before
    assert not list(compose.parent.glob(".panther-ops/backups/*"))


def test_ctrl_c_in_gps_watch_between_refreshes_ends_at_once_with_the_recap(demo: Path) -> None:
    got = interrupted(["-i", str(demo), "gps", "watch", "--all", "--window", "0.5"],
                      lambda out: "refresh 2)" in out)
    shown = plain(got.run.out + got.run.err)
    assert got.run.code == 130, shown
    assert got.after_s < ANSWER_S, f"{got.after_s:.2f} s after the SIGINT"
    _no_traceback(shown)
    assert re.search(r"finished: panther-01 \w+, panther-02 \w+, panther-03 \w+", shown), shown
    recap = shown[shown.index("recap (interrupted)"):]
    for robot in ("panther-01", "panther-02", "panther-03"):
        assert re.search(rf"^{robot}\s+\w+\s+connect \d+\.\d s", recap, re.M), recap


def test_ctrl_c_in_gps_watch_during_a_refresh_says_where_each_robot_was(fleet: Path, silent: Silent) -> None:
    got = interrupted(["-i", str(fleet), "gps", "watch", "--all"], lambda _out: _in_connect(silent))
    shown = plain(got.run.out + got.run.err)
    assert got.run.code == 130, shown
    assert got.after_s < ANSWER_S, f"{got.after_s:.2f} s after the SIGINT"
    _no_traceback(shown)
    assert "cut short: hang-01 (connect), hang-02 (connect)" in shown, shown
    recap = shown[shown.index("recap (interrupted)"):]
    assert re.search(r"^hang-01\s+interrupted\s+connect \d+\.\d s", recap, re.M), recap
