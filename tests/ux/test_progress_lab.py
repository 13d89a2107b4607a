"""Live per-robot progress of a fleet change (issue 16, finding 11), on a 30-robot lab with
docker: phases on a pseudo-terminal, nothing but the table (or JSON) when piped."""

from __future__ import annotations

import json
import os
import re
from collections.abc import Iterator
from typing import Any

import pytest

from .termrun import on_pty, piped, plain

pytestmark = pytest.mark.lab

COMPOSE = "/home/husarion/compose.yaml"
SIZE = int(os.environ.get("PANTHER_OPS_PROGRESS_ROBOTS", "30"))


@pytest.fixture(scope="module")
def fleet(lab_factory: Any) -> Iterator[Any]:
    lab = lab_factory(SIZE, docker=True)
    saved = {r.name: lab.read(r.name, COMPOSE) for r in lab.robots}
    yield lab
    for r in lab.robots:
        lab.write(r.name, COMPOSE, saved[r.name])
        lab.sh(r.name, "rm -rf /home/husarion/.panther-ops; true")


def _set(lab: Any, wheel: str, *extra: str) -> list[str]:
    return ["-i", str(lab.inventory_path), "config", "set", "wheel_type", wheel, "--all", "--yes",
            "--settle", "1", *extra]


def test_a_fleet_change_shows_live_phases_and_a_recap_on_a_terminal(fleet: Any) -> None:
    names = [r.name for r in fleet.robots]
    run = on_pty(_set(fleet, "WH02"), cols=120, stdout_pipe=True)
    assert run.code == 0, run.out + run.err
    live = plain(run.out)  # stderr, on the terminal
    # the live view: robots in their phases, redrawn (cursor movement) as they change
    assert "\x1b[" in run.out and "\x1b[2K" in run.out
    for phase in ("plan", "write", "recreate", "verify"):
        assert re.search(rf"^r\d\d\s+{phase}\s+\d+\.\d s", live, re.M), phase
    assert f"{SIZE}/{SIZE} robots done" in live
    # the recap: one line per robot with its result and the time of each phase
    recap = live[live.index("recap\n"):].splitlines()[1:]
    rows = {line.split()[0]: line for line in recap if line.split() and line.split()[0] in names}
    assert set(rows) == set(names)
    assert all(" changed " in row and "recreate " in row and "verify " in row for row in rows.values())
    assert all(row.count(f"{phase} ") == 1 for row in rows.values() for phase in ("connect", "write"))
    # stdout (piped here) carries the table only
    assert all(n in run.err for n in names) and "recap" not in run.err and "verify" not in run.err


def test_piped_there_is_nothing_but_the_table(fleet: Any) -> None:
    run = piped(_set(fleet, "WH04"))
    assert run.code == 0, run.err
    assert "\x1b[" not in run.out + run.err
    assert "recap" not in run.out + run.err
    assert not re.search(r"(connect|plan|write|recreate|verify)\s+\d+\.\d s", run.out + run.err)
    assert run.out.count(" changed ") == SIZE  # the table: one row per robot
    assert f"{SIZE} robots: {SIZE} changed" in run.err


def test_json_and_quiet_show_no_progress_on_a_terminal(fleet: Any) -> None:
    run = on_pty(_set(fleet, "WH02", "--json"), cols=120, stdout_pipe=True)
    assert run.code == 0
    assert json.loads(run.err)["summary"]["changed"] == SIZE  # stdout: the one document
    assert "recap" not in plain(run.out) and "robots done" not in plain(run.out)
    run = on_pty(["-q", *_set(fleet, "WH04")], cols=120, stdout_pipe=True)
    assert run.code == 0
    assert "recap" not in plain(run.out) and "robots done" not in plain(run.out)
