from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from panther_ops.cli.app import main


def test_status_json_on_demo_fleet(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    capsys.readouterr()
    assert main(["-i", str(demo), "status", "--all", "--json"]) == 0
    out, err = capsys.readouterr()
    doc = json.loads(out)
    assert doc["schema"] == 1 and doc["command"] == "status" and doc["exit_code"] == 0
    assert [r["data"]["stack_version"] for r in doc["robots"]] == ["2.1.1", "2.0.4", "2.2.2", "2.3.2"]
    assert [r["data"]["stack_generation"] for r in doc["robots"]][-2:] == ["2.2.1+", "2.3.2"]
    assert f"inventory: {demo} (from -i)" in err


def test_doctor_names_the_release_with_the_safety_fixes(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Every release before husarion_ugv 2.3.2 lacks the soft E-stop (#606/#607) and battery-dead (#596/#603)
    fixes: doctor warns on the Humble robots, naming 2.3.2; the demo's 2.3.2 robot has them."""
    capsys.readouterr()
    assert main(["-i", str(demo), "doctor", "--all", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    fixes = {r["robot"]: next(f for f in r["data"]["findings"] if f["check"] == "safety fixes") for r in doc["robots"]}
    for name in ("panther-01", "panther-02", "panther-03"):
        assert fixes[name]["state"] == "warn", fixes[name]
        assert "#606/#607" in fixes[name]["detail"] and "#596/#603" in fixes[name]["detail"]
        assert "first released in husarion_ugv 2.3.2" in fixes[name]["detail"] and "(Humble)" in fixes[name]["detail"]
    assert fixes["panther-04"]["state"] == "ok" and "husarion_ugv 2.3.2" in fixes["panther-04"]["detail"]


def test_doctor_fails_a_robot_on_a_driver_line_panther_ops_does_not_know(
        demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    compose = demo / "robots" / "panther-04" / "home" / "husarion" / "compose.yaml"
    compose.write_text(compose.read_text().replace("jazzy-2.3.2-20260622", "kilted-2.4.0-20270101"))
    capsys.readouterr()
    assert main(["-i", str(demo), "doctor", "-r", "panther-04", "--json"]) != 0
    (robot,) = json.loads(capsys.readouterr().out)["robots"]
    (stack,) = [f for f in robot["data"]["findings"] if f["check"] == "stack"]
    assert stack["state"] == "fail" and "stack kilted 2.4.0" in stack["detail"]


def test_status_table(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["-i", str(demo), "status", "-g", "warehouse"]) == 0
    out = capsys.readouterr().out
    assert "panther-01" in out and "panther-02" in out and "panther-03" not in out
    assert "panther_ros 2.1.1" in out


def test_no_selection_on_a_fleet_is_a_usage_error(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # a change insists on a choice; a read-only command answers for every robot (issue 16)
    assert main(["-i", str(demo), "driver", "restart", "--dry-run"]) == 2
    assert "choose with --robot" in capsys.readouterr().err


def test_bad_inventory_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text("robots:\n  r1: {host: a, port: nope}\n")
    assert main(["-i", str(bad), "inventory", "validate"]) == 2
    err = capsys.readouterr().err
    assert f"{bad}:2 [robots.r1.port]" in err


def test_unknown_option_is_usage(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["status", "--nope"]) == 2


def test_inventory_commands(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    capsys.readouterr()
    assert main(["-i", str(demo), "inventory", "list", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert [r["name"] for r in doc["robots"]] == ["panther-01", "panther-02", "panther-03", "panther-04"]
    assert main(["-i", str(demo), "inventory", "show", "panther-01", "--json"]) == 0
    shown = json.loads(capsys.readouterr().out)["robot"]
    assert shown["desired"] == {"launch_args": {"wheel_type": "WH02"}}
    assert main(["-i", str(demo), "inventory", "validate"]) == 0
    assert "4 robots, 2 groups, valid" in capsys.readouterr().out


def test_doctor_on_demo(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    capsys.readouterr()
    assert main(["-i", str(demo), "doctor", "--all", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    checks = {f["check"]: f["state"] for f in doc["robots"][0]["data"]["findings"]}
    assert checks["clock"] == "ok" and checks["stack"] == "ok"
    assert doc["data"]["fleet_findings"][0]["check"] == "time sync"


def test_cli_import_is_light() -> None:
    code = (
        "import sys, panther_ops.cli.app; "
        "bad = [m for m in ('paramiko', 'fabric', 'docker', 'ruamel', 'ruamel.yaml', 'rich', 'invoke') "
        "if m in sys.modules]; print(','.join(bad))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == ""


def test_help_texts_are_complete(capsys: pytest.CaptureFixture[str]) -> None:
    for argv in (["--help"], ["status", "--help"], ["doctor", "--help"], ["trust", "--help"],
                 ["inventory", "--help"], ["inventory", "validate", "--help"], ["demo", "init", "--help"]):
        assert main(argv) == 0
        out = capsys.readouterr().out
        assert "Usage:" in out
        if argv in (["--help"], ["inventory", "--help"]):  # a group: its commands listed
            assert "Commands" in out and "Example:" not in out, argv
        else:  # a command: with a real example (one, or several)
            marker = "Examples:" if "Examples:" in out else "Example:"
            assert marker in out and "panther-ops " in out.split(marker, 1)[1], argv


def test_the_background_imports_end_before_the_interpreter(demo: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """main() called in-process, then a normal exit: the interpreter waits for the background
    import instead of tearing down a thread inside one (it aborted: "FATAL: exception not
    rethrown", exit -6)."""
    import threading

    from panther_ops.cli import context

    started: list[threading.Thread] = []

    class Recorded(threading.Thread):
        def start(self) -> None:
            started.append(self)
            super().start()

    monkeypatch.setattr(threading, "Thread", Recorded)
    context._import_paramiko()
    assert [t.name for t in started] == ["import-paramiko"] and not started[0].daemon
    started[0].join(timeout=30)
    monkeypatch.undo()
    code = ("from panther_ops.cli.app import main; import sys; "
            f"sys.exit(main(['-i', {str(demo)!r}, 'status', '--all', '--json']))")
    for _ in range(3):
        done = subprocess.run([sys.executable, "-c", code], check=False, capture_output=True, text=True,
                              timeout=120)
        assert done.returncode == 0, done.stderr
