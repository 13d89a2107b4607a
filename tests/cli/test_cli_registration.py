"""Start-up: typer registers only the command group a run needs; --help still lists them all."""

from __future__ import annotations

import subprocess
import sys

import pytest

from panther_ops.cli import app as cli_app

TOP = ["status", "doctor", "describe", "apply", "trust", "config", "driver", "shutdown", "inventory", "demo", "bt",
       "lights", "manager", "gps", "sim", "estop", "webui",
       "teleop", "reimage"]


@pytest.mark.parametrize(("argv", "words"), [
    (["status", "--all"], ("status", None)),
    (["-i", "fleet.yaml", "config", "set", "wheel_type", "WH02"], ("config", "set")),
    (["--inventory", "fleet.yaml", "-v", "driver", "status"], ("driver", "status")),
    (["--inventory=fleet.yaml", "--debug", "shutdown", "check"], ("shutdown", "check")),
    (["-vi", "fleet.yaml", "apply"], ("apply", None)),
    (["-ifleet.yaml", "status"], ("status", None)),
    (["-vv", "trust", "r1"], ("trust", "r1")),
    (["config", "--help"], ("config", None)),
    (["--help"], (None, None)),
    (["-h"], (None, None)),
    (["-i", "x", "--version"], (None, None)),
    ([], (None, None)),
    (["-i", "x"], (None, None)),
])
def test_command_words(argv: list[str], words: tuple[str | None, str | None]) -> None:
    assert cli_app._command_words(argv) == words


def _built(*argv: str) -> dict[str, list[str]]:
    """What typer is given to build for ``argv``: {top-level word: its subcommands}."""
    cli_app._register(*cli_app._command_words(list(argv)))
    out: dict[str, list[str]] = {cli_app._name(c): [] for c in cli_app.app.registered_commands}
    for g in cli_app.app.registered_groups:
        assert g.name is not None and g.typer_instance is not None
        out[g.name] = [cli_app._name(c) for c in g.typer_instance.registered_commands]
    return out


def test_a_run_builds_only_its_own_command() -> None:
    assert _built("-i", "x", "config", "set", "wheel_type", "WH02") == {"config": ["set"]}
    assert _built("config", "restore-defaults", "--all") == {"config": ["restore-defaults"]}
    assert _built("status", "--all") == {"status": []}
    assert _built("driver", "update", "humble-2.2.1") == {"driver": ["update"]}


def test_a_group_without_the_subcommand_named_is_built_whole() -> None:
    whole = _built("config", "--help")["config"]
    assert {"get", "set", "unset", "push", "pull", "restore-defaults"} <= set(whole)
    assert _built("config", "sett")["config"] == whole  # click names the unknown one and lists the rest
    assert _built("config", "set")["config"] == ["set"]


def test_narrowing_leaves_the_command_modules_whole() -> None:
    _built("config", "set")
    from panther_ops.cli.commands import config

    names = [cli_app._name(c) for c in config.app.registered_commands]
    assert {"get", "set", "unset", "restore-defaults"} <= set(names)
    _built("--help")
    listed = {g.name for g in cli_app.app.registered_groups} | {cli_app._name(c) for c in cli_app.app.registered_commands}
    assert listed == set(TOP)


def test_a_narrowed_run_still_works_end_to_end(capsys: pytest.CaptureFixture[str]) -> None:
    assert cli_app.main(["config", "set", "--help"]) == 0
    assert "wheel_type" in capsys.readouterr().out
    assert cli_app.main(["config", "sett"]) == 2
    assert "No such command" in capsys.readouterr().err


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
