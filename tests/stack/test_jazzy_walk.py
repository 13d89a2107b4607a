"""A Jazzy robot is handled by every command that handles a 2.2 robot (issue 25's acceptance).

The walk takes the commands from the typer application itself (`tests.badinput.commands`), so a
command added later is walked, or listed here with its reason, or this test fails. Every command
that targets robots runs on the demo fleet's husarion_ugv 2.2.2 robot (panther-03) and on its
2.3.2 robot (panther-04), with the same arguments, each run on its own copy of the fleet:
read-only, --dry-run where the command writes, and a real write plus rollback where the demo's
local transport allows it (`config set` / `config rollback`). The 2.3.2 robot must be handled:
exit 0 or the 2.2 robot's own exit code, the same kind of outcome, its own stack read (no
"not supported", no internal error, no traceback), and 2.3's facts where they differ (the
catalogue: use_madgwick_filter on 2.3.2 only, publish_robot_state on 2.2 only).

What the demo fleet cannot run (a terminal, SSH, a docker engine, a LAN) is listed in
`ELSEWHERE` (or, where the demo robot skips the robot's part, `DEMO_SKIPS`) with the reason and
the lab test that runs it, on a lab with a 2.3.2 robot.
"""

from __future__ import annotations

import io
import json
import re
import shutil
from pathlib import Path
from typing import Any

import pytest

from panther_ops.cli.app import main
from panther_ops.core.fleet.templates import template_path
from tests.badinput.commands import Command, every_command

HUMBLE, JAZZY = "panther-03", "panther-04"
"""The demo fleet's husarion_ugv 2.2.2 and 2.3.2 robots (panther_ops/core/demo/fleet.py)."""
ROOT = Path(__file__).resolve().parents[2]
HOSTS = str(template_path("config", "husarion-ugv-2.2", "husarion_ugv_manager", "config", "shutdown_hosts.yaml"))
ANIMATIONS = str(template_path("config", "husarion-ugv-2.2", "husarion_ugv_lights", "config", "user_animations.yaml"))
"""husarion_ugv's stock user animations file (the same at 2.2.2 and 2.3.2)."""

WALK: dict[str, list[list[str]]] = {
    "status": [[]],
    "doctor": [[]],
    "describe": [["{robot}"]],
    "apply": [["--dry-run"]],
    "config get": [["wheel_type"], ["controller.linear.x.max_velocity"], ["namespace"]],
    "config set": [["wheel_type", "WH02", "--dry-run"], ["controller.linear.x.max_velocity", "1.5", "--dry-run"]],
    "config unset": [["wheel_type", "--dry-run"]],
    "config diff": [[]],
    "config history": [[]],
    "config rollback": [["--dry-run"]],
    "config push": [["{tmp}/{robot}-controller.yaml", "--as", "controller", "--dry-run"]],
    "config pull": [["controller"], ["components"]],
    "config restore-defaults": [["--dry-run"]],
    "driver status": [[]],
    "driver logs": [[]],
    "driver restart": [["--dry-run"]],
    "driver stop": [["--dry-run"]],
    "driver start": [["--dry-run"]],
    "driver versions": [[]],
    "driver update": [["jazzy-2.3.2-20260622", "--dry-run"], ["humble-2.2.2-20250702", "--dry-run"]],
    "shutdown setup": [["--host", "127.0.0.1", "--yes"]],
    "shutdown check": [[]],
    "shutdown robot": [["--dry-run"]],
    "shutdown hosts list": [[]],
    "shutdown hosts validate": [["{tmp}/hosts.yaml"]],
    "shutdown hosts add": [["--ip", "10.15.20.9", "--user", "husarion", "--dry-run"]],
    "shutdown hosts remove": [["--ip", "10.15.20.3", "--dry-run"]],
    "inventory list": [[]],
    "inventory show": [["{robot}"]],
    "lights deploy": [[ANIMATIONS, "--dry-run"]],
    "lights test": [["16"]],
    "manager deploy": [["--dry-run"]],
    "manager remove": [["--dry-run"]],
    "manager status": [[]],
    "manager logs": [[]],
    "gps enable": [["--dry-run"]],
    "gps disable": [["--dry-run"]],
    "gps status": [[]],
    "gps watch": [["--count", "2", "--window", "0.5"]],
    "estop status": [[]],
    "estop trigger": [[]],
    "estop reset": [["--dry-run"]],
    "webui status": [[]],
    "webui get": [[]],
    "webui url": [[]],
    "webui install": [[]],
    "webui start": [[]],
    "webui stop": [[]],
    "webui set": [["webui.port=8081", "--dry-run"]],
    "reimage plan": [[]],
    "reimage backup": [["--out", "{tmp}/backups"]],
    "reimage restore": [["--from", "{tmp}/{robot}.tar.gz", "--dry-run"]],
}
"""Each robot-targeting command and its argument forms ({robot}: the robot walked, which is also
chosen with -r unless the command names it as an argument; {tmp}: the fixture's files)."""

DIFFERS: dict[tuple[str, int], tuple[int, str, str]] = {
    ("driver update", 1): (2, "has no backup of a migration from 2.2",
                           "the way back from 2.3 restores the migration's backup (none on a demo robot); "
                           "run in tests/driver/migrate/test_migrate_lab.py"),
}
"""Forms where the 2.3.2 robot's answer rightly differs from the 2.2 robot's: its exit code, a
piece of its message, why."""

ELSEWHERE: dict[str, tuple[str, str]] = {
    "trust": ("a robot's SSH host key: a demo robot is a directory and has none",
              "tests/fleet/test_foundation_lab.py"),
    "teleop": ("a terminal and the driver container's rclpy: a demo robot has neither",
               "tests/remote/teleop/test_teleop_lab.py"),
    "shutdown": ("--hosts --via ROBOT reaches the robot's LAN hosts over its SSH connection",
                 "tests/shutdown/test_shutdown_lab.py"),
    "gps router show": ("the RUTX11 router behind the robot's SSH connection", "tests/gps/test_gps_router_lab.py"),
    "gps router set": ("the RUTX11 router behind the robot's SSH connection", "tests/gps/test_gps_router_lab.py"),
}
"""Robot-targeting commands the demo fleet cannot run at all: the reason, the lab test that runs them."""

DEMO_SKIPS: dict[str, tuple[str, str]] = {
    "driver status": ("the driver container (a docker engine)", "tests/driver/test_driver_lab.py"),
    "driver logs": ("the driver container's log (a docker engine)", "tests/driver/test_driver_lab.py"),
    "driver versions": ("the robot's images (a docker engine)", "tests/driver/test_driver_lab.py"),
    "lights test": ("the lights controller's service in the driver container",
                    "tests/manager_ops/test_manager_safety_lab.py"),
    "manager logs": ("the manager's container (a docker engine)", "tests/manager_ops/test_manager_lab.py"),
    "shutdown check": ("the hosts on the robot's LAN", "tests/shutdown/test_shutdown_lab.py"),
    "estop trigger": ("the driver's trigger service", "tests/remote/estop/test_estop_lab.py"),
    "webui start": ("the User Computer's snapd", "tests/remote/webui/test_webui_lab.py"),
}
"""Walked commands whose demo run skips the robot's part (said in their result): the reason and the
lab test that runs that part."""

NOT_ROBOTS: dict[str, str] = {
    "inventory validate": "checks the inventory file (every robot's entry), reaches no robot",
    "inventory export": "writes the inventory in Ansible's form, reaches no robot",
    "demo init": "creates the demo fleet's directories",
    "bt validate": "a local BT project file (stack-independent: BehaviorTree.CPP's schema)",
    "lights validate": "a local animations file (its --stack is walked in test_stack_option_takes_232)",
    "lights preview": "renders a local animations file to an image",
    "manager run": "runs the manager on this machine (--sim)",
    "gps listen": "listens for NMEA on this machine",
    "sim gps add": "edits a local simulation components file",
    "sim world show": "reads a local Gazebo world",
    "sim world set": "edits a local Gazebo world",
    "sim battery check": "checks a local battery plugin file",
    "sim battery charge": "calls a local simulation's charging service",
    "reimage flash": "writes a card (a block device of this machine)",
    "reimage verify": "reads a card back",
    "reimage bmap": "a local disk image",
}
"""Commands that target no robot, with what they work on instead."""


def _targets_robots(c: Command) -> bool:
    return c.option("--robot") is not None or any(a.name == "name" for a in c.arguments)


def test_every_command_is_walked_or_listed() -> None:
    commands = {str(c): c for c in every_command()}
    assert len(commands) > 60
    robots = {n for n, c in commands.items() if _targets_robots(c)}
    listed = [*WALK, *ELSEWHERE, *NOT_ROBOTS]
    assert len(listed) == len(set(listed)), "a command is in two lists"
    assert set(listed) == set(commands), ("a command neither walked nor listed with its reason",
                                           sorted(set(commands) ^ set(listed)))
    assert robots <= set(WALK) | set(ELSEWHERE), sorted(robots & set(NOT_ROBOTS))
    assert set(DEMO_SKIPS) <= set(WALK)
    for command, (_, test) in {**ELSEWHERE, **DEMO_SKIPS}.items():
        text = (ROOT / test).read_text()
        words = ", ".join(f'"{w}"' for w in command.split())
        assert words in text, (command, test)  # the lab test runs the command
        # on a lab with a 2.3.2 robot: the shared jazzy_lab, or its own images
        assert re.search(r'jazzy_lab|images=\([^)]*"2\.3\.2"', text), (command, test)


@pytest.fixture(scope="module")
def fleet(tmp_path_factory: pytest.TempPathFactory) -> Path:
    tmp = tmp_path_factory.mktemp("jazzy-walk")
    assert main(["demo", "init", "--dest", str(tmp / "demo")]) == 0
    for robot in (HUMBLE, JAZZY):
        assert main(["-i", str(tmp / "demo"), "config", "pull", "controller", "-r", robot, "--output",
                     str(tmp / f"{robot}-controller.yaml")]) == 0
        assert main(["-i", str(tmp / "demo"), "reimage", "backup", "-r", robot, "--out", str(tmp / "archives")]) == 0
        (archive,) = (tmp / "archives").glob(f"{robot}-*.tar.gz")
        shutil.copy(archive, tmp / f"{robot}.tar.gz")
    (tmp / "hosts.yaml").write_text("hosts:\n  - ip: 10.15.20.3\n    username: husarion\n")
    return tmp


def _run(fleet: Path, tmp: Path, command: str, args: list[str], robot: str,
         capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> tuple[int, str, str]:
    demo = tmp / robot / "demo"  # a fleet of its own: a write on one robot's run never shows in the other's
    shutil.copytree(fleet / "demo", demo, symlinks=True)
    monkeypatch.chdir(demo.parent)
    monkeypatch.setattr("sys.stdin", io.StringIO(""))
    words = [a.format(tmp=fleet, robot=robot) for a in args]
    select = [] if "{robot}" in args else ["-r", robot]
    argv = ["-i", str(demo), *command.split(), *words, *select, "--json"]
    capsys.readouterr()
    code = main(argv)
    out, err = capsys.readouterr()
    assert "internal error" not in err.lower() and "Traceback" not in out + err, (argv, err)
    assert "not supported" not in (out + err).lower(), (argv, out, err)
    return code, out, err


def _robot(doc: dict[str, Any], robot: str) -> dict[str, Any] | None:
    return next((r for r in doc.get("robots", []) if r.get("robot") == robot), None)


_ALIKE = {"ok": "done", "changed": "done", "skipped": "skipped", "failed": "failed", "rolled-back": "failed",
          "unreachable": "unreachable"}

CASES = [(c, i) for c, forms in WALK.items() for i in range(len(forms))]


@pytest.mark.parametrize(("command", "form"), CASES, ids=[f"{c}#{i}" for c, i in CASES])
def test_the_232_robot_is_handled_as_the_22_robot(command: str, form: int, fleet: Path, tmp_path: Path,
                                                    capsys: pytest.CaptureFixture[str],
                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    args = WALK[command][form]
    got: dict[str, tuple[int, dict[str, Any], str]] = {}
    for robot in (HUMBLE, JAZZY):
        code, out, err = _run(fleet, tmp_path, command, args, robot, capsys, monkeypatch)
        got[robot] = code, json.loads(out), err
    (hcode, hdoc, _), (jcode, jdoc, jerr) = got[HUMBLE], got[JAZZY]
    if (command, form) in DIFFERS:
        code, text, _ = DIFFERS[command, form]
        assert jcode == code and text in jerr + json.dumps(jdoc), (jcode, jerr)
        return
    assert jcode in (0, hcode), f"{command} {args}: 2.2.2 exit {hcode}, 2.3.2 exit {jcode}\n{jerr}"
    humble, jazzy = _robot(hdoc, HUMBLE), _robot(jdoc, JAZZY)
    if humble is None:  # a document about the inventory (inventory show): the robot's entry, not its stack
        assert jazzy is None and jcode == hcode
        return
    assert jazzy is not None, jdoc
    assert _ALIKE[jazzy["outcome"]] == _ALIKE[humble["outcome"]], (command, args, humble, jazzy)
    if jazzy["outcome"] == "skipped":
        assert command in DEMO_SKIPS, f"{command}: skipped on the demo robot ({jazzy['message']}): list it in DEMO_SKIPS"
    htext, jtext = json.dumps(humble), json.dumps(jazzy)
    if re.search(r"husarion_ugv 2\.2\.2|humble-2\.2\.2", htext):  # the 2.2 robot's stack is named: so is 2.3.2's
        assert re.search(r"husarion_ugv 2\.3\.2|jazzy-2\.3\.2", jtext), (command, args, jazzy)
        targets_humble = "humble-2.2.2" in args
        assert targets_humble or not re.search(r"husarion_ugv 2\.2\.2|humble-2\.2\.2", jtext), (command, jazzy)


def test_stack_option_takes_232(capsys: pytest.CaptureFixture[str]) -> None:
    """The commands that check a file for a stack (--stack) know 2.3.2 as they know 2.2.2."""
    with_stack = {str(c): c for c in every_command() if c.option("--stack") is not None}
    assert set(with_stack) == {"lights validate", "shutdown hosts validate"}
    for name, file in (("lights validate", ANIMATIONS), ("shutdown hosts validate", HOSTS)):
        c = with_stack[name]
        codes = []
        for stack in ("2.2.2", "2.3.2"):
            capsys.readouterr()
            codes.append(main([*c.words, file, "--stack", stack, "--json"]))
            out, err = capsys.readouterr()
            assert json.loads(out)["exit_code"] == codes[-1] and "not supported" not in (out + err).lower()
        assert codes == [0, 0], (str(c), codes)


# --- 2.3's own facts, on the same two robots -------------------------------------------------


def _cli(demo: Path, capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, dict[str, Any], str]:
    capsys.readouterr()
    code = main(["-i", str(demo), *argv, "--json"])
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err
    return code, (json.loads(out) if out.strip() else {}), err


@pytest.mark.parametrize(("key", "has", "lacks"), [
    # husarion_ugv_ros@2.3.2:husarion_ugv_bringup/launch/bringup.launch.py declares use_madgwick_filter,
    # @2.2.2 does not; @2.2.2 declares publish_robot_state, @2.3.2 does not
    ("use_madgwick_filter", JAZZY, HUMBLE),
    ("publish_robot_state", HUMBLE, JAZZY),
])
def test_catalogue_per_robot(key: str, has: str, lacks: str, fleet: Path, tmp_path: Path,
                             capsys: pytest.CaptureFixture[str]) -> None:
    demo = tmp_path / "demo"
    shutil.copytree(fleet / "demo", demo, symlinks=True)
    code, doc, err = _cli(demo, capsys, "config", "set", key, "true", "-r", has, "--dry-run")
    assert code == 0, err
    assert _robot(doc, has)["outcome"] == "changed"  # type: ignore[index]
    code, doc, err = _cli(demo, capsys, "config", "set", key, "true", "-r", lacks, "--dry-run")
    assert code == 2 and f"{key} needs" in err and "this robot runs husarion_ugv" in err, err
    # both at once: each robot planned against its own stack; refused as a whole, nothing written
    code, doc, err = _cli(demo, capsys, "config", "set", key, "true", "-r", has, "-r", lacks, "--dry-run")
    assert code == 2 and lacks in err, err

    code, doc, _ = _cli(demo, capsys, "config", "get", key, "-r", has, "-r", lacks)
    assert code == 0
    yes, no = _robot(doc, has), _robot(doc, lacks)
    assert yes is not None and yes["outcome"] == "ok" and yes["data"]["source"] == "default"
    assert no is not None and no["outcome"] == "skipped" and no["data"]["value"] is None, no
    assert f"{key} needs" in no["message"], no


@pytest.mark.parametrize("robot", [HUMBLE, JAZZY])
def test_a_real_write_and_its_rollback(robot: str, fleet: Path, tmp_path: Path,
                                       capsys: pytest.CaptureFixture[str]) -> None:
    """`config set` writes the robot's compose.yaml (local transport: the demo allows it), then
    `config rollback` restores it byte for byte; the 2.3.2 robot takes 2.3.2's own argument."""
    demo = tmp_path / "demo"
    shutil.copytree(fleet / "demo", demo, symlinks=True)
    compose = demo / "robots" / robot / "home" / "husarion" / "compose.yaml"
    before = compose.read_bytes()
    key = "use_madgwick_filter" if robot == JAZZY else "publish_robot_state"
    for argv, value in ((("config", "set", "wheel_type", "WH02"), "WH02"), (("config", "set", key, "true"), "true")):
        code, doc, err = _cli(demo, capsys, *argv, "-r", robot, "--yes")
        assert code == 0 and _robot(doc, robot)["outcome"] == "changed", err  # type: ignore[index]
        assert f"{argv[2]}:={value}" in compose.read_text()
        code, doc, err = _cli(demo, capsys, "config", "get", argv[2], "-r", robot)
        assert code == 0 and str(_robot(doc, robot)["data"]["value"]).lower() == value.lower()  # type: ignore[index]
    code, doc, _ = _cli(demo, capsys, "config", "history", "-r", robot)
    history = _robot(doc, robot)["data"]["history"]  # type: ignore[index]
    assert code == 0 and [h["command"] for h in history] == ["config set wheel_type WH02", f"config set {key} true"]
    code, doc, err = _cli(demo, capsys, "config", "rollback", "-r", robot, "--to", history[0]["id"], "--yes")
    assert code == 0 and _robot(doc, robot)["outcome"] == "changed", err  # type: ignore[index]
    assert compose.read_bytes() == before
