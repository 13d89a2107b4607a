"""Tables at 80 and 120 columns (issue 26, finding 1), the confirmation's order (finding 6) and the
small things of finding 10.

Every view that prints a table is rendered at 80 and 120 columns with robots of long names, an
unreachable robot, backup ids, image ids and nine paths of one directory: no line is wider than
the terminal, no robot name or id is broken, no two paths look the same. Then the demo fleet on
a pseudo-terminal 80 columns wide, as an operator sees it.
"""

from __future__ import annotations

import ast
import json
import re
from collections.abc import Callable
from pathlib import Path

import pytest

from panther_ops.cli import output
from panther_ops.cli.render import print_results
from panther_ops.cli.views import driver, estop, gps, history, manager, reimage, shutdown, status
from panther_ops.results import FleetResult, Outcome, RobotResult
from tests.clirun import run

from .termrun import on_pty, plain

Capsys = pytest.CaptureFixture[str]

LONG = "panther-warehouse-north-17"
NAMES = ["panther-01", LONG, "lynx-field-testbed-02"]
DOWN = "panther-far-away-99"
REASON = ("could not connect to husarion@10.15.20.2:22 through operator@gateway.example.org:22: timed out "
          "after 10 s (is the robot powered on and on the network?)")
IDS = ["20250114T101502Z-9f3a", "20250114T101733Z-0c1e"]
IMAGE_ID = "sha256:4f1c2a9b8d7e6f5a4b3c2d1e0f9a8b7c6d5e4f3a2b1c0d9e8f7a6b5c4d3e2f1a0"
CONFIG = "/home/husarion/config/husarion_ugv_controller/config/"
PATHS = [CONFIG + f for f in ("WH01_controller.yaml", "WH02_controller.yaml", "WH04_controller.yaml",
                              "WH05_controller.yaml", "components.yaml", "enu_localization.yaml",
                              "enu_localization_with_gps.yaml", "relative_localization.yaml",
                              "relative_localization_with_gps.yaml")]
BOX = re.compile(r"[│┃]")


def _unreachable() -> RobotResult:
    return RobotResult(DOWN, Outcome.UNREACHABLE, REASON)


def _fleet(command: str, data: Callable[[str], dict[str, object]], message: str = "ok",
           outcome: Outcome = Outcome.OK) -> FleetResult:
    results = [RobotResult(n, outcome, message, data=data(n)) for n in NAMES]
    return FleetResult(command, [*results, _unreachable()])


def _status(n: str) -> dict[str, object]:
    return {"hostname": n, "robot_model": "panther", "robot_version": "1.2", "robot_serial": "PTH0101",
            "system_build_version": "v2.2.0", "stack": "husarion_ugv", "stack_version": "2.2.2",
            "driver_state": "running", "disk_free_bytes": 80 << 30, "clock_offset_s": -0.001,
            "containers": [{"name": "husarion_ugv_ros", "state": "running", "restart_count": 0},
                           {"name": "gamepad_controller", "state": "running", "restart_count": 3}],
            "webui": {"installed": True, "running": True, "port": 8080}}


def _doctor(n: str) -> dict[str, object]:
    return {"findings": [{"check": "ssh key auth", "state": "ok", "detail": f"connected as husarion to {n}"},
                         {"check": "clock", "state": "warn", "detail": "robot clock is +3.20 s off this machine",
                          "fix": "sync time: on the robot `sudo timedatectl set-ntp true`"}]}


def _history(n: str) -> dict[str, object]:
    return {"history": [{"id": i, "created": "2025-01-14T10:15:02.671+00:00", "command": "config set wheel_type WH02",
                         "summary": "wheel_type:=WH02", "files": [{"path": "/home/husarion/compose.yaml"}],
                         "status": "applied"} for i in IDS]}


def _carried(n: str) -> dict[str, object]:
    return {"robot": {"model": "panther", "serial": "PTH0203", "stack": "husarion_ugv 2.2.2", "os_build": "v2.2.0"},
            "files": [{"path": p, "role": "config tree", "size": 4400, "mode": "0644", "owner": "husarion:husarion",
                       "secret": False} for p in PATHS]}


def _gps(n: str) -> dict[str, object]:
    return {"verdict": "fix", "sentences_per_s": 4, "recorded": True, "age_s": 0.4,
            "fix": {"lat": 53.1978127, "lon": 18.3732456, "satellites": 11, "hdop": 0.7},
            "driver": {"mode": "nmea_navsat_driver"}, "detail": "53.1978127 18.3732456, 11 satellites, HDOP 0.7"}


def _router(n: str) -> dict[str, object]:
    return {"gps_enabled": True, "forwarding": True, "hostname": "10.15.20.2", "port": 5000, "proto": "udp",
            "sentences": ["GGA", "RMC", "GSA", "GSV"]}


def _driver(n: str) -> dict[str, object]:
    return {"service": "husarion_ugv_ros", "image": "husarion/husarion-ugv:humble-2.2.2-20250702",
            "state": "running", "uptime_s": 7200, "restart_count": 0, "exit_code": 0, "health": "healthy",
            "command_drift": False}


def _versions(n: str) -> dict[str, object]:
    return {"local": [{"image": "husarion/husarion-ugv:humble-2.2.2-20250702", "in_use": True, "in_compose": True,
                       "id": IMAGE_ID, "size": 3 << 30},
                      {"image": "husarion/husarion-ugv:humble-2.2.0-20250312", "in_use": False, "in_compose": False,
                       "id": IMAGE_ID[:20] + "ffffffffffff", "size": 3 << 30}]}


def _manager(n: str) -> dict[str, object]:
    return {"version": "0.9.0", "mode": "replace", "state": "running", "uptime_s": 360, "restart_count": 0,
            "disable_manager": "true"}


def _estop(n: str) -> dict[str, object]:
    return {"e_stop": True, "cmd_vel_publishers": ["/teleop_twist_keyboard", "/joy2twist"], "namespace": "/panther",
            "recorded": True}


def _check(n: str) -> dict[str, object]:
    return {"hosts": [{"host": "husarion@10.15.20.3:22", "ok": False, "step": "ssh",
                       "message": "the key was refused by 10.15.20.3", "fix": "ssh-copy-id -p 22 husarion@10.15.20.3"}]}


def _steps(n: str) -> dict[str, object]:
    return {"steps": [{"step": "hosts file", "outcome": "changed", "message": "added 10.15.20.3 (ssh, husarion)"},
                      {"step": "key", "outcome": "ok", "message": "the robot's key is on 10.15.20.3"}]}


def _hosts_down(n: str) -> dict[str, object]:
    return {"hosts": [{"robot": "husarion@10.15.20.3:22", "outcome": "ok", "message": "powered off (no ping for 2 s)",
                       "duration_s": 4.2}]}


def _hosts_list(n: str) -> dict[str, object]:
    return {"hosts_file": "/home/husarion/config/husarion_ugv_manager/config/shutdown_hosts.yaml",
            "hosts": [{"ip": "10.15.20.3", "method": "ssh", "username": "husarion", "port": 22,
                       "command": "sudo shutdown now", "secret": "", "timeout": 5.0, "ping_for_success": True}]}


VIEWS: dict[str, Callable[[], None]] = {
    "print_results": lambda: print_results(_fleet("config set", lambda n: {"dry_run": True},
                                                  "would change: wheel_type:=WH02 in " + CONFIG + "x.yaml",
                                                  Outcome.CHANGED)),
    "status": lambda: status.print_status(_fleet("status", _status)),
    "doctor": lambda: status.print_doctor(_fleet("doctor", _doctor)),
    "config history": lambda: history.print_history(_fleet("config history", _history)),
    "reimage plan": lambda: reimage.print_carried(_fleet("reimage plan", _carried, "9 files"), title="reimage plan"),
    "gps status": lambda: gps.print_status(_fleet("gps status", _gps)),
    "gps router show": lambda: gps.print_router(_fleet("gps router show", _router)),
    "driver status": lambda: driver.print_status(_fleet("driver status", _driver)),
    "driver versions": lambda: driver.print_versions(_fleet("driver versions", _versions)),
    "manager status": lambda: manager.print_status(_fleet("manager status", _manager, "running the deployed manager")),
    "estop status": lambda: estop.print_state(_fleet("estop status", _estop)),
    "shutdown check": lambda: shutdown.print_check(_fleet("shutdown check", _check, "1 host failed", Outcome.FAILED)),
    "shutdown setup": lambda: shutdown.print_steps(_fleet("shutdown setup", _steps, "set up", Outcome.CHANGED)),
    "shutdown robot": lambda: shutdown.print_robots_down(_fleet("shutdown robot", _hosts_down, "powered off")),
    "shutdown hosts list": lambda: shutdown.print_list(_fleet("shutdown hosts list", _hosts_list, "1 host")),
    "shutdown --hosts": lambda: shutdown.finish_hosts(FleetResult("shutdown --hosts h.yaml", [
        RobotResult("husarion@10.15.20.3:22", Outcome.OK, "powered off", duration_s=3.1),
        RobotResult("pi@10.15.20.44:22", Outcome.FAILED, REASON, duration_s=5.0)], subject="host"), False),
}

IDS_SHOWN = {"config history": IDS, "driver versions": [IMAGE_ID.removeprefix("sha256:")[:12]]}


def _render(view: Callable[[], None], width: int, capsys: Capsys, monkeypatch: pytest.MonkeyPatch,
            wide: bool = False) -> str:
    """What the view prints on stdout when the output is ``width`` columns wide."""
    monkeypatch.setattr(output, "PIPE_WIDTH", width)
    if wide:
        output.set_wide(True)
    try:
        capsys.readouterr()
        view()
        return capsys.readouterr().out
    finally:
        if wide:
            output.set_wide(False)


def _rows(out: str) -> list[str]:
    return [line for line in out.splitlines() if BOX.match(line[:1])]


@pytest.mark.parametrize("width", [80, 120])
@pytest.mark.parametrize("name", sorted(VIEWS))
def test_every_table_fits_and_breaks_no_name_or_id(name: str, width: int, capsys: Capsys,
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    out = _render(VIEWS[name], width, capsys, monkeypatch)
    rows = _rows(out)
    assert rows, out
    too_wide = [line for line in out.splitlines() if len(line) > width]
    assert not too_wide, f"{name} at {width}:\n{out}"
    text = "\n".join(rows)
    robots = ["husarion@10.15.20.3:22", "pi@10.15.20.44:22"] if name == "shutdown --hosts" else [*NAMES, DOWN]
    for robot in robots:  # each name whole, in the first cell of its row (or the table's title)
        assert robot in out, f"{name} at {width}: {robot!r} is broken\n{out}"
    for ident in IDS_SHOWN.get(name, []):
        assert ident in text, f"{name} at {width}: id {ident!r} is broken\n{out}"
    if DOWN in text:  # the unreachable robot's reason: on full-width lines under its row, not in a column
        assert any(line.startswith("│   could not connect to husarion@10.15.20.2:22") for line in rows), out


@pytest.mark.parametrize("width", [80, 120])
def test_nine_paths_of_one_directory_stay_nine_different_paths(width: int, capsys: Capsys,
                                                               monkeypatch: pytest.MonkeyPatch) -> None:
    out = _render(VIEWS["reimage plan"], width, capsys, monkeypatch)
    shown = [line.split("│")[1].strip() for line in _rows(out) if line.startswith("│ ") and ".yaml" in line
             and line.count("│") > 3]
    files = [s for s in shown if s.endswith(".yaml")][:9]
    assert len(files) == 9 and len(set(files)) == 9, out
    for path, seen in zip(PATHS, files, strict=True):  # shortened from the left: the file's name is kept
        assert path.endswith(seen.removeprefix("…")), (path, seen)


def test_status_at_80_columns_is_a_line_per_robot(capsys: Capsys, monkeypatch: pytest.MonkeyPatch) -> None:
    """Three reachable robots and one unreachable: a line each, the reason on a line under its row,
    the hidden columns named; --wide shows every column."""
    out = _render(VIEWS["status"], 80, capsys, monkeypatch)
    body = [line for line in _rows(out) if not line.startswith(("┃", "┏", "┡", "└"))]
    assert len(body) <= 2 * 3 + 1 + 3, out  # a robot's row is at most 2 lines, the reason at most 3 (was 37 for 3)
    assert any(re.match(rf"│ {DOWN} +│ unreachable +│", line) for line in body), out
    assert "not shown at this width:" in out and "--wide" in out
    wide = _render(VIEWS["status"], 80, capsys, monkeypatch, wide=True)
    header = next(line for line in wide.splitlines() if line.startswith("┃"))
    for col in ("hostname", "model / serial", "OS build", "containers", "disk free", "clock", "webui"):
        assert col in header, wide
    assert "not shown" not in wide


def test_clock_offsets_that_round_to_nothing_are_not_negative(capsys: Capsys,
                                                              monkeypatch: pytest.MonkeyPatch) -> None:
    out = _render(VIEWS["status"], 160, capsys, monkeypatch)
    assert "-0.00 s" not in out and "│ +0.00 s" in out, out


def test_no_rich_table_outside_the_fitting_table() -> None:
    """Every data table is a FitTable (rich's Table only for the progress grid and the sim panel)."""
    cli = Path(__file__).resolve().parents[2] / "panther_ops" / "cli"
    allowed = {"tables.py", "progress.py", "sim.py"}
    users = []
    for path in cli.rglob("*.py"):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module == "rich.table" and path.name not in allowed:
                users.append(str(path))
    assert users == []


def test_every_module_that_builds_a_table_is_rendered_here() -> None:
    cli = Path(__file__).resolve().parents[2] / "panther_ops" / "cli"
    building = {p.stem for p in (cli / "views").glob("*.py") if "new_table(" in p.read_text()}
    covered = {m.__name__.rsplit(".", 1)[1] for m in (driver, estop, gps, history, manager, reimage, shutdown, status)}
    assert building <= covered | {"inventory"}, building - covered  # inventory: on the demo fleet below


# -- the demo fleet on an 80-column terminal -------------------------------------------------------------
def _table_lines(out: str) -> list[str]:
    """The lines of the tables (box and rows) and of the note under them."""
    return [line for line in out.splitlines() if line[:1] in "┏┃┡│└" or line.startswith(("not shown", "containers"))]


def _shown(demo: Path, *args: str, cols: int = 80) -> str:
    run_ = on_pty(["-i", str(demo), "-q", *args], cols=cols)
    assert run_.code == 0, run_.out
    return plain(run_.out)


def test_demo_status_at_80_columns(demo: Path) -> None:
    out = _shown(demo, "status", "--all")
    assert all(len(line) <= 80 for line in _table_lines(out)), out
    for robot in ("panther-01", "panther-02", "panther-03"):
        assert re.search(rf"^│ {robot} +│ ok", out, re.M), out
    assert len(_rows(out)) <= 3 + 3, out  # header, three robots, the box (was 37 lines)


def test_demo_commands_at_80_and_120_columns_wrap_no_robot_name(demo: Path) -> None:
    for cols in (80, 120):
        for args in (("gps", "status", "--all"), ("driver", "status", "--all"), ("manager", "status", "--all"),
                     ("inventory", "list"), ("doctor", "--all"), ("estop", "status", "--all")):
            out = _shown(demo, *args, cols=cols)
            assert all(len(line) <= cols for line in _table_lines(out)), (args, out)
            for robot in ("panther-01", "panther-02", "panther-03"):
                assert re.search(rf"^│ {robot} ", out, re.M), (args, cols, out)


def test_demo_reimage_plan_shows_every_path_apart(demo: Path) -> None:
    out = _shown(demo, "reimage", "plan", "-r", "panther-03")
    paths = [line.split("│")[1].strip() for line in out.splitlines() if line.startswith("│ ") and line.count("│") > 3]
    files = [p for p in paths if "/" in p]
    assert len(files) > 9 and len(set(files)) == len(files), out
    assert all(len(line) <= 80 for line in _table_lines(out)), out


def test_demo_config_history_keeps_the_backup_ids_whole(demo: Path, capsys: Capsys) -> None:
    for wheel in ("WH02", "WH01"):
        code, _, err = run(capsys, "-i", str(demo), "config", "set", "wheel_type", wheel, "-r", "panther-01", "--yes")
        assert code == 0, err
    code, out, _ = run(capsys, "-i", str(demo), "config", "history", "-r", "panther-01", "--json")
    ids = [e["id"] for e in json.loads(out)["robots"][0]["data"]["history"]]
    assert len(ids) == 2
    shown = _shown(demo, "config", "history", "--all")
    for ident in ids:  # what `config rollback --to` takes, copied from one line
        assert re.search(rf"│ {re.escape(ident)} +│", shown), shown


# -- finding 6: the question names the robots in inventory order -----------------------------------------
def test_the_confirmation_lists_robots_in_inventory_order(demo: Path) -> None:
    from panther_ops.cli.mutate import question
    from panther_ops.core.fleet.inventory_file import load_inventory

    inv = load_inventory(str(demo))
    chosen = inv.select([], [], True)
    finished = ["panther-03", "panther-01", "panther-02"]  # the order the plans came in
    assert question("Apply to", "robot", finished, chosen) == "Apply to 3 robots: panther-01, panther-02, panther-03?"
    assert question("Recreate", "robot", ["panther-02"], chosen) == "Recreate 1 robot: panther-02?"


# -- finding 10: the small things --------------------------------------------------------------------------
def test_dry_run_rows_say_would_change_once(demo: Path, capsys: Capsys) -> None:
    code, out, _ = run(capsys, "-i", str(demo), "config", "set", "wheel_type", "WH02", "--all", "--dry-run")
    assert code == 0
    rows = [line for line in out.splitlines() if line.startswith("│ panther-")]
    assert len(rows) == 4 and all(row.count("would change") == 1 for row in rows), out
    code, out, _ = run(capsys, "-i", str(demo), "config", "set", "wheel_type", "WH02", "--all", "--dry-run", "--json")
    assert all(r["message"].startswith("would change: ") for r in json.loads(out)["robots"])  # JSON as it was


def test_one_robot_is_one_robot(tmp_path: Path, capsys: Capsys) -> None:
    inv = tmp_path / "one.yaml"
    (tmp_path / "r").mkdir()
    inv.write_text("version: 1\ngroups:\n  g: {}\nrobots:\n  solo:\n    transport: local\n    root: r\n    groups: [g]\n")
    code, out, _ = run(capsys, "-i", str(inv), "inventory", "validate")
    assert code == 0 and "1 robot, 1 group, valid" in out, out


def test_validate_names_the_file_once(tmp_path: Path, capsys: Capsys, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    Path("h.yaml").write_text("hosts:\n  - ip: 10.15.20.5\n    username: pi\n    command: sudo shutdown now\n")
    code, out, _ = run(capsys, "shutdown", "hosts", "validate", "h.yaml")
    assert code == 0 and out.strip() == "h.yaml: ok 1 host valid, 0 warnings", out
    Path("anim.yaml").write_text("global:\n  ros__parameters:\n    foo: 1\n")
    code, out, err = run(capsys, "lights", "validate", "anim.yaml")
    assert code == 2 and out.count("anim.yaml") == 0 and "anim.yaml: animations refused (1 error, 0 warnings)" in err
