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
