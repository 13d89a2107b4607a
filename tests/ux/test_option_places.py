"""Global options after the command and a command's options before it are taken where the user
put them (issue 26, finding 3: ``--json status`` suggested ``--version``; ``status -i DIR`` said
only "No such option: -i")."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from panther_ops.cli.app import full_command
from panther_ops.cli.argv_order import in_place
from tests.clirun import run

Capsys = pytest.CaptureFixture[str]


@pytest.mark.parametrize("argv", [
    ["--json", "-i", "{demo}", "status"],
    ["--json", "status", "-i", "{demo}"],
    ["status", "-i", "{demo}", "--json"],
    ["status", "--json", "--inventory={demo}", "-q", "--color", "never"],
    ["-q", "--json", "status", "--inventory", "{demo}", "--wide"],
])
def test_json_and_the_inventory_where_the_user_puts_them(argv: list[str], demo: Path, capsys: Capsys) -> None:
    code, out, err = run(capsys, *(a.format(demo=demo) for a in argv))
    doc = json.loads(out)
    assert code == doc["exit_code"] == 0 and doc["command"] == "status", err
    assert {r["robot"] for r in doc["robots"]} == {"panther-01", "panther-02", "panther-03", "panther-04"}
    assert f"inventory: {demo} (from -i)" in err


def test_a_global_option_after_a_subcommand_and_its_arguments(demo: Path, capsys: Capsys) -> None:
    code, out, err = run(capsys, "config", "get", "wheel_type", "-r", "panther-01", "-i", str(demo), "--color", "never")
    assert code == 0 and "panther-01" in out and "WH01" in out, err


def test_an_option_nobody_has_is_still_refused_by_name(demo: Path, capsys: Capsys) -> None:
    code, _, err = run(capsys, "--bogus", "status", "-i", str(demo))
    assert code == 2 and "No such option: --bogus" in err, err
    code, _, err = run(capsys, "status", "--nope", "-i", str(demo))
    assert code == 2 and "No such option: --nope" in err, err


def test_what_is_moved_and_what_stays() -> None:
    root = full_command()
    assert in_place(["status", "-i", "x", "-r", "a"], root) == ["-i", "x", "status", "-r", "a"]
    assert in_place(["--json", "-v", "status"], root) == ["-v", "status", "--json"]
    assert in_place(["-i", "x", "status", "--json"], root) == ["-i", "x", "status", "--json"]  # already right
    assert in_place(["status", "--", "-i", "x"], root) == ["status", "--", "-i", "x"]
    assert in_place(["config", "-i", "x"], root) == ["config", "-i", "x"]  # a group without its subcommand
    assert in_place(["status", "-r", "-i", "-i", "x"], root) == ["-i", "x", "status", "-r", "-i"]  # -r's value
