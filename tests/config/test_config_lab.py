"""Issue-3 acceptance on the lab: config set / push / pull / rollback / apply on real
sshd + dockerd + compose v2 robots (the driver is the lab's ros2 stand-in)."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml

from panther_ops.core.config.read import read_and_plan_args
from panther_ops.core.fleet.changes import apply_fleet, plan_fleet
from panther_ops.core.fleet.inventory_file import load_inventory
from panther_ops.core.fleet.pipeline import ApplyOptions
from panther_ops.core.fleet.runner import Connections, RunOptions
from tests.clirun import run_cli
from tests.labtools import COMPOSE, robot_of, robots_put_back

pytestmark = pytest.mark.lab


def driver_cmd(lab: Any, name: str) -> list[str]:
    r = lab.robot(name)
    out = lab.docker(name, "inspect", "-f", "{{json .Config.Cmd}}", r.driver_container, check=True).stdout
    return list(json.loads(out))


def driver_state(lab: Any, name: str) -> dict[str, Any]:
    r = lab.robot(name)
    out = lab.docker(name, "inspect", "-f", "{{json .}}", r.driver_container, check=True).stdout
    return dict(json.loads(out))


@pytest.fixture
def pristine(lab: Any) -> Iterator[None]:
    """Put every robot back as it was: compose.yaml, ~/config, backups, running stack."""
    with robots_put_back(lab):
        yield


def changed_lines(before: str, after: str) -> list[tuple[str, str]]:
    a, b = before.splitlines(), after.splitlines()
    assert len(a) == len(b)
    return [(x, y) for x, y in zip(a, b, strict=True) if x != y]


@pytest.mark.parametrize("version", ["2.1.1", "2.2.2"])
def test_set_wheel_type_recreates_and_second_run_is_ok(lab: Any, pristine: None, version: str,
                                                        capsys: pytest.CaptureFixture[str]) -> None:
    name = robot_of(lab, version)
    before = lab.read(name, COMPOSE)
    code, doc, _, _ = run_cli(capsys, "-i", str(lab.inventory_path), "config", "set", "wheel_type", "WH02",
                              "-r", name, "--yes", "--settle", "2", "--json")
    assert code == 0, doc
    assert doc["robots"][0]["outcome"] == "changed"
    after = lab.read(name, COMPOSE)
    (old, new), = changed_lines(before, after)
    assert old.strip().startswith("command:") and new == old + " wheel_type:=WH02"
    assert "wheel_type:=WH02" in driver_cmd(lab, name)
    assert driver_state(lab, name)["State"]["Status"] == "running"
    code, doc, _, _ = run_cli(capsys, "-i", str(lab.inventory_path), "config", "set", "wheel_type", "WH02",
                              "-r", name, "--yes", "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "ok"
    assert "already WH02" in doc["robots"][0]["message"]
    assert lab.read(name, COMPOSE) == after


def test_one_connection_per_robot(lab: Any, pristine: None, capsys: pytest.CaptureFixture[str]) -> None:
    """Each robot's sshd sees exactly one TCP connection and one login for a whole change."""
    direct = [r.name for r in lab.robots if not r.jump]
    conns = {n: lab.sshd_connections(n) for n in direct}
    logins = {n: lab.sshd_accepts(n) for n in direct}
    code, doc, _, _ = run_cli(capsys, "-i", str(lab.inventory_path), "config", "set", "wheel_type", "WH04",
                              *[a for n in direct for a in ("-r", n)], "--yes", "--no-restart", "--json")
    assert code == 0, doc
    assert {r["outcome"] for r in doc["robots"]} == {"changed"}
    for n in direct:
        assert lab.sshd_connections(n) - conns[n] == 1, n
        assert lab.sshd_accepts(n) - logins[n] == 1, n


def test_dry_run_prints_the_diff_and_writes_nothing(lab: Any, pristine: None,
                                                    capsys: pytest.CaptureFixture[str]) -> None:
    name = robot_of(lab, "2.1.1")
    before = lab.read_bytes(name, COMPOSE)
    mtime = lab.sh(name, f"stat -c %Y.%i {COMPOSE}").stdout
    code, _, out, _ = run_cli(capsys, "-i", str(lab.inventory_path), "config", "set", "wheel_type", "WH04",
                              "-r", name, "--dry-run")
    assert code == 0
    assert "+++ b/home/husarion/compose.yaml" in out and "wheel_type:=WH04" in out
    assert lab.read_bytes(name, COMPOSE) == before
    assert lab.sh(name, f"stat -c %Y.%i {COMPOSE}").stdout == mtime
    assert lab.sh(name, "ls -A /home/husarion/.panther-ops 2>/dev/null | wc -l").stdout.strip() == "0"


def test_bad_values_exit_2_and_touch_nothing(lab: Any, pristine: None, capsys: pytest.CaptureFixture[str]) -> None:
    before = {r.name: lab.read_bytes(r.name, COMPOSE) for r in lab.robots}
    code, _, _, err = run_cli(capsys, "-i", str(lab.inventory_path), "config", "set", "wheel_type", "WH03",
                              "--all", "--yes")
    assert code == 2
    assert "WH01, WH02, WH04, custom" in err
    wh01 = robot_of(lab, "2.0.4")  # default wheel type WH01
    code, _, _, err = run_cli(capsys, "-i", str(lab.inventory_path), "config", "set",
                              "controller.linear.x.max_velocity", "5.0", "-r", wh01, "--yes")
    assert code == 2
    assert "limit of 2.0 m/s" in err
    assert {r.name: lab.read_bytes(r.name, COMPOSE) for r in lab.robots} == before


def test_push_and_pull_controller_on_21(lab: Any, pristine: None, tmp_path: Path,
                                        capsys: pytest.CaptureFixture[str]) -> None:
    name = robot_of(lab, "2.1.1")
    mine = tmp_path / "my_controller.yaml"
    mine.write_text("# mine\n/**:\n  drive_controller:\n    ros__parameters:\n      linear:\n        x:\n"
                    "          max_velocity: 0.8 # slow indoors\n")
    code, doc, _, _ = run_cli(capsys, "-i", str(lab.inventory_path), "config", "push", str(mine), "--as",
                              "controller", "-r", name, "--yes", "--settle", "2", "--json")
    assert code == 0, doc
    robot_path = "/home/husarion/config/panther_controller/config/my_controller.yaml"
    assert lab.read_bytes(name, robot_path) == mine.read_bytes()
    state = driver_state(lab, name)
    mounts = {m["Destination"]: m["Source"] for m in state["Mounts"]}
    assert mounts["/config/panther_controller/config/my_controller.yaml"] == robot_path
    assert "controller_config_path:=/config/panther_controller/config/my_controller.yaml" in state["Config"]["Cmd"]
    assert state["State"]["Status"] == "running"
    out_file = tmp_path / "pulled.yaml"
    code, _, _, _ = run_cli(capsys, "-i", str(lab.inventory_path), "config", "pull", "controller", "-r", name,
                            "-o", str(out_file))
    assert code == 0
    assert out_file.read_bytes() == mine.read_bytes()


def test_failing_change_is_rolled_back_and_history_rollback(lab: Any, pristine: None,
                                                            capsys: pytest.CaptureFixture[str]) -> None:
    name = robot_of(lab, "2.1.1")
    inv = str(lab.inventory_path)
    original = lab.read_bytes(name, COMPOSE)
    code, doc, _, _ = run_cli(capsys, "-i", inv, "config", "set", "wheel_type", "WH04", "-r", name, "--yes",
                              "--settle", "2", "--json")
    assert code == 0, doc
    first_backup = doc["robots"][0]["data"]["backup"]
    good = lab.read_bytes(name, COMPOSE)
    good_cmd = driver_cmd(lab, name)
    code, doc, _, _ = run_cli(capsys, "-i", inv, "config", "set", "controller_config_path",
                              "/nonexistent/controller.yaml", "-r", name, "--yes", "--force", "--settle", "3",
                              "--json")
    assert code == 3, doc
    res = doc["robots"][0]
    assert res["outcome"] == "rolled-back", res
    assert lab.read_bytes(name, COMPOSE) == good
    assert driver_cmd(lab, name) == good_cmd
    assert driver_state(lab, name)["State"]["Status"] == "running"
    code, doc, _, _ = run_cli(capsys, "-i", inv, "config", "history", "-r", name, "--json")
    entries = doc["robots"][0]["data"]["history"]
    assert [e["status"].split(":")[0] for e in entries] == ["applied", "rolled-back"]
    assert entries[0]["id"] == first_backup
    code, doc, _, _ = run_cli(capsys, "-i", inv, "config", "rollback", "--to", first_backup, "-r", name, "--yes",
                              "--settle", "2", "--json")
    assert code == 0, doc
    assert lab.read_bytes(name, COMPOSE) == original
    assert "wheel_type:=WH04" not in driver_cmd(lab, name)


@pytest.mark.parametrize("early", [False, True], ids=["staged-after-confirmation", "staged-while-planning"])
def test_sshd_killed_between_upload_and_rename(lab: Any, pristine: None, early: bool) -> None:
    inv = load_inventory(str(lab.inventory_path))
    robots = list(inv.robots.values())
    victim = robots[2].name
    lab.sh(victim, "rm -f /home/husarion/.compose.yaml.panther-ops.*")  # a killed session's leftover (earlier case)
    before = {r.name: lab.read_bytes(r.name, COMPOSE) for r in robots}
    reached: list[str] = []

    def on_staged(name: str) -> None:
        if name == victim:
            staged = lab.sh(victim, r"ls -A /home/husarion | grep -c '^\.compose\.yaml\.panther-ops\.'").stdout.strip()
            reached.append(staged)
            lab.kill_sshd_and_sessions(victim)

    opts = RunOptions(forks=5)
    apply = ApplyOptions(restart=False, command="t", on_staged=on_staged)
    try:
        with Connections(inv) as conns:
            fp = plan_fleet("t", inv, robots, lambda c: read_and_plan_args(c, {"wheel_type": "WH04"}, []), conns, opts,
                            stage=apply if early else None)
            assert not fp.usage_errors and len(fp.to_change) == 5
            assert len(fp.staged) == (5 if early else 0)
            result = apply_fleet(fp, inv, robots, conns, opts, apply)
    finally:
        lab.start_sshd(victim)
    assert reached == ["1"], "the victim's new compose.yaml was uploaded (staged) before sshd died"
    by = {r.robot: r for r in result.results}
    assert by[victim].outcome.value == "unreachable"
    assert all(by[r.name].outcome.value == "changed" for r in robots if r.name != victim)
    assert int(result.exit_code) == 3
    assert lab.read_bytes(victim, COMPOSE) == before[victim]
    for r in robots:
        if r.name != victim:
            assert b"wheel_type:=WH04" in lab.read_bytes(r.name, COMPOSE)


def test_apply_converges_drift(lab: Any, pristine: None, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    doc = yaml.safe_load(Path(lab.inventory_path).read_text())
    base = Path(lab.inventory_path).parent
    doc["settings"] = {k: str(base / v) for k, v in doc["settings"].items()}
    doc["defaults"]["identity_file"] = str(base / doc["defaults"]["identity_file"])
    targets = [r.name for r in lab.robots if not r.jump][:3]
    for n in targets:
        doc["robots"][n]["desired"] = {"launch_args": {"wheel_type": "WH02"},
                                       "controller": {"linear.x.max_velocity": 1.0}}
    inv = tmp_path / "inventory.yaml"
    inv.write_text(yaml.safe_dump(doc))
    sel = [a for n in targets for a in ("-r", n)]
    code, out, _, _ = run_cli(capsys, "-i", str(inv), "config", "diff", *sel, "--json")
    assert code == 0 and [r["outcome"] for r in out["robots"]] == ["changed"] * 3
    code, out, _, _ = run_cli(capsys, "-i", str(inv), "apply", *sel, "--yes", "--settle", "2", "--json")
    assert code == 0, out
    assert [r["outcome"] for r in out["robots"]] == ["changed"] * 3
    for n in targets:
        assert "wheel_type:=WH02" in driver_cmd(lab, n)
    code, out, _, _ = run_cli(capsys, "-i", str(inv), "config", "diff", *sel, "--json")
    assert code == 0 and [r["outcome"] for r in out["robots"]] == ["ok"] * 3
    assert all(r["message"] == "matches the inventory's desired state" for r in out["robots"])


def test_compose_refused_by_docker_compose_is_not_written(lab: Any, pristine: None) -> None:
    """Validate before writing: the robot's own `docker compose config` checks the staged file."""
    from panther_ops.core.fleet.plan import FileEdit, RobotPlan
    from panther_ops.core.robot.read import read_config

    name = robot_of(lab, "2.1.1")
    inv = load_inventory(str(lab.inventory_path))
    robots = [inv.robots[name]]
    before = lab.read_bytes(name, COMPOSE)

    def planner(ctx: Any) -> RobotPlan:
        cfg = read_config(ctx)
        broken = cfg.before.replace(b"container_name: panther_ros", b"container_nam: panther_ros")
        return RobotPlan(name, "break it", [FileEdit(cfg.compose_path, cfg.before, broken)], (cfg.service,),
                         cfg.compose_path)

    opts = RunOptions(forks=1)
    with Connections(inv) as conns:
        fp = plan_fleet("t", inv, robots, planner, conns, opts)
        result = apply_fleet(fp, inv, robots, conns, opts, ApplyOptions(command="t"))
    res = result.results[0]
    assert res.outcome.value == "failed"
    assert "docker compose refuses" in res.message and "nothing written" in res.message
    assert lab.read_bytes(name, COMPOSE) == before
    leftovers = lab.sh(name, r"ls -A /home/husarion | grep -c '^\.compose\.yaml\.panther-ops\.' || true")
    assert leftovers.stdout.strip() == "0"
