"""Issue-29 item 4 on the lab: the default path (recreate + verify) waits for the driver to be
ready, not for ``--settle``.

10 robots with docker (stacks 2.1.1 and 2.2.2 alternating): `config set wheel_type WH02 --all
--yes` with ``--settle 20`` finishes well before 20 s, every driver recreated and running the
new command; a driver that exits after docker started it (the ros2 stand-in refuses a
``controller_config_path:=`` that does not exist, as the real launch does) is still rolled
back, also with the long ``--settle``.
"""

from __future__ import annotations

import time
from typing import Any

import pytest

from panther_ops.core.fleet.readiness import MIN_STABLE_S
from tests.clirun import run_cli
from tests.labtools import containers, robots_put_back

pytestmark = pytest.mark.lab

FLEET = 10
SETTLE = "20"


@pytest.fixture(scope="module")
def lab10(lab_factory: Any) -> Any:
    return lab_factory(FLEET, docker=True, images=("2.1.1", "2.2"))


def driver(lab: Any, name: str) -> dict[str, Any]:
    return containers(lab, name)[lab.robot(name).driver_container]


def test_ready_drivers_finish_before_settle(lab10: Any, capsys: pytest.CaptureFixture[str]) -> None:
    lab = lab10
    with robots_put_back(lab):
        started = time.monotonic()
        code, doc, _, _ = run_cli(capsys, "-i", str(lab.inventory_path), "config", "set", "wheel_type", "WH02",
                                  "--all", "--yes", "--settle", SETTLE, "--json")
        wall = time.monotonic() - started
        assert code == 0, doc
        assert [r["outcome"] for r in doc["robots"]] == ["changed"] * FLEET, doc
        for r in lab.robots:
            d = driver(lab, r.name)
            assert d["state"] == "running" and d["restarts"] == 0, (r.name, d)
            assert any("WH02" in w for w in d["cmd"]), (r.name, d["cmd"])
        # each robot was watched for at least the window, and none for --settle
        assert MIN_STABLE_S <= wall < float(SETTLE), wall


def test_a_driver_that_exits_after_starting_is_rolled_back(lab10: Any,
                                                           capsys: pytest.CaptureFixture[str]) -> None:
    lab = lab10
    name = lab.robots[0].name
    with robots_put_back(lab):
        before = driver(lab, name)["cmd"]
        started = time.monotonic()
        code, doc, _, _ = run_cli(capsys, "-i", str(lab.inventory_path), "config", "set", "controller_config_path",
                                  "/nonexistent/controller.yaml", "-r", name, "--yes", "--force",
                                  "--settle", SETTLE, "--json")
        wall = time.monotonic() - started
        assert code == 3, doc
        res = doc["robots"][0]
        assert res["outcome"] == "rolled-back", res
        assert "after recreate" in res["message"], res
        after = driver(lab, name)
        assert after["cmd"] == before and after["state"] == "running", after
        assert wall < float(SETTLE), wall
