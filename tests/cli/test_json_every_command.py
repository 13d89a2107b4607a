"""Every command that takes --json prints exactly one JSON document on stdout (docs/json.md).

The commands are discovered from the application: a new command with --json and no entry in
VALID fails here until it gets one.
"""

from __future__ import annotations

import io
import json
import shutil
from pathlib import Path

import pytest

from panther_ops.cli.app import main
from panther_ops.core.fleet.templates import template_path
from tests.badinput.commands import every_command
from tests.sim_world import WORLD

R = ["-r", "panther-01"]
VALID: dict[str, list[str]] = {
    "status": ["--all"],
    "doctor": ["--all"],
    "describe": ["panther-01"],
    "apply": ["--all", "--dry-run"],
    "config get": ["wheel_type", "--all"],
    "config set": ["wheel_type", "WH02", *R, "--dry-run"],
    "config unset": ["wheel_type", *R, "--dry-run"],
    "config diff": ["--all"],
    "config history": ["--all"],
    "config rollback": [*R, "--dry-run"],
    "config push": ["{tmp}/controller.yaml", "--as", "controller", *R, "--dry-run"],
    "config pull": ["controller", *R],
    "config restore-defaults": [*R, "--dry-run"],
    "driver status": ["--all"],
    "driver logs": R,
    "driver restart": [*R, "--dry-run"],
    "driver stop": [*R, "--dry-run"],
    "driver start": [*R, "--dry-run"],
    "driver versions": ["--all"],
    "driver update": ["humble-2.1.1-20240828", *R, "--dry-run"],
    "shutdown": ["--hosts", "{tmp}/hosts.yaml", "--dry-run"],
    "shutdown setup": ["--host", "127.0.0.1", *R, "--yes"],
    "shutdown check": R,
    "shutdown robot": [*R, "--dry-run"],
    "shutdown hosts list": R,
    "shutdown hosts validate": ["{tmp}/hosts.yaml"],
    "shutdown hosts add": ["--ip", "10.15.20.9", "--user", "husarion", *R, "--dry-run"],
    "shutdown hosts remove": ["--ip", "10.15.20.3", *R, "--dry-run"],
    "inventory list": [],
    "inventory show": ["panther-01"],
    "inventory validate": [],
    "bt validate": [str(template_path("behavior_trees", "PantherSafetyBT.btproj"))],
    "lights validate": [str(template_path("lights", "user_animations.example.yaml"))],
    "lights deploy": [str(template_path("lights", "user_animations.example.yaml")), *R, "--dry-run"],
    "lights test": ["21", *R],
    "manager run": ["--sim", "--scenario", "low_battery", "--duration", "3"],
    "manager deploy": [*R, "--dry-run"],
    "manager remove": [*R, "--dry-run"],
    "manager status": ["--all"],
    "manager logs": R,
    "reimage plan": R,
    "reimage backup": [*R, "--out", "{tmp}/backups"],
    "reimage restore": [*R, "--from", "{tmp}/panther-01.tar.gz", "--yes"],
    "lights preview": [str(template_path("lights", "user_animations.example.yaml")), "--id", "21", "--out",
                       "anim.gif"],
    "demo init": ["--dest", "another-demo"],
    "gps enable": [*R, "--dry-run"],
    "gps disable": [*R, "--dry-run"],
    "gps status": R,  # a demo robot answers with its recorded NMEA
    "gps watch": [*R, "--count", "2", "--window", "0.5"],
    "sim gps add": [str(template_path("config", "panther-2.1", "panther_description", "config", "components.yaml")),
                    "--dry-run"],
    "sim world show": ["{tmp}/world.sdf"],
    "sim world set": ["{tmp}/world.sdf", "--latitude", "52.2297", "--longitude", "21.0122", "--dry-run"],
    "sim battery charge": ["start", "--dry-run"],
    "sim battery check": [str(template_path("config", "panther-2.1", "panther_gazebo", "config",
                                            "battery_plugin_config.yaml"))],
    "estop status": ["--all"],
    "estop trigger": ["--all"],
    "estop reset": [*R, "--dry-run"],
    "webui status": ["--all"],
    "webui get": R,
    "webui url": R,
    "webui install": R,
    "webui start": R,
    "webui stop": R,
    "webui set": ["webui.port=8081", *R, "--dry-run"],
}
"""Arguments that make each command valid on the demo fleet (a demo robot has no docker engine
or SSH: some commands report that per robot, in their JSON document)."""


LOCAL_FILE: list[tuple[str, list[str]]] = [
    ("config history", ["--file", "{tmp}/local/hosts.yaml"]),
    ("config rollback", ["--file", "{tmp}/local/hosts.yaml", "--dry-run"]),
    ("config rollback", ["--file", "{tmp}/local/hosts.yaml", "--yes"]),
    ("shutdown hosts add", ["{tmp}/local/hosts.yaml", "--ip", "10.15.20.9", "--user", "pi", "--dry-run"]),
    ("shutdown hosts remove", ["{tmp}/local/hosts.yaml", "--ip", "10.15.20.3", "--dry-run"]),
]
"""The forms on a local hosts file (its backups beside it, in the fixture's local/): each prints
one JSON document too."""

ON_A_DEVICE = {
    "reimage flash": "tests/reimage/test_reimage_flash_lab.py",
    "reimage verify": "tests/reimage/test_reimage_flash_lab.py",
}
"""Commands whose valid input is a block device: their --json runs on loop devices in the lab test named."""

ELSEWHERE = {
    **ON_A_DEVICE,
    # the RUTX11 router (credentials, REST API behind a robot's SSH): the lab's stand-in router
    "gps router show": "tests/gps/test_gps_router_lab.py",
    "gps router set": "tests/gps/test_gps_router_lab.py",
    # a disk image with partitions and file systems, made with sfdisk/mkfs/mcopy by the test
    "reimage bmap": "tests/reimage/test_reimage_bmap.py",
    # NMEA from a sender: the test sends real datagrams over loopback
    "gps listen": "tests/gps/test_gps_listen.py",
    # a host key: a demo robot is a directory and has none (the lab's robots have sshd)
    "trust": "tests/fleet/test_foundation_lab.py",
}
"""Commands whose valid input the demo fleet cannot give: the test named runs them with --json and parses it."""

JSON_COMMANDS = sorted(str(c) for c in every_command() if c.option("--json") and str(c) not in ELSEWHERE)


def test_every_json_command_has_valid_arguments() -> None:
    assert len(JSON_COMMANDS) > 30
    assert set(JSON_COMMANDS) == set(VALID), "a command with --json needs an entry in VALID (and only those)"
    every = {str(c) for c in every_command() if c.option("--json")}
    assert set(ELSEWHERE) <= every
    for command, test in ELSEWHERE.items():  # that test runs it with --json and parses it
        text = (Path(__file__).resolve().parents[2] / test).read_text()
        words = ", ".join(f'"{w}"' for w in command.split())
        # json.loads there, or tests.clirun.run_cli, which parses a --json run's output with it
        parses = "json.loads" in text or "from tests.clirun import run_cli" in text
        assert words in text and '"--json"' in text and parses, (command, test)


@pytest.fixture(scope="module")
def fleet(tmp_path_factory: pytest.TempPathFactory) -> Path:
    tmp = tmp_path_factory.mktemp("json")
    assert main(["demo", "init", "--dest", str(tmp / "demo")]) == 0
    assert main(["-i", str(tmp / "demo"), "config", "pull", "controller", *R, "--output",
                 str(tmp / "controller.yaml")]) == 0
    (tmp / "hosts.yaml").write_text("hosts:\n  - ip: 10.15.20.3\n    username: husarion\n")
    (tmp / "world.sdf").write_text(WORLD)
    (tmp / "local").mkdir()
    (tmp / "local" / "hosts.yaml").write_text("hosts:\n  - ip: 10.15.20.3\n    username: husarion\n")
    assert main(["shutdown", "hosts", "add", str(tmp / "local" / "hosts.yaml"), "--ip", "10.15.20.4", "--user", "pi",
                 "--yes"]) == 0  # a backup to list and roll back to
    assert main(["-i", str(tmp / "demo"), "reimage", "backup", *R, "--out", str(tmp / "backups")]) == 0
    (archive,) = (tmp / "backups").glob("panther-01-*.tar.gz")
    shutil.copy(archive, tmp / "panther-01.tar.gz")  # a name the arguments above can give
    return tmp


@pytest.mark.parametrize("command", JSON_COMMANDS)
def test_one_json_document(command: str, fleet: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                           monkeypatch: pytest.MonkeyPatch) -> None:
    _one_document(command, VALID[command], fleet, tmp_path, capsys, monkeypatch)


@pytest.mark.parametrize(("command", "args"), LOCAL_FILE, ids=[f"{c} {' '.join(a[2:])}" for c, a in LOCAL_FILE])
def test_one_json_document_on_a_local_file(command: str, args: list[str], fleet: Path, tmp_path: Path,
                                           capsys: pytest.CaptureFixture[str],
                                           monkeypatch: pytest.MonkeyPatch) -> None:
    local = tmp_path / "local"  # its own copy of the file and its backups
    shutil.copytree(fleet / "local", local)
    _one_document(command, [a.replace("{tmp}/local", str(local)) for a in args], fleet, tmp_path, capsys,
                  monkeypatch)


def _one_document(command: str, args: list[str], fleet: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                  monkeypatch: pytest.MonkeyPatch) -> None:
    demo = tmp_path / "demo"  # each command on its own copy: --dry-run or not, nothing leaks
    shutil.copytree(fleet / "demo", demo, symlinks=True)
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr("sys.stdin", io.StringIO(""))
    argv = ["-i", str(demo), *command.split(), *(a.format(tmp=fleet) for a in args), "--json"]
    capsys.readouterr()
    code = main(argv)
    out, err = capsys.readouterr()
    assert code != 1 and "internal error" not in err, f"{argv}: exit {code}\n{err}"
    try:
        doc = json.loads(out)
    except json.JSONDecodeError as exc:
        raise AssertionError(f"panther-ops {' '.join(argv)}: stdout is not one JSON document ({exc})\n"
                             f"--- stdout\n{out}\n--- stderr\n{err}") from None
    assert isinstance(doc, dict) and doc.get("schema") == 1, doc
    assert isinstance(doc.get("command"), str) and doc["command"].startswith(command), doc  # one shape
    assert doc.get("exit_code") == code, f"{argv}: exit {code}, the document says {doc.get('exit_code')}"


ALL_JSON_COMMANDS = sorted(str(c) for c in every_command() if c.option("--json"))


@pytest.mark.parametrize("command", ALL_JSON_COMMANDS)
def test_a_usage_error_is_one_json_document_too(command: str, tmp_path: Path,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    """An error (exit 2) printed nothing on stdout with --json: now the error's document, with
    ``command`` and ``exit_code`` as every other (issue 26), the message still on stderr."""
    argv = ["-i", str(tmp_path / "none"), *command.split(), "--no-such-option", "--json"]
    capsys.readouterr()
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 2 and "No such option: --no-such-option" in err, (argv, code, err)
    doc = json.loads(out)
    assert doc["schema"] == 1 and doc["command"] == command and doc["exit_code"] == 2, doc
    assert doc["error"]["code"] == "USAGE" and "--no-such-option" in doc["error"]["message"], doc


ROBOT_COMMANDS = sorted(c for c in JSON_COMMANDS if any(a in ("-r", "--all") for a in VALID[c]))


@pytest.mark.parametrize("command", ROBOT_COMMANDS)
def test_a_robot_not_in_the_inventory_is_one_json_error_document(
        command: str, fleet: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A robot the inventory does not have: exit 2 before anything is contacted, and the error's
    document names the inventory and what is allowed."""
    args = [a for a in VALID[command] if a not in ("--all", *R)]
    demo = tmp_path / "demo"
    shutil.copytree(fleet / "demo", demo, symlinks=True)
    argv = ["-i", str(demo), *command.split(), *(a.format(tmp=fleet) for a in args), "-r", "no-such-robot", "--json"]
    capsys.readouterr()
    code = main(argv)
    out, err = capsys.readouterr()
    doc = json.loads(out)
    assert code == doc["exit_code"] == 2 and doc["command"].startswith(command), (argv, doc, err)
    assert doc["error"]["type"] == "InventoryError" and "no-such-robot" in doc["error"]["message"], doc
    assert doc["error"]["hint"].startswith("robots: panther-01"), doc


def test_bad_input_for_each_robot_is_one_json_error_document(fleet: Path, tmp_path: Path,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    """A value refused per robot while planning (each robot's stack decides): one error document
    with each robot's error, in inventory order."""
    demo = tmp_path / "demo"
    shutil.copytree(fleet / "demo", demo, symlinks=True)
    capsys.readouterr()
    code = main(["-i", str(demo), "config", "set", "wheel_type", "WH05", "--all", "--dry-run", "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert code == doc["exit_code"] == 2
    assert doc["error"]["code"] == "USAGE" and "nothing was changed" in doc["error"]["message"]
    assert list(doc["error"]["robots"]) == ["panther-01", "panther-02", "panther-03", "panther-04"]
    assert "Lynx" in doc["error"]["robots"]["panther-03"]["message"]
