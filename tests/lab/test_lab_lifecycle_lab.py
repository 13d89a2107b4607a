"""The lab's own life cycle through its CLI, as an operator runs it (issue 29: a lab of hundreds).

`python -m tests.lab up 12 --no-docker --rtt 20`, panther-ops used against it, `down`: then
nothing of the lab is left on the machine: no network namespace (`ip netns list`), no link
(`ip link`), no process it started (the recorded PIDs, the delay relay, anything in its
namespaces), no directory. And after a crash that lost the state file, `down --prefix`
still finds and removes everything by the lab's names. The 300-robot run is a benchmark
(docs/lab.md), not part of CI.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.lab import DEFAULT_BASE
from tests.lab._sys import alive
from tests.lab.state import LabState
from tests.lab.teardown import host_links, netns_list  # `ip netns list`, `ip -o link show`

pytestmark = pytest.mark.lab

ROOT = Path(__file__).resolve().parents[2]


def lab_cli(*args: str, timeout: float = 120) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "tests.lab", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=timeout, check=False)


def panther_ops() -> str:
    beside = Path(sys.executable).with_name("panther-ops")
    found = str(beside) if beside.exists() else shutil.which("panther-ops")
    assert found, "the panther-ops console script is not installed"
    return found


def assert_nothing_left(prefix: str, procs: list[tuple[int, int | None]]) -> None:
    assert [n for n in netns_list() if n.startswith(prefix + "-")] == []
    assert [x for x in host_links() if x.startswith(prefix + "-")] == []
    assert [p for p in procs if alive(*p)] == []
    assert not (DEFAULT_BASE / prefix).exists()
    left = lab_cli("leftovers", "--prefix", prefix)
    assert left.returncode == 0 and left.stdout.strip() == "nothing left behind", left.stdout + left.stderr


def unique_prefix(tag: str) -> str:
    return f"{tag}{os.getpid() % 100000}"


def test_up_used_down_leaves_nothing_behind(lab_ready: None) -> None:
    prefix = unique_prefix("cy")
    try:
        up = lab_cli("up", "12", "--no-docker", "--rtt", "20", "--prefix", prefix)
        assert up.returncode == 0, up.stderr
        inventory = re.search(r"^inventory: (.+)$", up.stdout, flags=re.M)
        assert inventory is not None, up.stdout
        st = LabState.load(DEFAULT_BASE / prefix / "state.json")
        assert sorted(st.robots) == [f"r{i:02d}" for i in range(1, 13)]
        assert len({r.ip for r in st.robots.values()}) == 12
        relays = {p.key() for r in st.robots.values() for p in r.procs if p.role == "relay"}
        assert len(relays) == 1  # one delay relay process carries the 12 robots
        procs = [p.key() for r in st.robots.values() for p in r.procs]
        assert all(alive(*p) for p in procs)
        assert len([n for n in netns_list() if n.startswith(prefix + "-")]) == 12

        used = subprocess.run([panther_ops(), "-i", inventory.group(1), "config", "get", "wheel_type", "--all",
                               "--json"], capture_output=True, text=True, timeout=60, check=False)
        assert used.returncode == 0, used.stderr
        doc = json.loads(used.stdout)
        assert doc["summary"]["ok"] == 12
        assert {r["robot"]: r["data"]["value"] for r in doc["robots"]} == {n: "WH01" for n in st.robots}

        down = lab_cli("down", "--prefix", prefix)
        assert down.returncode == 0, down.stderr
        assert_nothing_left(prefix, procs)
    finally:
        lab_cli("down", "--prefix", prefix)


def test_down_by_name_after_the_state_file_is_lost(lab_ready: None) -> None:
    prefix = unique_prefix("cz")
    try:
        up = lab_cli("up", "4", "--no-docker", "--rtt", "20", "--prefix", prefix)
        assert up.returncode == 0, up.stderr
        state = DEFAULT_BASE / prefix / "state.json"
        procs = [p.key() for r in LabState.load(state).robots.values() for p in r.procs]
        state.unlink()  # as after a crash before anything was recorded
        left = lab_cli("leftovers", "--prefix", prefix)
        assert left.returncode == 1
        assert f"{prefix}: network namespace {prefix}-r01" in left.stdout
        assert "runs a program of the lab" in left.stdout  # the relay, outside the namespaces
        down = lab_cli("down", "--prefix", prefix)
        assert down.returncode == 0, down.stderr
        assert "removed by name" in down.stderr
        assert_nothing_left(prefix, procs)
    finally:
        lab_cli("down", "--prefix", prefix)
