"""Shared computations of one command: core.memo.Memo and transport.filecache.parsed."""

from __future__ import annotations

import os
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

from panther_ops.core.fleet.memo import Memo
from panther_ops.transport import filecache

THREADS = 8


class SlowCompute:
    """A computation that counts its runs and takes long enough for callers to overlap."""

    def __init__(self, delay: float = 0.2) -> None:
        self.delay = delay
        self.calls = 0
        self.running = 0
        self.most_at_once = 0
        self._lock = threading.Lock()

    def __call__(self, value: str) -> list[str]:
        with self._lock:
            self.calls += 1
            self.running += 1
            self.most_at_once = max(self.most_at_once, self.running)
        time.sleep(self.delay)
        with self._lock:
            self.running -= 1
        return [value]  # a fresh object per computation: identity shows sharing


def test_one_key_is_computed_once_by_concurrent_callers() -> None:
    memo: Memo[list[str]] = Memo()
    compute = SlowCompute()
    start = threading.Barrier(THREADS)

    def caller(_: int) -> list[str]:
        start.wait(timeout=10)
        return memo.get(("compose", b"same bytes"), lambda: compute("v"))

    with ThreadPoolExecutor(THREADS) as pool:
        values = list(pool.map(caller, range(THREADS)))

    assert compute.calls == 1
    assert memo.computed == 1
    assert all(v is values[0] for v in values), "every caller gets the one computed object"
    assert values[0] == ["v"]
    assert memo.get(("compose", b"same bytes"), lambda: compute("other")) is values[0]
    assert compute.calls == 1


def test_different_keys_are_computed_separately_and_in_parallel() -> None:
    memo: Memo[list[str]] = Memo()
    compute = SlowCompute()
    start = threading.Barrier(THREADS)
    inside = threading.Barrier(THREADS)  # only passable if all computations run at the same time

    def caller(i: int) -> list[str]:
        start.wait(timeout=10)

        def work() -> list[str]:
            inside.wait(timeout=10)
            return compute(f"v{i}")

        return memo.get(i, work)

    with ThreadPoolExecutor(THREADS) as pool:
        values = list(pool.map(caller, range(THREADS)))

    assert values == [[f"v{i}"] for i in range(THREADS)]
    assert compute.calls == THREADS
    assert memo.computed == THREADS
    assert compute.most_at_once > 1
    assert [memo.get(i, lambda: ["again"]) for i in range(THREADS)] == values, "all remembered"


def test_an_error_is_not_remembered() -> None:
    memo: Memo[str] = Memo()
    calls: list[int] = []

    def failing() -> str:
        calls.append(1)
        raise ValueError(f"boom {len(calls)}")

    with pytest.raises(ValueError, match="boom 1"):
        memo.get("k", failing)
    with pytest.raises(ValueError, match="boom 2"):
        memo.get("k", failing)
    assert len(calls) == 2, "the failure was computed again, not replayed"
    assert memo.get("k", lambda: "fine") == "fine"
    assert memo.get("k", failing) == "fine"
    assert len(calls) == 2
    assert memo.computed == 1, "only the successful computation counts"


def test_concurrent_callers_of_a_failing_key_each_get_their_own_error() -> None:
    memo: Memo[str] = Memo()
    calls: list[int] = []
    lock = threading.Lock()
    start = threading.Barrier(THREADS)

    def failing() -> str:
        with lock:
            calls.append(1)
            n = len(calls)
        time.sleep(0.05)
        raise RuntimeError(f"failure {n}")

    def caller(_: int) -> str:
        start.wait(timeout=10)
        try:
            return memo.get("k", failing)
        except RuntimeError as exc:
            return str(exc)

    with ThreadPoolExecutor(THREADS) as pool:
        messages = list(pool.map(caller, range(THREADS)))

    assert len(calls) == THREADS
    assert sorted(messages) == sorted(f"failure {n}" for n in range(1, THREADS + 1))
    assert memo.get("k", lambda: "recovered") == "recovered"


def test_the_size_bound_clears_the_memo() -> None:
    memo: Memo[str] = Memo(size=2)
    runs: list[str] = []

    def compute(key: str) -> str:
        runs.append(key)
        return key.upper()

    assert memo.get("a", lambda: compute("a")) == "A"
    assert memo.get("b", lambda: compute("b")) == "B"
    assert memo.get("a", lambda: compute("a")) == "A"
    assert runs == ["a", "b"]
    assert memo.get("c", lambda: compute("c")) == "C"  # full: cleared, then c stored
    assert memo.get("c", lambda: compute("c")) == "C"
    assert memo.get("a", lambda: compute("a")) == "A"
    assert memo.get("b", lambda: compute("b")) == "B"
    assert runs == ["a", "b", "c", "a", "b"]
    assert memo.computed == 5


def test_keys_compare_by_value() -> None:
    memo: Memo[int] = Memo()
    data = b"services: {}\n"
    assert memo.get(("k", bytes(data), 1), lambda: 1) == 1
    assert memo.get(("k", b"services: {}\n", 1), lambda: 2) == 1, "equal keys share"
    assert memo.get(("k", b"services: {} \n", 1), lambda: 3) == 3, "a different input is its own key"


# -- filecache.parsed ----------------------------------------------------------------


class CountingParser:
    def __init__(self) -> None:
        self.paths: list[str] = []

    def __call__(self, path: str) -> dict[str, str]:
        self.paths.append(path)
        return {"text": Path(path).read_text()}


def test_a_file_is_parsed_once_per_version(tmp_path: Path) -> None:
    f = tmp_path / "ssh_config"
    f.write_text("Host a\n")
    parse = CountingParser()
    first = filecache.parsed("ssh_config", str(f), parse)
    second = filecache.parsed("ssh_config", str(f), parse)
    assert first == {"text": "Host a\n"}
    assert second is first
    assert parse.paths == [str(f)]


@pytest.mark.parametrize(("new", "mtime_step"), [
    ("a ssh-ed25519 AAAA\nb ssh-ed25519 BBBB\n", 0),  # same mtime: only the size tells
    ("b ssh-ed25519 AAAA\n", 1_000_000_000),  # same size: only the mtime tells
])
def test_a_changed_file_is_parsed_again(tmp_path: Path, new: str, mtime_step: int) -> None:
    f = tmp_path / "known_hosts"
    f.write_text("a ssh-ed25519 AAAA\n")
    parse = CountingParser()
    assert filecache.parsed("known_hosts", str(f), parse) == {"text": "a ssh-ed25519 AAAA\n"}
    st = f.stat()
    f.write_text(new)
    os.utime(f, ns=(st.st_atime_ns, st.st_mtime_ns + mtime_step))
    assert filecache.parsed("known_hosts", str(f), parse) == {"text": new}
    assert filecache.parsed("known_hosts", str(f), parse) == {"text": new}
    assert len(parse.paths) == 2, "parsed once per version of the file"


def test_a_missing_file_is_none_and_not_parsed(tmp_path: Path) -> None:
    parse = CountingParser()
    missing = tmp_path / "nope"
    assert filecache.parsed("ssh_config", str(missing), parse) is None
    assert parse.paths == []
    missing.write_text("Host late\n")
    assert filecache.parsed("ssh_config", str(missing), parse) == {"text": "Host late\n"}, "not remembered as missing"
    missing.unlink()
    assert filecache.parsed("ssh_config", str(missing), parse) is None


def test_kinds_are_cached_apart(tmp_path: Path) -> None:
    f = tmp_path / "file"
    f.write_text("x\n")
    assert filecache.parsed("one", str(f), lambda p: "as one") == "as one"
    assert filecache.parsed("two", str(f), lambda p: "as two") == "as two"
    assert filecache.parsed("one", str(f), lambda p: "again") == "as one"


def test_concurrent_connections_parse_a_file_once(tmp_path: Path) -> None:
    """A fleet command's first connections start together (one per fork): they wait for one
    parse instead of each parsing the file (issue 29: at 300 robots and --forks 32, 32 threads
    parsed the 300-line known_hosts, paramiko's load is quadratic in its lines)."""
    f = tmp_path / "known_hosts"
    f.write_text("a ssh-ed25519 AAAA\n")
    parse = SlowCompute(delay=0.2)
    start = threading.Barrier(THREADS)

    def caller(_: int) -> list[str] | None:
        start.wait(timeout=10)
        return filecache.parsed("known_hosts", str(f), parse)

    with ThreadPoolExecutor(THREADS) as pool:
        values = list(pool.map(caller, range(THREADS)))

    assert parse.calls == 1
    assert all(v is values[0] for v in values), "every connection gets the one parsed object"
    assert values[0] == [str(f)]


def test_a_file_that_does_not_parse_is_parsed_again_and_leaves_nothing_behind(tmp_path: Path) -> None:
    f = tmp_path / "known_hosts"
    f.write_text("not a key\n")
    calls: list[str] = []

    def refuse(path: str) -> str:
        calls.append(path)
        raise ValueError(f"{path}: not a known_hosts line")

    for _ in range(2):
        with pytest.raises(ValueError, match="not a known_hosts line"):
            filecache.parsed("known_hosts-bad", str(f), refuse)
    assert len(calls) == 2, "a parse that raised is not remembered"
    assert not [k for k in filecache._parsing if k[0] == "known_hosts-bad"], "no per-version lock left behind"
