"""`panther-ops describe ROBOT` (issue 26): one robot, part by part, on the demo fleet; its view
at 80 and 120 columns with long names, images and ids; one robot only."""

from __future__ import annotations

import json
import socket
from pathlib import Path

import pytest

from panther_ops.cli import output
from panther_ops.cli.app import main
from panther_ops.cli.views.describe import LABEL, print_describe
from panther_ops.results import FleetResult, Outcome, RobotResult
from tests.clirun import run, run_cli

Capsys = pytest.CaptureFixture[str]
LABELS = ("reached", "hostname", "model", "OS build", "stack", "image", "containers", "disk", "clock", "WebUI",
          "GPS", "E-stop", "last change", "backup", "doctor")


@pytest.fixture()
def demo(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> str:
    monkeypatch.chdir(tmp_path)
    assert main(["demo", "init", "--dest", "demo-fleet"]) == 0
    return str(tmp_path / "demo-fleet")


def test_every_part_of_one_demo_robot(demo: str, capsys: Capsys) -> None:
    code, out, err = run(capsys, "-i", demo, "describe", "panther-01")
    assert code == 0, err
    lines = out.splitlines()
    assert lines[0].split()[:3] == ["panther-01", "ok", "panther_ros"]
    labels = [line[:LABEL].strip() for line in lines[1:] if line[:1] != " "]
    assert labels == list(LABELS), out
    shown = {line[:LABEL].strip(): line[LABEL:].strip() for line in lines[1:] if line[:1] != " "}
    assert shown["stack"] == "panther_ros 2.1.1"
    assert shown["image"] == "husarion/panther:humble-2.1.1-20240828"
    assert shown["containers"] == "not read: demo robot: no docker engine"
    assert shown["WebUI"] == "running http://10.15.20.3:8080/ui"  # the recorded User Computer
    assert shown["GPS"].startswith("fix: 53.1978127 18.3732456, 11 satellites")
    assert shown["E-stop"].startswith("triggered; cmd_vel publishers: none")
    assert (shown["last change"], shown["backup"]) == ("none recorded", "no backups yet")
    assert shown["doctor"].split()[:4] == ["ok", "ssh", "key", "auth"]
    assert "1 robot: 1 ok" in err


def test_the_last_change_and_its_backup_after_a_change(demo: str, capsys: Capsys) -> None:
    assert main(["-i", demo, "config", "set", "wheel_type", "WH01", "-r", "panther-02", "--yes"]) == 0
    _, history, _, _ = run_cli(capsys, "-i", demo, "config", "history", "-r", "panther-02", "--json")
    (entry,) = history["robots"][0]["data"]["history"]
    code, doc, _, _ = run_cli(capsys, "-i", demo, "describe", "panther-02", "--json")
    assert code == 0 and doc["command"] == "describe" and doc["exit_code"] == 0
    (robot,) = doc["robots"]
    last = robot["data"]["history"]["data"]["last"]
    assert last["id"] == entry["id"] and last["command"] == "config set wheel_type WH01"
    assert last["status"] == "applied" and last["files"] == ["/home/husarion/compose.yaml"]
    assert robot["data"]["history"]["data"]["backups"] == 1
    code, out, _ = run(capsys, "-i", demo, "describe", "panther-02")
    assert f"config rollback -r panther-02 --to {entry['id']}" in " ".join(out.split())


def test_json_has_each_part_from_its_own_reader(demo: str, capsys: Capsys) -> None:
    code, doc, _, _ = run_cli(capsys, "-i", demo, "describe", "panther-03", "--json")
    assert code == 0
    data = doc["robots"][0]["data"]
    assert set(data) == {"where", "status", "gps", "estop", "history", "doctor"}
    # the same answers as the commands that read each part
    for command, part in (("status", None), ("estop status", "estop"), ("gps status", "gps")):
        _, alone, _, _ = run_cli(capsys, "-i", demo, *command.split(), "-r", "panther-03", "--json")
        own = alone["robots"][0]["data"]
        mine = data["status"] if part is None else data[part]["data"]
        keys = {"stack", "stack_version", "driver_image", "hostname", "webui"} if part is None else \
            {"e_stop", "cmd_vel_publishers", "namespace"} if part == "estop" else {"verdict", "detail", "fix"}
        assert {k: mine[k] for k in keys} == {k: own[k] for k in keys}, command
    checks = [f["check"] for f in data["doctor"]["data"]["findings"]]
    assert checks == ["ssh key auth", "clock", "stack", "safety fixes", "docker", "disk"]  # no password check: one connection


def test_a_part_that_cannot_be_read_says_why_and_the_rest_is_shown(demo: str, capsys: Capsys) -> None:
    (Path(demo) / "robots/panther-01/var/lib/panther-ops-demo/ros.json").unlink()
    code, doc, _, _ = run_cli(capsys, "-i", demo, "describe", "panther-01", "--json")
    assert code == 0
    data = doc["robots"][0]["data"]
    assert data["estop"]["error"].startswith("no recorded driver answers")
    assert "demo init --force" in data["estop"]["hint"]
    assert data["status"]["stack_version"] == "2.1.1" and data["doctor"]["outcome"] == "ok"
    code, out, _ = run(capsys, "-i", demo, "describe", "panther-01")
    assert "E-stop        not read: no recorded driver answers" in out


def test_one_robot_only(demo: str, capsys: Capsys) -> None:
    code, doc, _, err = run_cli(capsys, "-i", demo, "describe", "panther-0*", "--json")
    assert code == 2 and doc["exit_code"] == 2
    assert "describe shows one robot; 'panther-0*' names 4: panther-01, panther-02, panther-03, panther-04" in err
    code, _, err = run(capsys, "-i", demo, "describe", "panther-1")
    assert code == 2 and "did you mean 'panther-01'" in err


def test_an_unreachable_robot_is_exit_4(tmp_path: Path, capsys: Capsys) -> None:
    with socket.socket() as s:  # a port nobody listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    key = tmp_path / "id_ed25519"
    key.write_text("not used: the connection is refused first\n")
    inv = tmp_path / "fleet.yaml"
    inv.write_text(f"version: 1\nrobots:\n  far-01:\n    host: 127.0.0.1\n    port: {port}\n"
                   f"    identity_file: {key}\n    connect_timeout: 2\n")
    code, doc, _, _ = run_cli(capsys, "-i", str(inv), "describe", "far-01", "--json")
    assert code == 4 and doc["exit_code"] == 4
    assert doc["robots"][0]["outcome"] == "unreachable"
    code, out, _ = run(capsys, "-i", str(inv), "describe", "far-01")
    assert code == 4 and out.splitlines()[0].split()[:2] == ["far-01", "unreachable"]
    assert "reached" not in out  # nothing else was read


# -- the view at 80 and 120 columns ------------------------------------------------------------------------
LONG = "panther-warehouse-north-17"
BACKUP = "20250114T101502Z-9f3a"
IMAGE = "husarion/husarion-ugv:humble-2.2.2-20250702"
URL = "http://10.15.20.3:8080/ui"


def _described() -> FleetResult:
    status = {"hostname": LONG, "os": "Ubuntu 22.04.4 LTS", "robot_model": "panther", "robot_version": "1.2",
              "robot_serial": "PTH0101", "system_build_version": "v2.2.0", "stack": "husarion_ugv",
              "stack_version": "2.2.2", "driver_image": IMAGE, "driver_service": "husarion_ugv_ros",
              "disk_free_bytes": 80 << 30, "disk_total_bytes": 250 << 30, "clock_offset_s": 0.002,
              "containers": [{"name": "husarion_ugv_ros", "state": "running", "restart_count": 0, "image": IMAGE,
                              "service": "husarion_ugv_ros"},
                             {"name": "husarion_ugv_gamepad_controller_with_a_long_name", "state": "restarting",
                              "restart_count": 12, "image": "husarion/joy2twist:humble-1.0.0-20240725-stable",
                              "service": "gamepad_controller"}],
              "webui": {"installed": True, "running": True, "port": "8080", "url": URL}}
    data = {
        "where": f"husarion@{LONG}.husarnet.example.org:22 via operator@gateway.example.org:22",
        "status": status,
        "gps": {"outcome": "ok", "message": "", "data": {"verdict": "data but no fix", "detail":
                "NMEA arrives but without a position fix (antenna's sky view?)", "driver": {"mode": "service"}}},
        "estop": {"outcome": "ok", "message": "", "data": {"e_stop": False, "cmd_vel_publishers": ["/joy2twist"]}},
        "history": {"outcome": "ok", "message": "", "data": {"backups": 7, "last": {
            "id": BACKUP, "created": "2025-01-14T10:15:02.671+00:00",
            "command": "config push my_controller_with_a_long_name.yaml --as controller", "summary":
            "controller_config_path:=/config/my_controller_with_a_long_name.yaml", "status": "applied"}}},
        "doctor": {"outcome": "ok", "message": "", "data": {"findings": [
            {"check": "clock", "state": "ok", "detail": "+0.00 s from this machine"},
            {"check": "default password", "state": "warn", "detail": "sshd accepts the default password for "
             "husarion", "fix": "change it (`passwd` on the robot) or set `PasswordAuthentication no` in "
             "/etc/ssh/sshd_config"}]}},
    }
    return FleetResult("describe", [RobotResult(LONG, Outcome.OK, "husarion_ugv 2.2.2; driver running", data=data)])


@pytest.mark.parametrize("width", [80, 120])
def test_the_view_fits_and_breaks_no_name_id_image_or_url(width: int, capsys: Capsys,
                                                           monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(output, "PIPE_WIDTH", width)
    capsys.readouterr()
    print_describe(_described())
    out = capsys.readouterr().out
    assert not [line for line in out.splitlines() if len(line) > width], out
    assert not [line for line in out.splitlines() if line != line.rstrip()], "trailing blanks"
    for word in (LONG, BACKUP, IMAGE, URL, "husarion_ugv_gamepad_controller_with_a_long_name"):
        assert word in out, f"{word!r} is broken at {width}:\n{out}"
    assert out.startswith(LONG)
    lines = out.splitlines()
    fix = next(i for i, line in enumerate(lines) if line.strip().startswith("fix: change it"))
    assert "warn default password  sshd accepts" in "\n".join(lines[fix - 2:fix])  # under its finding
    assert lines[fix].index("fix:") == lines[fix - 1].index("husarion" if width == 80 else "sshd")


def test_json_document_is_one(demo: str, capsys: Capsys) -> None:
    capsys.readouterr()
    assert main(["-i", demo, "describe", "panther-01", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert list(doc)[:3] == ["schema", "command", "exit_code"]
