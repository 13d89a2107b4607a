"""The write's robot side in Perl: chosen where the robot has perl, the shell script elsewhere.

The behaviour of both is checked by the apply/kept/early-staging session tests, each run both
ways (``robot_scripts``); these check which one a robot runs, and what the Perl one saves."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

from panther_ops.core.config.plans import plan_args
from panther_ops.core.fleet.inventory import Inventory
from panther_ops.core.fleet.pipeline import ApplyOptions, apply_plan
from panther_ops.core.fleet.runner import Connections, RobotContext
from panther_ops.results import Outcome
from panther_ops.transport import scripts_perl
from panther_ops.transport.base import Command

SHELL_TOOLS = ("sh", "tar", "head", "sync", "sha256sum", "mv", "rm", "rmdir", "chmod", "cat", "mkdir", "dirname")


def _bin_dir(tmp_path: Path, tools: tuple[str, ...], perl_log: Path | None = None) -> Path:
    """A PATH directory holding only ``tools`` (and, with ``perl_log``, a perl that logs its runs)."""
    d = tmp_path / "bin"
    d.mkdir()
    for tool in tools:
        found = shutil.which(tool)
        assert found, tool
        (d / tool).symlink_to(found)
    if perl_log is not None:
        real = shutil.which("perl")
        assert real
        wrapper = d / "perl"
        wrapper.write_text(f'#!/bin/sh\necho run >> "{perl_log}"\nexec "{real}" "$@"\n')
        wrapper.chmod(0o755)
    return d


def _change(demo: tuple[Inventory, Connections]) -> tuple[bytes, Path, str]:
    inv, conns = demo
    robot = inv.robots["panther-01"]
    ctx = RobotContext(robot, conns.get(robot), inv)
    plan = plan_args(ctx, {"wheel_type": "WH04"}, [])
    result = apply_plan(ctx, plan, ApplyOptions(restart=False, command="config set"))
    assert result.outcome is Outcome.CHANGED, result.message
    compose = ctx.transport.local_path(plan.edits[0].path)  # type: ignore[attr-defined]
    backup = ctx.transport.local_path(f"~/.panther-ops/backups/{result.data['backup']}")  # type: ignore[attr-defined]
    assert (backup / "files" / "0").read_bytes() == plan.edits[0].before
    return compose.read_bytes(), backup, str(result.data["backup"])


def test_a_robot_with_perl_runs_the_perl_program(demo_connections: tuple[Inventory, Connections], tmp_path: Path,
                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    log = tmp_path / "perl.log"
    monkeypatch.setenv("PATH", str(_bin_dir(tmp_path, SHELL_TOOLS, perl_log=log)))
    after, backup, _ = _change(demo_connections)
    assert b"wheel_type:=WH04" in after
    assert log.read_text() == "run\n", "the read and the write: one perl process"
    assert (backup / "status").read_text() == "applied (not recreated)\n"


def test_a_robot_without_perl_runs_the_shell_script(demo_connections: tuple[Inventory, Connections],
                                                    tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PATH", str(_bin_dir(tmp_path, SHELL_TOOLS)))
    after, backup, _ = _change(demo_connections)
    assert b"wheel_type:=WH04" in after
    assert (backup / "status").read_text() == "applied (not recreated)\n"


def test_both_leave_the_same_files(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from panther_ops.cli.app import main
    from panther_ops.core.fleet.inventory import load_inventory

    results = {}
    for way in ("1", "0"):
        monkeypatch.setenv("PANTHER_OPS_ROBOT_PERL", way)
        dest = tmp_path / f"demo{way}"
        assert main(["demo", "init", "--dest", str(dest)]) == 0
        inv = load_inventory(str(dest))
        with Connections(inv) as conns:
            after, backup, _ = _change((inv, conns))
        files = {p.relative_to(backup).as_posix(): (p.read_bytes(), p.stat().st_mode & 0o7777)
                 for p in sorted(backup.rglob("*")) if p.is_file()}
        manifest = files.pop("manifest.json")  # names this attempt (id, time): compared by shape
        files["manifest.json"] = (b"", manifest[1])
        results[way] = (after, files, backup.stat().st_mode & 0o7777)
    assert results["1"] == results["0"]


def test_the_command_offers_perl_first_then_the_shell(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("PANTHER_OPS_ROBOT_PERL", raising=False)
    cmd = scripts_perl.read_kept("~/compose.yaml", "@@m@@").render(reveal=True)
    assert cmd.startswith("command -v perl >/dev/null 2>&1 && exec perl -e ")
    assert "; exec sh -c " in cmd and cmd.endswith(" sh '~/compose.yaml' @@m@@")
    monkeypatch.setenv("PANTHER_OPS_ROBOT_PERL", "0")
    assert scripts_perl.read_kept("~/compose.yaml", "@@m@@").render(reveal=True).startswith("sh -c ")


def test_user_input_arrives_as_arguments_only() -> None:
    evil = ["~/x'; rm -rf / #.yaml", "$(touch /tmp/pwned)", "-e", "a\\b"]
    program = 'shift @ARGV; print join("\\n", @ARGV), "\\n"'
    rendered = Command.sh("exit 9", *evil, perl=program).render(reveal=True)
    out = subprocess.run(["sh", "-c", rendered], capture_output=True, text=True, check=False)
    assert (out.returncode, out.stdout.splitlines()) == (0, evil)


def test_the_perl_program_loads_no_module_and_is_strict_and_warning_free() -> None:
    for program in (scripts_perl.READ_KEPT_PERL, scripts_perl.APPLY_PERL):
        assert "use " not in program and "require " not in program
        check = subprocess.run(["perl", "-Mstrict", "-w", "-c", "-e", program], capture_output=True, text=True,
                               check=False, env={**os.environ, "LC_ALL": "C"})
        assert check.returncode == 0 and check.stderr.strip() == "-e syntax OK", check.stderr
