"""`manager deploy|remove|status` planning and applying on local (demo-style) robots: the
compose edits on the three real-shaped templates, the uploaded files, the archive, idempotence,
the exact revert, and the on-robot entry point (`python3 -m panther_ops.manager`)."""

from __future__ import annotations

import io
import json
import shutil
import subprocess
import sys
import zipfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml

from panther_ops.cli.app import main
from panther_ops.core.fleet.inventory import Inventory
from panther_ops.core.fleet.inventory_file import load_inventory
from panther_ops.core.fleet.pipeline import ApplyOptions, apply_plan
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import Connections, RobotContext
from panther_ops.core.fleet.templates import template_path
from panther_ops.core.manager_ops import bundle as manager_bundle
from panther_ops.core.manager_ops.bundle import ARCHIVE_NAME, ManagerBundle, build_bundle, bundle_build
from panther_ops.core.manager_ops.read import read_and_plan_deploy, read_and_plan_remove
from panther_ops.core.manager_ops.settings import DBUS_POWEROFF, SERVICE, SSH_POWEROFF, manager_settings
from panther_ops.core.manager_ops.status import describe, running_version, status_task
from panther_ops.errors import UsageError
from panther_ops.manager.__main__ import main as manager_main
from panther_ops.manager.__main__ import resolve_find
from panther_ops.manager.config import load_manager_config
from panther_ops.results import Outcome

HOME = "/home/husarion"
ROOT = f"{HOME}/panther-ops/manager"

#: template -> (driver service, command line before, command line after, hosts file, localhost command)
CASES = {
    "panther-2.0.4.yaml": (
        "panther_ros",
        "    command: ros2 launch panther_bringup bringup.launch.py namespace:=panther",
        "    command: ros2 launch panther_bringup bringup.launch.py namespace:=panther disable_manager:=True",
        "$(find panther_bringup)/config/shutdown_hosts.yaml",
        SSH_POWEROFF,
    ),
    "panther-2.1.1.yaml": (
        "panther_ros",
        "    command: ros2 launch panther_bringup bringup.launch.py",
        "    command: ros2 launch panther_bringup bringup.launch.py disable_manager:=True",
        "$(find panther_manager)/config/shutdown_hosts_config.yaml",
        SSH_POWEROFF,
    ),
    "husarion-ugv-2.2.2.yaml": (
        "husarion_ugv_ros",
        "    command: ros2 launch husarion_ugv_bringup bringup.launch.py common_dir_path:=/config launch_gamepad:=true",
        "    command: ros2 launch husarion_ugv_bringup bringup.launch.py common_dir_path:=/config launch_gamepad:=true"
        " disable_manager:=true",
        "/config/husarion_ugv_manager/config/shutdown_hosts.yaml",
        DBUS_POWEROFF,
    ),
}


def make_fleet(tmp: Path, robots: dict[str, tuple[str, dict[str, Any]]]) -> Inventory:
    """Local robots, each with one compose template (and desired: settings)."""
    lines = ["robots:"]
    for name, (template, desired) in robots.items():
        home = tmp / "robots" / name / "home" / "husarion"
        home.mkdir(parents=True)
        shutil.copy(template_path("compose", template), home / "compose.yaml")
        if template.startswith("husarion-ugv"):
            hosts = home / "config" / "husarion_ugv_manager" / "config" / "shutdown_hosts.yaml"
            hosts.parent.mkdir(parents=True)
            hosts.write_text("hosts: []\n")
        entry = {"transport": "local", "root": f"robots/{name}"}
        if desired:
            entry["desired"] = desired
        lines.append(f"  {name}: {json.dumps(entry)}")
    (tmp / "inv.yaml").write_text("\n".join(lines) + "\n")
    return load_inventory(str(tmp / "inv.yaml"))


@pytest.fixture
def ctxs(tmp_path: Path) -> Iterator[tuple[Path, dict[str, RobotContext]]]:
    inv = make_fleet(tmp_path, {"r20": ("panther-2.0.4.yaml", {}), "r21": ("panther-2.1.1.yaml", {}),
                                "r22": ("husarion-ugv-2.2.2.yaml", {})})
    with Connections(inv) as conns:
        yield tmp_path, {n: RobotContext(r, conns.get(r), inv) for n, r in inv.robots.items()}


def rfile(tmp: Path, robot: str, path: str) -> Path:
    return tmp / "robots" / robot / path.lstrip("/")


def apply(ctx: RobotContext, plan: RobotPlan) -> Any:
    return apply_plan(ctx, plan, ApplyOptions(settle_s=0))


TEMPLATE_ROBOT = {"panther-2.0.4.yaml": "r20", "panther-2.1.1.yaml": "r21", "husarion-ugv-2.2.2.yaml": "r22"}


# ------------------------------------------------------------------ the archive


def test_archive_is_reproducible_and_pure_python() -> None:
    first = build_bundle()
    build_bundle.cache_clear()
    again = build_bundle()
    assert again.data == first.data and again.version == first.version
    names = set(first.members)
    assert {"__main__.py", "panther_ops/__init__.py", "panther_ops/manager/__main__.py",
            "panther_ops/manager/runtime.py", "py_trees/__init__.py", "pydot/__init__.py",
            "pyparsing/__init__.py", "yaml/__init__.py"} <= names
    assert not [n for n in names if n.endswith((".so", ".pyc")) or "__pycache__" in n]
    assert not [n for n in names if n.startswith(("panther_ops/cli", "panther_ops/core", "PIL", "paramiko"))]
    assert bundle_build(first.data) == first.build and first.version.endswith("-" + first.build)
    with zipfile.ZipFile(io.BytesIO(first.data)) as zf:
        assert {i.compress_type for i in zf.infolist()} == {zipfile.ZIP_STORED}
        assert f'__build__ = "{first.build}"' in zf.read("panther_ops/__init__.py").decode()
    assert set(first.dependencies) == {"py_trees", "pydot", "pyparsing", "PyYAML"}


def _python310() -> str | None:
    for cand in sorted(Path("/root/.pyenv/versions").glob("3.10.*/bin/python3.10")):
        return str(cand)
    return shutil.which("python3.10")


def test_archive_runs_alone_on_python_310(tmp_path: Path) -> None:
    py = _python310()
    if py is None:
        pytest.skip("no Python 3.10 on this machine")
    pyz = tmp_path / ARCHIVE_NAME
    pyz.write_bytes(build_bundle().data)
    bt = template_path("behavior_trees")
    cp = subprocess.run([py, "-I", str(pyz), "--check", "--sim",
                         "--scenario", str(template_path("manager", "scenarios", "battery_overheat.yaml")),
                         "--lights-bt", str(bt / "PantherLightsBT.btproj"),
                         "--safety-bt", str(bt / "PantherSafetyBT.btproj")],
                        capture_output=True, text=True, timeout=60, cwd=tmp_path, check=False)
    assert cp.returncode == 0, cp.stderr
    assert "check ok (simulation mode" in cp.stdout and "Python 3.10." in cp.stdout
    assert f"({pyz}," in cp.stdout  # everything came from the archive (-I: no site-packages)


# ------------------------------------------------------------------ deploy plans on the templates


STACKS = {"panther-2.0.4.yaml": "2.0.4", "panther-2.1.1.yaml": "2.1.1", "husarion-ugv-2.2.2.yaml": "2.2.2"}
STOCK_BT = {  # issue 24: the release's own stock projects (templates/config/<generation>/<pkg>/behavior_trees)
    "panther-2.0.4.yaml": ("panther-2.0/panther_manager", "Panther"),
    "panther-2.1.1.yaml": ("panther-2.1/panther_manager", "Panther"),
    "husarion-ugv-2.2.2.yaml": ("husarion-ugv-2.2/husarion_ugv_manager", ""),
}


@pytest.mark.parametrize("template", list(CASES))
def test_deploy_adds_the_service_and_sets_disable_manager(ctxs: Any, template: str) -> None:
    tmp, cs = ctxs
    name = TEMPLATE_ROBOT[template]
    driver, old_cmd, new_cmd, hosts, poweroff = CASES[template]
    bundle = build_bundle()
    before = rfile(tmp, name, f"{HOME}/compose.yaml").read_text()
    plan = read_and_plan_deploy(cs[name])
    assert plan.recreate == (driver, SERVICE)
    assert [v.service for v in plan.verify] == [driver, SERVICE]
    assert plan.verify[0].cmd_contains == (new_cmd.rsplit(" ", 1)[1],)
    paths = [e.path for e in plan.edits]
    assert paths[0] == f"{HOME}/compose.yaml"
    stock_dir, prefix = STOCK_BT[template]
    projects = (f"{prefix}LightsBT.btproj", "lights.xml", f"{prefix}SafetyBT.btproj", "safety.xml", "shutdown.xml")
    assert set(paths[1:]) == {f"{ROOT}/{bundle.version}/{ARCHIVE_NAME}", f"{ROOT}/config/manager.yaml",
                              f"{ROOT}/deployed.json", *(f"{ROOT}/config/behavior_trees/{f}" for f in projects)}
    uploaded = {e.path.rsplit("/", 1)[1]: e.after for e in plan.edits if "/behavior_trees/" in e.path}
    for f in projects:  # the stock project of the release; the robot's power-off as 2.2.1+ does it before 2.2.1
        own = f == "shutdown.xml" and template != "husarion-ugv-2.2.2.yaml"
        source = template_path("behavior_trees", f) if own else template_path("config", stock_dir, "behavior_trees", f)
        assert uploaded[f] == source.read_bytes(), f
    after = plan.edits[0].after.decode()  # type: ignore[union-attr]
    a, b = before.splitlines(), after.splitlines()
    assert b[: len(a)] == [new_cmd if line == old_cmd else line for line in a]  # only the driver's command
    doc = yaml.safe_load(after)
    svc = doc["services"][SERVICE]
    assert svc["image"] == doc["services"][driver]["image"]
    added = b[len(a):]
    assert added[added.index(f"  {SERVICE}:") + 1: added.index(f"  {SERVICE}:") + 4] == [
        f"    image: {svc['image']}", f"    container_name: {SERVICE}", "    <<: *common-config"]
    assert svc["restart"] == "always" and svc["network_mode"] == "host"  # from the merge
    assert "environment" not in yaml.safe_load(after.replace("<<: *common-config", ""))["services"][SERVICE]
    assert f"{ROOT}:/opt/panther-ops/manager:ro" in svc["volumes"]
    assert svc["command"].split() == [
        "python3", f"/opt/panther-ops/manager/{bundle.version}/{ARCHIVE_NAME}",
        "--config", "/opt/panther-ops/manager/config/manager.yaml",
        "--lights-bt", f"/opt/panther-ops/manager/config/behavior_trees/{prefix}LightsBT.btproj",
        "--safety-bt", f"/opt/panther-ops/manager/config/behavior_trees/{prefix}SafetyBT.btproj",
        "--stack", STACKS[template],
        *(["--namespace", "panther"] if template == "panther-2.0.4.yaml" else [])]
    params = yaml.safe_load(next(e.after for e in plan.edits if e.path.endswith("manager.yaml")))  # type: ignore[arg-type]
    # the hosts file, the robot's power-off, and the stock manager's values of the release (issue 24:
    # no docker engine here, so the release's table, tests/manager_ops/test_manager_stock_params.py)
    from panther_ops.core.manager_ops.stock import stock_manager

    version = tuple(int(x) for x in STACKS[template].split("."))
    assert params["/**"]["ros__parameters"] == {"shutdown_hosts_path": hosts, "shutdown_localhost_command": poweroff,
                                                **stock_manager(version).values}  # type: ignore[arg-type]
    if template.startswith("husarion-ugv"):  # the tree's hosts file, D-Bus power-off like the driver
        assert "/home/husarion/config:/config:ro" in svc["volumes"]
        assert "/run/dbus/system_bus_socket:/run/dbus/system_bus_socket" in svc["volumes"]
        assert svc["security_opt"] == ["apparmor:unconfined"]
    else:
        assert "~/.ssh/id_rsa:/root/.ssh/id_rsa:ro" in svc["volumes"] and "security_opt" not in svc


@pytest.mark.parametrize("template", list(CASES))
def test_remove_after_deploy_is_byte_identical(ctxs: Any, template: str) -> None:
    tmp, cs = ctxs
    name = TEMPLATE_ROBOT[template]
    compose = rfile(tmp, name, f"{HOME}/compose.yaml")
    before = compose.read_bytes()
    res = apply(cs[name], read_and_plan_deploy(cs[name]))
    assert res.outcome is Outcome.CHANGED, res.message
    assert rfile(tmp, name, f"{ROOT}/deployed.json").is_file()
    again = read_and_plan_deploy(cs[name])
    assert again.edits == [] and "already deployed" in (again.noop or "")
    plan = read_and_plan_remove(cs[name])
    assert plan.recreate == (CASES[template][0],)
    res = apply(cs[name], plan)
    assert res.outcome is Outcome.CHANGED, res.message
    assert compose.read_bytes() == before
    assert not rfile(tmp, name, f"{HOME}/panther-ops").exists()  # files and empty directories gone
    assert read_and_plan_remove(cs[name]).noop == "the manager is not deployed"
    assert list(rfile(tmp, name, f"{HOME}/.panther-ops/backups").iterdir())  # both changes left a backup


def with_disable_manager(tmp: Path, value: str) -> Path:
    """r21's compose.yaml, its driver launched with disable_manager:=`value` already."""
    compose = rfile(tmp, "r21", f"{HOME}/compose.yaml")
    compose.write_text(compose.read_text().replace("bringup.launch.py\n", f"bringup.launch.py disable_manager:={value}\n"))
    return compose


def test_disable_manager_set_before_is_restored(ctxs: Any) -> None:
    tmp, cs = ctxs
    compose = with_disable_manager(tmp, "False")
    before = compose.read_bytes()
    plan = read_and_plan_deploy(cs["r21"])
    assert "disable_manager:=True" in plan.edits[0].after.decode()  # type: ignore[union-attr]
    assert "disable_manager:=False" not in plan.edits[0].after.decode()  # type: ignore[union-attr]
    apply(cs["r21"], plan)
    assert json.loads(rfile(tmp, "r21", f"{ROOT}/deployed.json").read_text())["disable_manager_before"] == "False"
    apply(cs["r21"], read_and_plan_remove(cs["r21"]))
    assert compose.read_bytes() == before


def test_already_disabled_driver_is_not_recreated(ctxs: Any) -> None:
    tmp, cs = ctxs
    compose = with_disable_manager(tmp, "True")
    before = compose.read_bytes()
    plan = read_and_plan_deploy(cs["r21"])
    assert plan.recreate == (SERVICE,)
    apply(cs["r21"], plan)
    remove = read_and_plan_remove(cs["r21"])
    assert remove.recreate == ()  # disable_manager stays as the operator had it
    apply(cs["r21"], remove)
    assert compose.read_bytes() == before


def test_refused_on_200(tmp_path: Path) -> None:
    inv = make_fleet(tmp_path, {"old": ("panther-2.0.4.yaml", {})})
    compose = tmp_path / "robots/old/home/husarion/compose.yaml"
    compose.write_text(compose.read_text().replace("humble-2.0.4-20240628", "humble-2.0.0-20240402"))
    with Connections(inv) as conns:
        ctx = RobotContext(inv.robots["old"], conns.get(inv.robots["old"]), inv)
        with pytest.raises(UsageError, match=r"panther_ros 2\.0\.0: disable_manager exists from panther_ros 2\.0\.1"):
            read_and_plan_deploy(ctx)


def test_sim_mode_uploads_the_scenario(ctxs: Any) -> None:
    _tmp, cs = ctxs
    plan = read_and_plan_deploy(cs["r21"], sim=True, scenario="low_battery")
    scenario = next(e for e in plan.edits if e.path == f"{ROOT}/config/scenario.yaml")
    assert scenario.after == template_path("manager", "scenarios", "low_battery.yaml").read_bytes()
    cmd = yaml.safe_load(plan.edits[0].after)["services"][SERVICE]["command"].split()  # type: ignore[arg-type]
    assert cmd[-3:] == ["--sim", "--scenario", "/opt/panther-ops/manager/config/scenario.yaml"]
    apply(cs["r21"], plan)
    ros2 = read_and_plan_deploy(cs["r21"], sim=False)  # back to ros2: the scenario file goes, the manager is recreated
    assert [e.path for e in ros2.edits if e.after is None] == [f"{ROOT}/config/scenario.yaml"]
    assert ros2.recreate == (SERVICE,)


def test_upgrade_replaces_the_archive_and_keeps_the_driver(ctxs: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    tmp, cs = ctxs
    old = build_bundle()
    apply(cs["r21"], read_and_plan_deploy(cs["r21"], bundle=old))
    new = ManagerBundle(old.data + b"\0", "9.9.9-abcdefabcdef", "abcdefabcdef", old.members, old.dependencies)
    plan = read_and_plan_deploy(cs["r21"], bundle=new)
    assert plan.recreate == (SERVICE,)
    gone = [e.path for e in plan.edits if e.after is None]
    assert gone == [f"{ROOT}/{old.version}/{ARCHIVE_NAME}"]
    assert f"manager {old.version} -> 9.9.9-abcdefabcdef" in plan.summary
    apply(cs["r21"], plan)
    assert not rfile(tmp, "r21", f"{ROOT}/{old.version}").exists()
    assert rfile(tmp, "r21", f"{ROOT}/9.9.9-abcdefabcdef/{ARCHIVE_NAME}").is_file()


def test_diffs_show_the_archive_in_one_line(ctxs: Any) -> None:
    _tmp, cs = ctxs
    plan = read_and_plan_deploy(cs["r21"])
    diffs = {d.path: d.unified for d in plan.diffs}
    archive = next(p for p in diffs if p.endswith(ARCHIVE_NAME))
    assert len(diffs[archive].splitlines()) == 4 and "py_trees 2." in diffs[archive]
    assert ("panther_ros 2.1.1's stock lights.xml (templates/config/panther-2.1/panther_manager/behavior_trees)"
            in diffs[f"{ROOT}/config/behavior_trees/lights.xml"])
    assert f"+  {SERVICE}:" in diffs[f"{HOME}/compose.yaml"]
    assert '+  "disable_manager_before": null,' in diffs[f"{ROOT}/deployed.json"]


def test_manager_yaml_carries_desired_params(tmp_path: Path) -> None:
    desired = {"manager": {"params": {"battery.percent.threshold.low": 0.3, "cpu.temp.fan_on": 75}}}
    inv = make_fleet(tmp_path, {"r": ("panther-2.1.1.yaml", desired)})
    with Connections(inv) as conns:
        ctx = RobotContext(inv.robots["r"], conns.get(inv.robots["r"]), inv)
        apply(ctx, read_and_plan_deploy(ctx))
    path = tmp_path / "robots/r" / f"{ROOT}/config/manager.yaml".lstrip("/")
    cfg = load_manager_config([path])
    assert cfg.lights.low_battery_threshold_percent == 0.3 and cfg.safety.cpu_fan_on_temp == 75
    assert cfg.safety.shutdown_localhost_command == SSH_POWEROFF
    assert not cfg.notes


@pytest.mark.parametrize(("manager", "key", "message"), [
    ({"colour": "red"}, "manager.colour", "unknown key"),
    ({"mode": "ros1"}, "manager.mode", "ros2 or sim"),
    ({"params": {"battery.percent.threshold.low": 7}}, "manager.params", "fraction"),
    ({"shutdown_hosts": "relative.yaml"}, "manager.shutdown_hosts", "an absolute path"),
    ({"shutdown_hosts": "/home/husarion/../x.yaml"}, "manager.shutdown_hosts", "without '..'"),
    ({"mode": "sim", "scenario": "no_such"}, "manager.scenario", "no such shipped scenario"),
])
def test_bad_desired_manager_is_refused_when_the_inventory_loads(tmp_path: Path, manager: dict[str, Any], key: str,
                                                                 message: str) -> None:
    """Refused by the inventory (every command, exit 2), no longer only by deploy's plan; the
    planner's own call of the same validator still refuses a block given to it directly."""
    with pytest.raises(UsageError, match=message) as exc:
        make_fleet(tmp_path, {"r": ("panther-2.1.1.yaml", {"manager": manager})})
    assert f"[robots.r.desired.{key}]" in str(exc.value) and "inv.yaml" in str(exc.value)
    with pytest.raises(UsageError, match=message):
        manager_settings({"manager": manager})


def test_disabled_robot_is_left_alone(tmp_path: Path) -> None:
    inv = make_fleet(tmp_path, {"r": ("panther-2.1.1.yaml", {"manager": {"enabled": False}})})
    with Connections(inv) as conns:
        ctx = RobotContext(inv.robots["r"], conns.get(inv.robots["r"]), inv)
        plan = read_and_plan_deploy(ctx)
    assert plan.edits == [] and "enabled is false" in (plan.noop or "")


def test_settings_overrides() -> None:
    s = manager_settings({"manager": {"mode": "sim", "scenario": "charging"}}, sim=False)
    assert s.mode == "ros2"
    assert manager_settings({}, sim=True, scenario="fan_hysteresis").scenario == "fan_hysteresis"


# ------------------------------------------------------------------ CLI on local robots


def test_cli_dry_run_deploy_then_deploy_and_remove(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    make_fleet(tmp_path, {"r": ("panther-2.1.1.yaml", {})})
    inv = str(tmp_path / "inv.yaml")
    compose = tmp_path / "robots/r/home/husarion/compose.yaml"
    before = compose.read_bytes()
    assert main(["-i", inv, "manager", "deploy", "-r", "r", "--dry-run"]) == 0
    out = capsys.readouterr().out
    assert "+  panther_ops_manager:" in out and "disable_manager:=True" in out and "py_trees" in out
    assert "PK\x03\x04" not in out  # the archive is described, not dumped
    assert compose.read_bytes() == before and not (tmp_path / "robots/r/home/husarion/panther-ops").exists()
    assert main(["-i", inv, "manager", "deploy", "-r", "r", "--yes", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["robots"][0]["outcome"] == "changed" and doc["robots"][0]["data"]["service"] == SERVICE
    assert main(["-i", inv, "manager", "status", "-r", "r", "--json"]) == 0  # no engine: skipped, facts kept
    doc = json.loads(capsys.readouterr().out)
    r = doc["robots"][0]
    assert r["outcome"] == "skipped" and r["data"]["in_compose"] and r["data"]["disable_manager"] == "True"
    assert main(["-i", inv, "manager", "remove", "-r", "r", "--yes", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["robots"][0]["outcome"] == "changed"
    assert compose.read_bytes() == before
    assert main(["-i", inv, "manager", "status", "-r", "r", "--json"]) == 0
    assert "not deployed" in json.loads(capsys.readouterr().out)["robots"][0]["message"]


# ------------------------------------------------------------------ status (pure parts)


def test_describe_container() -> None:
    from datetime import datetime, timezone

    attrs = {"Name": "/panther_ops_manager", "RestartCount": 2,
             "State": {"Status": "running", "Running": True, "StartedAt": "2026-01-01T10:00:00.123456789Z"},
             "Config": {"Image": "husarion/panther:humble-2.1.1-20240828",
                        "Cmd": ["python3", "/opt/panther-ops/manager/0.1.0-abc/panther_ops_manager.pyz"]}}
    d = describe(attrs, datetime(2026, 1, 1, 10, 1, 30, tzinfo=timezone.utc))
    assert d["state"] == "running" and d["restart_count"] == 2 and d["uptime_s"] == pytest.approx(89.9, abs=0.1)
    assert d["running_version"] == "0.1.0-abc" and d["container"] == "panther_ops_manager"
    assert running_version(["ros2", "launch"]) is None


def test_status_of_a_robot_without_the_manager(ctxs: Any) -> None:
    _tmp, cs = ctxs
    res = status_task(cs["r22"])
    assert res.outcome is Outcome.OK and res.message.startswith("not deployed")


# ------------------------------------------------------------------ the entry point


def test_resolve_find(tmp_path: Path) -> None:
    share = tmp_path / "install/panther_manager/share/panther_manager"
    share.mkdir(parents=True)
    prefixes = f"/nowhere:{tmp_path / 'install/panther_manager'}"
    assert resolve_find("$(find panther_manager)/config/x.yaml", prefixes) == f"{share}/config/x.yaml"
    assert resolve_find("$(find other)/config/x.yaml", prefixes) == "$(find other)/config/x.yaml"
    assert resolve_find("/config/x.yaml", prefixes) == "/config/x.yaml"


def test_entry_point_check(capsys: pytest.CaptureFixture[str]) -> None:
    bt = template_path("behavior_trees")
    code = manager_main(["--check", "--sim", "--lights-bt", str(bt / "PantherLightsBT.btproj"),
                         "--safety-bt", str(bt / "PantherSafetyBT.btproj"),
                         "--scenario", str(template_path("manager", "scenarios", "charging.yaml"))])
    assert code == 0
    assert "check ok (simulation mode" in capsys.readouterr().out


def test_entry_point_sim_runs_and_stops_on_sigterm(tmp_path: Path) -> None:
    import signal
    import time

    proc = subprocess.Popen([sys.executable, "-m", "panther_ops.manager", "--sim", "--status-every", "0"],
                            stdout=subprocess.PIPE, text=True, cwd=Path(__file__).resolve().parents[2])
    assert proc.stdout is not None
    first = proc.stdout.readline()
    assert "simulation mode, scenario charging" in first
    seen: list[str] = []
    deadline = time.monotonic() + 20  # a loaded machine may take a while for the first tick
    while time.monotonic() < deadline and not any("call lights/set_animation" in line for line in seen):
        line = proc.stdout.readline()
        if not line:
            break
        seen.append(line)
    proc.send_signal(signal.SIGTERM)
    out, _ = proc.communicate(timeout=10)
    assert any("call lights/set_animation" in line for line in seen), seen
    assert proc.returncode == 0 and "manager: stopped" in out


def test_entry_point_reports_bad_parameters(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "manager.yaml"
    bad.write_text("/**:\n  ros__parameters:\n    battery.percent.threshold.low: 5\n")
    assert manager_main(["--check", "--config", str(bad)]) == 2
    assert "error:" in capsys.readouterr().out


def test_bundle_module_lists_only_pure_dependencies() -> None:
    assert [m for m, _ in manager_bundle.DEPENDENCIES] == ["py_trees", "pydot", "pyparsing", "yaml"]


def test_entry_point_warns_when_ssh_hosts_cannot_be_shut_down(tmp_path: Path,
                                                             monkeypatch: pytest.MonkeyPatch) -> None:
    import importlib.util

    from panther_ops.manager.__main__ import hosts_warnings

    hosts = tmp_path / "hosts.yaml"
    hosts.write_text("hosts:\n  - {ip: 192.0.2.3, username: husarion}\n  - {ip: 192.0.2.4, port: 3003, secret: s}\n")
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "paramiko" else real(name, *a))
    known = tmp_path / "known_hosts"
    known.write_text("192.0.2.3 ssh-ed25519 AAAAC3NzaC1lZDI1NTE5AAAAIOMqqnkVzrm0SdG6UOoqKLsabgH5C9okWi0dh2l9GKJl\n")
    assert hosts_warnings(str(hosts), str(known)) == []  # no paramiko, but the ssh client on PATH does it
    assert hosts_warnings(str(hosts), str(tmp_path / "none")) == [
        f"no host key in {tmp_path / 'none'} for husarion@192.0.2.3:22: their SSH shutdown will fail "
        "(unknown host keys are refused)"]
    monkeypatch.setenv("PATH", str(tmp_path))  # no ssh client either
    assert hosts_warnings(str(hosts), str(known)) == [
        "neither paramiko nor an ssh client in this image: SSH shutdown of "
        "192.0.2.3 will fail (HTTP hosts of husarion-shutdown need nothing more)"]
    assert hosts_warnings(str(tmp_path / "missing.yaml")) == []
