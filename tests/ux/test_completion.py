"""Shell completion is installable for bash, zsh and fish (issue 16, Deliver), with the real
shells, in a throw-away HOME."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

CLI_DIR = Path(sys.executable).parent


def _cli() -> str:
    exe = shutil.which("panther-ops", path=str(CLI_DIR))
    assert exe, "the panther-ops entry point is installed next to the interpreter"
    return exe


def _shell(name: str) -> str:
    exe = shutil.which(name)
    assert exe, f"{name} is needed (scripts/install-test-deps.sh)"
    return exe


def _env(home: Path) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith("_")}
    env.update(HOME=str(home), PATH=f"{CLI_DIR}{os.pathsep}{env.get('PATH', '')}")
    return env


def _install(shell: str, home: Path) -> str:
    # ``; :`` keeps the shell as the parent process (no exec): the shell is detected from it
    p = subprocess.run([_shell(shell), "-c", "panther-ops --install-completion; :"], env=_env(home),
                       capture_output=True, text=True, timeout=60, check=True)
    return p.stdout


def test_bash_completion_installs_and_completes(tmp_path: Path) -> None:
    out = _install("bash", tmp_path)
    script = tmp_path / ".bash_completions" / "panther-ops.sh"
    assert f"bash completion installed in {script}" in out
    assert f"source '{script}'" in (tmp_path / ".bashrc").read_text()
    probe = (f"source '{script}'; COMP_WORDS=(panther-ops config s); COMP_CWORD=2; "
             "_panther_ops_completion panther-ops; printf '%s\\n' \"${COMPREPLY[@]}\"")
    got = subprocess.run([_shell("bash"), "-c", probe], env=_env(tmp_path), capture_output=True, text=True,
                         timeout=60, check=True).stdout.split()
    assert "set" in got and "get" not in got


def test_zsh_completion_installs_and_completes(tmp_path: Path) -> None:
    out = _install("zsh", tmp_path)
    func = tmp_path / ".zfunc" / "_panther-ops"
    assert f"zsh completion installed in {func}" in out
    assert "fpath+=~/.zfunc" in (tmp_path / ".zshrc").read_text()
    assert "compdef _panther_ops_completion panther-ops" in func.read_text()
    # what the installed function evaluates, asked the way it asks
    env = _env(tmp_path) | {"_TYPER_COMPLETE_ARGS": "panther-ops con", "_PANTHER_OPS_COMPLETE": "complete_zsh"}
    got = subprocess.run([_cli()], env=env, capture_output=True, text=True, timeout=60, check=True).stdout
    assert "config" in got and "status" not in got


def test_fish_completion_installs_and_completes(tmp_path: Path) -> None:
    out = _install("fish", tmp_path)
    path = tmp_path / ".config" / "fish" / "completions" / "panther-ops.fish"
    assert f"fish completion installed in {path}" in out
    got = subprocess.run([_shell("fish"), "-c", "complete -C 'panther-ops con'"], env=_env(tmp_path),
                         capture_output=True, text=True, timeout=60, check=True).stdout
    assert got.split()[:1] == ["config"], got


def test_help_lists_the_completion_options(capsys: pytest.CaptureFixture[str]) -> None:
    from panther_ops.cli.app import main

    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    assert "--install-completion" in out and "--show-completion" in out
