"""Issue 25 on the lab: three husarion_ugv 2.2.2 robots (real sshd + dockerd + compose v2; the
driver is the lab's ros2 stand-in, whose 2.3.2 image the lab loads on every robot) customised
through panther-ops' own commands (`config set` of a controller limit, `config push` of the
gamepad file, components and user animations, `shutdown hosts add`), each robot with its own
values, are migrated with `driver update jazzy-2.3.2-... --all --canary 1`.

With the canary's 2.3.2 image removed, its new driver cannot start: the canary rolls back,
every file byte for byte, the 2.2.2 driver running again, and the two other robots are not
touched. With the image there the migration goes through: the canary first and alone (the
others' new drivers start after its own was up and verified), each customisation in its 2.3 form,
the files whose schema did not change byte-identical, a second run changes nothing, and
`driver update humble-2.2.2-...` restores each robot's migration backup byte for byte.

One lab (3 robots) for the module; each test leaves the robots as it found them."""

from __future__ import annotations

import contextlib
import io
import json
import re
from collections.abc import Iterator
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

import pytest
from ruamel.yaml import YAML

from panther_ops.cli.app import main
from panther_ops.core.fleet.readiness import MIN_STABLE_S
from tests.labtools import COMPOSE, containers, robots_put_back

pytestmark = pytest.mark.lab

HUMBLE_TAG = "humble-2.2.2-20250702"
HUMBLE = f"husarion/husarion-ugv:{HUMBLE_TAG}"
JAZZY_TAG = "jazzy-2.3.2-20260622"
JAZZY = f"husarion/husarion-ugv:{JAZZY_TAG}"
KEPT = "panther-ops-test/kept:jazzy"  # the canary's 2.3.2 image while its own tag is removed
CFG = "/home/husarion/config"
CONTROLLER = f"{CFG}/husarion_ugv_controller/config/WH01_controller.yaml"
JOY_22 = f"{CFG}/husarion_ugv_bringup/config/joy2twist_panther.yaml"
JOY_23 = f"{CFG}/husarion_ugv_teleop/config/joy2twist_panther.yaml"
COMPONENTS = f"{CFG}/husarion_ugv_description/config/components.yaml"
USER_ANIMATIONS = f"{CFG}/husarion_ugv_lights/config/user_animations.yaml"
SHUTDOWN_HOSTS = f"{CFG}/husarion_ugv_manager/config/shutdown_hosts.yaml"
TRANSLATED = {COMPOSE, CONTROLLER, f"{CFG}/husarion_ugv_controller/config/WH04_controller.yaml",
              f"{CFG}/husarion_ugv_localization/config/relative_localization.yaml", COMPONENTS}
"""The files of the lab's 2.2.2 tree whose schema 2.3.2 changed (besides the gamepad file, which moves);
every other file (user and stock animations, shutdown hosts, the Lights project and tree, .env) is
byte-identical after the migration."""
load = YAML(typ="safe", pure=True).load


@dataclass(frozen=True)
class Custom:
    """One robot's customisation: its own values, so that no robot can pass with another's file."""

    max_velocity: float
    fast: float
    lidar: str
    animation_id: int
    host: str


CUSTOM = (Custom(1.3, 0.8, "front_lidar", 21, "10.15.20.21"),
          Custom(1.5, 0.7, "rear_lidar", 22, "10.15.20.22"),
          Custom(1.1, 0.9, "top_lidar", 23, "10.15.20.23"))


def cli(*argv: str) -> dict[str, Any]:
    """`panther-ops --json ARGV` in-process; the JSON document (stdout), its exit code under "code"."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["-q", *argv, "--json"])
    doc: dict[str, Any] = json.loads(out.getvalue()) if out.getvalue().strip() else {}
    doc["code"], doc["stderr"] = code, err.getvalue()
    return doc


def ok(*argv: str) -> dict[str, Any]:
    doc = cli(*argv)
    assert doc["code"] == 0, doc
    return doc


def customise(lab: Any, name: str, c: Custom, work: Path) -> None:
    """The robot's customisation, through panther-ops' commands (no restart: the migration recreates)."""
    inv = ("-i", str(lab.inventory_path))
    put = ("-r", name, "--yes", "--no-restart")
    ok(*inv, "config", "set", "controller.linear.x.max_velocity", str(c.max_velocity), *put)
    joy = work / f"{name}-joy2twist.yaml"
    stock = lab.read(name, JOY_22)
    joy.write_text(re.sub(r"(?m)^(      fast: ).*$", rf"\g<1>{c.fast}", stock, count=1))
    assert joy.read_text() != stock
    ok(*inv, "config", "push", str(joy), "--as", "joy2twist", *put)
    comp = work / f"{name}-components.yaml"
    comp.write_text(f"components:\n  - type: LDR06\n    parent_link: cover_link\n    xyz: 0.0 0.0 0.1\n"
                    f"    rpy: 0.0 0.0 0.0\n    device_namespace: {c.lidar}\n")
    ok(*inv, "config", "push", str(comp), "--as", "components", *put)
    anim = work / f"{name}-user_animations.yaml"
    anim.write_text(f"# {name}'s animations\nuser_animations:\n  - id: {c.animation_id}\n    name: SITE_{name.upper()}\n"
                    "    priority: 2\n    animations:\n      - type: husarion_ugv_lights::ImageAnimation\n"
                    "        segments: all\n        animation:\n"
                    "          image: $(find husarion_ugv_lights)/animations/panther/ready_front.png\n"
                    "          duration: 2\n          repeat: 1\n")
    ok(*inv, "config", "push", str(anim), "--as", "user-animations", *put)
    ok(*inv, "shutdown", "hosts", "add", *put, "--ip", c.host, "--http", "--timeout", "8")


def files(lab: Any, name: str) -> dict[str, bytes]:
    """compose.yaml and every file of ~/config, by path."""
    listed = lab.sh(name, f"find {CFG} -type f | sort").stdout.split()
    return {p: lab.read_bytes(name, p) for p in [COMPOSE, *listed]}


def no_teleop_dir(lab: Any, name: str) -> bool:
    """The migration's husarion_ugv_teleop/ (2.3.2's gamepad file) is not left behind, not even empty."""
    return bool(lab.sh(name, f"test -e {CFG}/husarion_ugv_teleop && echo left || echo gone").stdout.strip() == "gone")


def driver(lab: Any, name: str) -> dict[str, Any]:
    return containers(lab, name)["husarion_ugv_ros"]


@dataclass
class Fleet:
    lab: Any
    names: list[str]
    before: dict[str, dict[str, bytes]]  # each robot's files once customised, on 2.2.2

    def update(self, tag: str, *more: str) -> dict[str, Any]:
        return cli("-i", str(self.lab.inventory_path), "driver", "update", tag, "--all", "--yes", "--settle", "2", *more)


@pytest.fixture(scope="module")
def fleet(lab_factory: Any, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Fleet]:
    """Three customised 2.2.2 robots of a lab of their own, shared by the module's tests."""
    lab = lab_factory(3, docker=True, images=("2.2",))
    names = [r.name for r in lab.robots]
    assert all(driver(lab, n)["image"] == HUMBLE for n in names)
    work = tmp_path_factory.mktemp("custom")
    with robots_put_back(lab, recreate=lambda _, compose_changed: compose_changed):
        for name, c in zip(names, CUSTOM, strict=True):
            customise(lab, name, c, work)
        yield Fleet(lab, names, {n: files(lab, n) for n in names})


@pytest.fixture
def put_back(fleet: Fleet) -> Iterator[Fleet]:
    """The fleet as the test found it afterwards, even when it fails half-way."""
    lab = fleet.lab
    with robots_put_back(lab, recreate=lambda name, _: driver(lab, name)["image"] != HUMBLE):
        yield fleet


def test_failing_canary_rolls_back_byte_for_byte_and_stops_the_fleet(put_back: Fleet) -> None:
    lab, (canary, *rest) = put_back.lab, put_back.names
    lab.docker(canary, "tag", JAZZY, KEPT, check=True)
    lab.docker(canary, "rmi", JAZZY, check=True)  # no 2.3.2 image on the canary: its new driver cannot start
    try:
        doc = put_back.update(JAZZY_TAG, "--canary", "1")
    finally:
        lab.docker(canary, "tag", KEPT, JAZZY, check=True)
        lab.docker(canary, "rmi", KEPT, check=True)
    assert doc["code"] == 3, doc
    res = {r["robot"]: r for r in doc["robots"]}
    assert res[canary]["outcome"] == "rolled-back" and "restored backup" in res[canary]["message"], res[canary]
    assert [res[n]["outcome"] for n in rest] == ["skipped"] * len(rest), doc
    for name in put_back.names:
        assert files(lab, name) == put_back.before[name], name
        assert no_teleop_dir(lab, name)
        ctr = driver(lab, name)
        assert (ctr["image"], ctr["state"]) == (HUMBLE, "running"), name


def started_at(lab: Any, name: str) -> str:
    return str(lab.docker(name, "inspect", "-f", "{{.State.StartedAt}}", "husarion_ugv_ros", check=True).stdout.strip())


def epoch(rfc3339: str) -> float:
    """docker's StartedAt (UTC, nanoseconds) as seconds since the epoch."""
    day, _, frac = rfc3339.rstrip("Z").partition(".")
    return datetime.strptime(day, "%Y-%m-%dT%H:%M:%S").replace(tzinfo=timezone.utc).timestamp() + float(f"0.{frac or 0}")


def assert_in_23_form(before: dict[str, bytes], after: dict[str, bytes], c: Custom) -> None:
    x = load(after[CONTROLLER])["/**"]["drive_controller"]["ros__parameters"]["linear"]["x"]
    assert (x["max_velocity"], x["min_velocity"]) == (c.max_velocity, -c.max_velocity)
    assert "has_velocity_limits" not in x and x["max_deceleration"] == -x["max_acceleration"]
    assert set(after) == set(before) - {JOY_22} | {JOY_23}
    joy = load(after[JOY_23])["/**"]["ros__parameters"]
    assert (joy["cmd_vel_topic"], joy["cmd_vel_stamped"], joy["linear_velocity_factor"]["fast"]) == \
        ("manual/cmd_vel", True, c.fast)
    (comp,) = load(after[COMPONENTS])["components"]
    assert comp["name"] == c.lidar and "device_namespace" not in comp
    assert comp["type"] == "LDR06" and comp["parent_link"] == "cover_link"
    changed = {p for p in before if p != JOY_22 and after[p] != before[p]}
    assert changed == TRANSLATED, changed ^ TRANSLATED  # the rest is byte-identical
    assert {USER_ANIMATIONS, SHUTDOWN_HOSTS} < set(before) - TRANSLATED
    assert f"id: {c.animation_id}" in after[USER_ANIMATIONS].decode()
    assert c.host in after[SHUTDOWN_HOSTS].decode()


def test_canary_migration_second_run_and_way_back(put_back: Fleet) -> None:
    lab, names, before = put_back.lab, put_back.names, put_back.before
    doc = put_back.update(JAZZY_TAG, "--canary", "1")
    assert doc["code"] == 0, doc
    res = {r["robot"]: r for r in doc["robots"]}
    for name in names:
        assert res[name]["outcome"] == "changed", res[name]
        assert res[name]["data"]["stack_to"] == "husarion_ugv 2.3.2", res[name]
    canary, *rest = names  # the canary first and alone: its new driver was up and verified before the others'
    up = {n: epoch(started_at(lab, n)) for n in names}  # one clock: the lab's robots share the host's kernel
    assert up[canary] + MIN_STABLE_S < min(up[n] for n in rest), up

    after = {n: files(lab, n) for n in names}
    for name, c in zip(names, CUSTOM, strict=True):
        assert_in_23_form(before[name], after[name], c)
        ctr = driver(lab, name)
        assert (ctr["image"], ctr["state"]) == (JAZZY, "running"), name

    running = {n: driver(lab, n)["id"] for n in names}
    again = put_back.update(JAZZY_TAG, "--canary", "1")
    assert again["code"] == 0 and [r["outcome"] for r in again["robots"]] == ["ok"] * len(names), again
    assert {n: files(lab, n) for n in names} == after
    assert {n: driver(lab, n)["id"] for n in names} == running  # not even recreated

    back = put_back.update(HUMBLE_TAG, "--canary", "1")
    assert back["code"] == 0, back
    for r in back["robots"]:
        assert r["outcome"] == "changed" and r["data"]["backup_restored"] == res[r["robot"]]["data"]["backup"], r
    for name in names:
        assert files(lab, name) == before[name], name
        assert no_teleop_dir(lab, name)
        ctr = driver(lab, name)
        assert (ctr["image"], ctr["state"]) == (HUMBLE, "running"), name
