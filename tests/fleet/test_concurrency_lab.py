"""Two and three operators change the same robots at the same moment: no update is lost.

Each operator is its own ``panther-ops`` process (as on two laptops), all started together
against the same 6 lab robots (stacks 2.1.1 and 2.2.2), each setting a different launch
argument with ``--all --yes --no-restart``. A robot's write compares the file with what its
plan read and renames under one lock on the robot (``flock``, see
``transport/scripts_apply.py``), so per robot: every run that reports ``changed`` has its
edit in the final compose.yaml, every run that does not reports ``failed`` with "changed on
the robot since it was read", and the file is never torn (it parses, one ``command:``).
"""

from __future__ import annotations

import json
import subprocess
import sys
from typing import Any

import pytest
import yaml

from tests.labtools import COMPOSE

pytestmark = pytest.mark.lab

TRIALS = 20
EDITS = (("wheel_type", "WH02"), ("use_ekf", "False"), ("disable_manager", "True"))


@pytest.fixture(scope="module")
def lab6(lab_factory: Any) -> Any:
    """6 robots, no docker (a --no-restart change needs none): 2.1.1 and 2.2.2 alternating."""
    return lab_factory(6, docker=False, images=("2.1.1", "2.2"))


def _driver_command(text: str) -> str:
    doc = yaml.safe_load(text)  # a torn file would not parse
    commands = [s["command"] for s in doc["services"].values() if isinstance(s, dict) and "command" in s]
    assert len(commands) >= 1
    return " ".join(c if isinstance(c, str) else " ".join(c) for c in commands)


@pytest.mark.parametrize("operators", [2, 3])
def test_concurrent_operators_lose_no_update(lab6: Any, operators: int) -> None:
    lab = lab6
    names = lab.names
    saved = {n: lab.read_bytes(n, COMPOSE) for n in names}
    edits = EDITS[:operators]
    conflicts = 0
    try:
        for trial in range(TRIALS):
            procs = [subprocess.Popen([sys.executable, "-m", "panther_ops.cli.app", "-i", str(lab.inventory_path),
                                       "config", "set", key, value, "--all", "--yes", "--no-restart", "--json"],
                                      stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
                     for key, value in edits]
            docs: list[dict[str, Any]] = []
            for p in procs:
                out, err = p.communicate(timeout=120)
                assert out.strip(), f"trial {trial}: no JSON (exit {p.returncode}): {err[-2000:]}"
                docs.append(json.loads(out))
            for name in names:
                final = _driver_command(lab.read(name, COMPOSE))
                for (key, value), doc in zip(edits, docs, strict=True):
                    res = next(r for r in doc["robots"] if r["robot"] == name)
                    if res["outcome"] == "changed":
                        assert f"{key}:={value}".lower() in final.lower(), (
                            f"trial {trial}, {name}: the run setting {key} said changed, but the final "
                            f"compose.yaml lacks it: {final}")
                    else:
                        assert res["outcome"] == "failed", (trial, name, res)
                        assert "changed on the robot since it was read" in res["message"], res
                        assert "re-run to apply on top" in res["message"], res
                        conflicts += 1
                leftovers = lab.sh(name, r"ls -A /home/husarion | grep -c '^\.compose\.yaml\.panther-ops\.' || true")
                assert leftovers.stdout.strip() == "0", f"trial {trial}, {name}: staged files left behind"
            for n in names:
                lab.write(n, COMPOSE, saved[n])
                lab.sh(n, "rm -rf /home/husarion/.panther-ops")
    finally:
        for n in names:
            lab.write(n, COMPOSE, saved[n])
            lab.sh(n, "rm -rf /home/husarion/.panther-ops")
    print(f"{operators} operators x {TRIALS} trials x {len(names)} robots: {conflicts} conflicts refused")


def test_a_rollback_never_overwrites_a_change_made_after_it(lab: Any) -> None:
    """Operator A's change fails its verify; while A watches the driver, operator B changes the
    same compose.yaml. A's rollback must not put A's old file back over B's change: it is
    refused, naming the file, and B's edit stays (before, the rollback wrote blindly)."""
    import os
    import signal
    import time

    from tests.labtools import robot_of, robots_put_back

    name = robot_of(lab, "2.1.1")
    inv = str(lab.inventory_path)
    with robots_put_back(lab):
        original = lab.read(name, COMPOSE)
        a = subprocess.Popen([sys.executable, "-m", "panther_ops.cli.app", "-i", inv, "config", "set",
                              "controller_config_path", "/nonexistent/controller.yaml", "-r", name, "--yes",
                              "--force", "--settle", "6", "--json"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True)
        deadline = time.monotonic() + 60
        while "/nonexistent/controller.yaml" not in lab.read(name, COMPOSE):
            assert a.poll() is None and time.monotonic() < deadline, "A's change never reached the robot"
            time.sleep(0.01)
        # A has written and is recreating the driver (a docker compose up on the robot takes a
        # second or more): A is held there, as a slow link would, while B writes, so B's change
        # comes between A's write and A's rollback whatever the machine's load
        os.kill(a.pid, signal.SIGSTOP)
        try:
            # --force: A's unmounted path is in the command B edits, which B would refuse otherwise
            b = subprocess.run([sys.executable, "-m", "panther_ops.cli.app", "-i", inv, "config", "set", "use_ekf",
                                "False", "-r", name, "--yes", "--no-restart", "--force", "--json"],
                               capture_output=True, text=True, timeout=120, check=False)
        finally:
            os.kill(a.pid, signal.SIGCONT)
        assert b.returncode == 0, b.stdout + b.stderr
        assert json.loads(b.stdout)["robots"][0]["outcome"] == "changed"
        out, _ = a.communicate(timeout=120)
        res = json.loads(out)["robots"][0]
        assert res["outcome"] == "failed", res
        assert "ROLLBACK REFUSED" in res["message"] and "compose.yaml changed on the robot" in res["message"], res
        final = lab.read(name, COMPOSE)
        assert "use_ekf:=False" in final, "B's change was overwritten by A's rollback"
        assert final != original
        staged = lab.sh(name, r"ls -A /home/husarion | grep -c '^\.compose\.yaml\.panther-ops\.' || true")
        assert staged.stdout.strip() == "0"
