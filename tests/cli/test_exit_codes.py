"""Exit codes a script reads (docs/results.md): a closed pipe, a declined confirmation,
``config diff --exit-code``, a local configuration error (issue 26, finding 4)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from panther_ops.errors import ExitCode

ROOT = Path(__file__).resolve().parents[2]


def _run_into_closed_pipe(argv: list[str]) -> tuple[int, str]:
    """``panther-ops *argv`` (a real process) with stdout a pipe whose reader has already gone, as
    ``... | head -3`` is once head has its lines: exit code and stderr."""
    read, write = os.pipe()
    os.close(read)  # the reader is gone before the first write: every write is EPIPE
    env = {**os.environ, "PYTHONPATH": str(ROOT), "PYTHONDONTWRITEBYTECODE": "1"}
    try:
        proc = subprocess.run([sys.executable, "-m", "panther_ops.cli.app", *argv], stdout=write,
                              stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, text=True, env=env, timeout=120,
                              check=False)
    finally:
        os.close(write)
    return proc.returncode, proc.stderr


@pytest.mark.parametrize("args", [
    ["config", "set", "wheel_type", "WH02", "--all", "--dry-run"],  # a table, then diffs (rich)
    ["status", "--all", "--json"],  # one JSON document
    ["config", "pull", "controller", "-r", "panther-01"],  # the file's bytes as they are
], ids=["table-and-diffs", "json", "bytes"])
def test_a_closed_pipe_is_a_quiet_exit_141(args: list[str], demo: Path) -> None:
    """``panther-ops ... --dry-run | head -3`` exited 1 ("a bug") with no message: now the exit of a
    tool killed by SIGPIPE in a shell (128 + 13, as ``git log | head``), without a message."""
    code, err = _run_into_closed_pipe(["-i", str(demo), *args])
    assert code == ExitCode.CLOSED_PIPE == 141, err
    assert "internal error" not in err and "Traceback" not in err and "Broken pipe" not in err, err


def test_every_exit_code_is_documented() -> None:
    """docs/results.md's table has a row per exit code, with its number and name; --help names each."""
    from panther_ops.cli.app import HELP

    rows = (ROOT / "docs" / "results.md").read_text()
    for code in ExitCode:
        assert f"| {int(code)} | {code.name} |" in rows, code
        assert f" {int(code)} " in " ".join(HELP.split()), code


def test_declining_the_confirmation_is_exit_5_not_bad_input(demo: Path) -> None:
    """Answering no on a terminal exited 2 ("bad input"): now 5, nothing changed, no "error"."""
    from tests.ux.termrun import on_pty, plain

    compose = demo / "robots" / "panther-01" / "home" / "husarion" / "compose.yaml"
    before = compose.read_text()
    run = on_pty(["-i", str(demo), "config", "set", "wheel_type", "WH02", "-r", "panther-01"], cols=120, typed="n\n")
    shown = plain(run.out)
    assert "Apply to 1 robot: panther-01?" in shown, shown
    assert run.code == ExitCode.DECLINED == 5, shown
    assert "nothing was changed on any robot" in shown and "error" not in shown, shown
    assert compose.read_text() == before


def test_no_one_to_answer_is_still_bad_input(demo: Path) -> None:
    """Not interactive and no --yes: a usage error (exit 2), naming --yes."""
    from tests.ux.termrun import piped

    run = piped(["-i", str(demo), "config", "set", "wheel_type", "WH02", "-r", "panther-01"])
    assert run.code == ExitCode.USAGE, run
    assert "pass --yes" in run.err


def test_config_diff_exit_code_tells_drift(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``config diff`` exited 0 with drift shown, so a script could not tell: ``--exit-code`` says it
    (0 none, 6 drift, as ``git diff --exit-code``), in the JSON document too; without it, still 0."""
    from tests.clirun import run, run_cli

    inv = ["-i", str(demo)]
    code, _, err = run(capsys, *inv, "config", "diff", "--all", "--exit-code")
    assert code == ExitCode.DRIFT == 6, err  # the warehouse group wants WH02
    assert "(exit 6: drift)" in err
    code, doc, _, _ = run_cli(capsys, *inv, "config", "diff", "--all", "--exit-code", "--json")
    assert code == doc["exit_code"] == 6
    assert run(capsys, *inv, "config", "diff", "--all")[0] == 0  # a read: 0 without --exit-code
    assert run(capsys, *inv, "apply", "-g", "warehouse", "--yes", "--no-restart")[0] == 0
    code, doc, _, err = run_cli(capsys, *inv, "config", "diff", "--all", "--exit-code", "--json")
    assert code == doc["exit_code"] == 0, err
    assert {r["outcome"] for r in doc["robots"]} == {"ok"}


def test_a_missing_identity_file_is_bad_input_before_anything_is_contacted(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A key file that does not exist was reported as unreachable (exit 4, after connecting) and
    ``inventory validate`` said "valid": now exit 2 naming the file, line and key, with nothing
    contacted (a listening socket sees no connection), and validate reports it."""
    import json
    import socket

    from tests.clirun import run

    listener = socket.socket()
    listener.bind(("127.0.0.1", 0))
    listener.listen(8)
    listener.settimeout(0.5)
    port = listener.getsockname()[1]
    inv = tmp_path / "inv.yaml"
    inv.write_text(f"robots:\n  r1:\n    host: 127.0.0.1\n    port: {port}\n    identity_file: keys/id_ed25519\n"
                   f"  r2:\n    host: 127.0.0.1\n    port: {port}\n")
    try:
        for argv in (["status", "--all"], ["config", "set", "wheel_type", "WH02", "-r", "r1", "--dry-run"],
                     ["inventory", "validate"]):
            code, out, err = run(capsys, "-i", str(inv), *argv)
            assert code == ExitCode.USAGE, (argv, code, err)
            assert f"{inv}:3 [robots.r1.identity_file]" in err, err  # where r1 is defined
            assert f"identity_file {tmp_path / 'keys' / 'id_ed25519'} does not exist" in err, err
            assert "ssh-keygen -t ed25519" in err and "valid" not in out
        code, out, _ = run(capsys, "-i", str(inv), "inventory", "validate", "--json")
        doc = json.loads(out)
        assert code == doc["exit_code"] == 2 and doc["error"]["key"] == "robots.r1.identity_file", doc
        with pytest.raises(TimeoutError):
            listener.accept()  # nobody came
    finally:
        listener.close()
    (tmp_path / "keys").mkdir()
    (tmp_path / "keys" / "id_ed25519").write_text("not checked here: only that it is a readable file\n")
    code, out, err = run(capsys, "-i", str(inv), "inventory", "validate")
    assert code == 0 and "valid" in out, err
