"""The README's test command works as root without sudo installed, and as a user (issue 26,
finding 9: ``sudo bash scripts/test.sh`` failed at once on a fresh machine where the user is
root and sudo is not installed); CI runs that same command."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
from collections.abc import Iterator
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
TOOLS = ("bash", "id", "dirname", "env", "cat")
"""What scripts/test.sh needs before it creates the venv (a PATH with these and no sudo)."""


def readme_command() -> str:
    """The command of the README's "Run the tests" section."""
    text = (ROOT / "README.md").read_text()
    section = text.split("## Run the tests", 1)[1].split("\n## ", 1)[0]
    (block,) = re.findall(r"```sh\n(.*?)```", section, re.S)
    (line,) = [x for x in block.splitlines() if x.strip()]
    return line.strip()


def test_ci_runs_the_readme_command() -> None:
    """As written: the command alone on its line, or with only its exit code kept (``|| RC=$?``)."""
    command = readme_command()
    kept = re.compile(re.escape(command) + r"( \|\| \w+=\$\?)?")
    assert any(kept.fullmatch(line.strip()) for line in (ROOT / ".ci" / "run").read_text().splitlines())


@pytest.fixture
def open_tmp() -> Iterator[Path]:
    """A directory another user can reach (pytest's tmp_path is under a root-only directory)."""
    path = Path(tempfile.mkdtemp(prefix="panther-ops-test-command-"))
    path.chmod(0o755)
    try:
        yield path
    finally:
        shutil.rmtree(path)


def _bin(tmp_path: Path, sudo: bool) -> Path:
    """A PATH directory with the tools the script starts with; with ``sudo``, a test double of
    sudo that says on stdout what it was asked to run and runs nothing."""
    bin_ = tmp_path / "bin"
    bin_.mkdir()
    for tool in TOOLS:
        found = shutil.which(tool)
        assert found, tool
        (bin_ / tool).symlink_to(found)
    if sudo:
        (bin_ / "sudo").write_text(f"#!{shutil.which('bash')}\necho \"sudo (test double): $*\"\n")
        (bin_ / "sudo").chmod(0o755)
    return bin_


def _run(command: str, tmp_path: Path, path: Path, user: str | None = None) -> subprocess.CompletedProcess[str]:
    """``command`` (with an interpreter that does not exist, so the run stops where the venv would
    be made), from the checkout, with only ``path`` on PATH; as ``user`` when given."""
    argv = ["bash", "-c", f"{command} --python {tmp_path}/no-python --venv {tmp_path}/venv"]
    if user is not None:
        argv = [shutil.which("setpriv") or "setpriv", "--reuid", user, "--regid", "nogroup" if user == "nobody" else user, "--clear-groups", *argv]
    env = {"PATH": str(path), "HOME": str(tmp_path), "CI": "true"}
    return subprocess.run(argv, cwd=ROOT, env=env, capture_output=True, text=True, timeout=60, check=False)


@pytest.mark.skipif(os.geteuid() != 0, reason="needs root (as a fresh machine's user is)")
def test_the_readme_command_as_root_without_sudo(tmp_path: Path) -> None:
    run = _run(readme_command(), tmp_path, _bin(tmp_path, sudo=False))
    assert "sudo: command not found" not in run.stderr, run.stderr
    assert "== as root: system packages and the lab tests" in run.stderr, run.stderr
    assert f"{tmp_path}/no-python" in run.stderr  # it went on to make the venv


@pytest.mark.skipif(os.geteuid() != 0 or not shutil.which("setpriv"), reason="needs root to become another user")
def test_the_readme_command_as_a_user_runs_again_through_sudo(open_tmp: Path) -> None:
    tmp_path = open_tmp
    run = _run(readme_command(), tmp_path, _bin(tmp_path, sudo=True), user="nobody")
    assert "== not root: running again through sudo" in run.stderr, run.stderr
    assert run.returncode == 0, run.stderr  # the sudo double's exit: nothing after it ran
    (said,) = [x for x in run.stdout.splitlines() if x.startswith("sudo (test double): ")]
    args = said.split(": ", 1)[1].split()
    assert args[:3] == ["--preserve-env=CI", "bash", "scripts/test.sh"], args
    assert args[3:] == ["--python", f"{tmp_path}/no-python", "--venv", f"{tmp_path}/venv"], args


@pytest.mark.skipif(os.geteuid() != 0 or not shutil.which("setpriv"), reason="needs root to become another user")
def test_the_readme_command_as_a_user_without_sudo_says_what_to_do(open_tmp: Path) -> None:
    tmp_path = open_tmp
    run = _run(readme_command(), tmp_path, _bin(tmp_path, sudo=False), user="nobody")
    assert "not root and no sudo: for the system packages and the lab tests run it as root" in run.stderr
    assert "su -c 'bash scripts/test.sh'" in run.stderr
    assert f"{tmp_path}/no-python" in run.stderr, run.stderr  # and went on with what a user can run
