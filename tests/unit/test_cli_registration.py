"""Start-up: typer registers only the command group a run needs; --help still lists them all."""

from __future__ import annotations

import subprocess
import sys

import pytest

from panther_ops.cli import app as cli_app

TOP = ["status", "doctor", "apply", "trust", "config", "driver", "shutdown", "inventory", "demo", "bt", "lights",
       "manager"]


@pytest.mark.parametrize(("argv", "word"), [
    (["status", "--all"], "status"),
    (["-i", "fleet.yaml", "config", "set", "wheel_type", "WH02"], "config"),
    (["--inventory", "fleet.yaml", "-v", "driver", "status"], "driver"),
    (["--inventory=fleet.yaml", "--debug", "shutdown", "check"], "shutdown"),
    (["-vi", "fleet.yaml", "apply"], "apply"),
    (["-ifleet.yaml", "status"], "status"),
    (["-vv", "trust", "r1"], "trust"),
    (["--help"], None),
    (["-h"], None),
    (["-i", "x", "--version"], None),
    ([], None),
    (["-i", "x"], None),
])
def test_command_word(argv: list[str], word: str | None) -> None:
    assert cli_app._command_word(argv) == word


def test_every_top_level_command_has_its_modules() -> None:
    cli_app._register(None)
    names = [c.name for c in cli_app.app.registered_commands] + [g.name for g in cli_app.app.registered_groups]
    assert sorted(n for n in names if n) == sorted(TOP)
    assert set(cli_app._NEEDS) == set(TOP)


def _help(*argv: str) -> str:
    proc = subprocess.run([sys.executable, "-m", "panther_ops.cli.app", *argv], capture_output=True, text=True,
                          check=True, env={"COLUMNS": "200", "PATH": "/usr/bin:/bin"})
    return proc.stdout


def test_root_help_lists_every_command_in_a_fresh_process() -> None:
    out = _help("--help")
    listed = [line.split()[0] for line in out.split("Commands:", 1)[1].splitlines() if line.strip()]
    assert sorted(listed) == sorted(TOP)


def test_a_group_run_registers_what_it_needs() -> None:
    out = _help("config", "--help")
    for sub in ("get", "set", "unset", "diff", "history", "rollback", "push", "pull", "restore-defaults"):
        assert f"  {sub} " in out, sub


def test_runs_in_one_process_add_groups_in_help_order(capsys: pytest.CaptureFixture[str]) -> None:
    assert cli_app.main(["lights", "--help"]) == 0
    assert cli_app.main(["config", "--help"]) == 0
    capsys.readouterr()
    assert cli_app.main(["--help"]) == 0
    out = capsys.readouterr().out
    listed = [line.split()[0] for line in out.split("Commands:", 1)[1].splitlines() if line.strip()]
    assert sorted(listed) == sorted(TOP)
    assert listed.index("config") < listed.index("lights"), "help keeps its order whatever ran first"
