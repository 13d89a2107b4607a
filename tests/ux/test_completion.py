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


# ---------------------------------------------------------------- names from the inventory in use (issue 26)


def _complete(line: str, cwd: Path, env: dict[str, str] | None = None) -> tuple[list[str], str]:
    """What bash's installed function gets for the command ``line`` (its last word is being
    completed; a trailing space: an empty word), asked the way it asks the entry point."""
    words = line.split(" ")
    run_env = _env(cwd) | (env or {}) | {"_PANTHER_OPS_COMPLETE": "complete_bash",
                                         "COMP_WORDS": line, "COMP_CWORD": str(len(words) - 1)}
    p = subprocess.run([_cli()], env=run_env, cwd=cwd, capture_output=True, text=True, timeout=60, check=True)
    return p.stdout.split(), p.stderr


@pytest.fixture(scope="module")
def demo(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A directory with a demo fleet in ./demo-fleet (groups warehouse and field)."""
    home = tmp_path_factory.mktemp("complete")
    subprocess.run([_cli(), "demo", "init", "--dest", "demo-fleet"], env=_env(home), cwd=home,
                   capture_output=True, text=True, timeout=60, check=True)
    return home


ROBOTS = ["panther-01", "panther-02", "panther-03", "panther-04"]


def test_robot_names_after_r_from_the_i_given(demo: Path) -> None:
    assert _complete("panther-ops -i demo-fleet status -r ", demo) == (ROBOTS, "")
    assert _complete("panther-ops -i demo-fleet config set wheel_type WH02 -r panther-0", demo)[0] == ROBOTS
    # a robot given already is not offered again
    assert _complete("panther-ops -i demo-fleet status -r panther-01 -r ", demo)[0] == ROBOTS[1:]
    assert _complete("panther-ops -i demo-fleet describe ", demo)[0] == ROBOTS


def test_the_inventory_in_use_is_found_as_a_run_finds_it(demo: Path, tmp_path: Path) -> None:
    fleet = str(demo / "demo-fleet")
    # no -i: $PANTHER_OPS_INVENTORY, else ./inventory
    assert _complete("panther-ops status -g ", tmp_path, {"PANTHER_OPS_INVENTORY": fleet})[0] == ["warehouse", "field"]
    (tmp_path / "inventory").symlink_to(fleet)
    assert _complete("panther-ops estop status -r panther-03", tmp_path)[0] == ["panther-03"]
    # -i wins over the environment
    other = tmp_path / "other.yaml"
    other.write_text("version: 1\nrobots:\n  lab-r01:\n    host: 127.0.0.1\n")
    assert _complete(f"panther-ops -i {other} status -r ", tmp_path, {"PANTHER_OPS_INVENTORY": fleet})[0] == ["lab-r01"]


def test_groups_after_g_but_not_those_given(demo: Path) -> None:
    assert _complete("panther-ops -i demo-fleet apply -g ", demo)[0] == ["warehouse", "field"]
    assert _complete("panther-ops -i demo-fleet apply -g warehouse -g ", demo)[0] == ["field"]


def test_zsh_and_fish_see_what_each_name_is(demo: Path) -> None:
    env = _env(demo) | {"_TYPER_COMPLETE_ARGS": "panther-ops -i demo-fleet status -g ",
                        "_PANTHER_OPS_COMPLETE": "complete_zsh"}
    got = subprocess.run([_cli()], env=env, cwd=demo, capture_output=True, text=True, timeout=60, check=True).stdout
    assert '"warehouse":"indoor robots on mecanum wheels"' in got and '"field":"outdoor robots"' in got


def test_config_keys_kinds_and_scenarios(demo: Path) -> None:
    assert _complete("panther-ops config set wheel_t", demo)[0] == ["wheel_type"]
    keys = _complete("panther-ops config get ", demo)[0]
    assert {"wheel_type", "namespace", "controller.linear.x.max_velocity", "controller.linear.y.max_velocity"} <= set(keys)
    assert _complete("panther-ops config unset controller.angular.z.max_v", demo)[0] == [
        "controller.angular.z.max_velocity"]
    kinds = ["controller", "wheel", "components", "led", "user-animations", "bt-lights", "bt-safety",
             "shutdown-hosts", "battery", "joy2twist"]
    assert _complete("panther-ops config push my.yaml --as ", demo)[0] == kinds
    assert _complete("panther-ops config pull bt-", demo)[0] == ["bt-lights", "bt-safety"]
    assert _complete("panther-ops manager run --sim --scenario battery_", demo)[0] == [
        "battery_faults", "battery_overheat"]
    assert "low_battery" in _complete("panther-ops manager deploy --sim --scenario ", demo)[0]


def test_an_inventory_that_cannot_be_read_completes_nothing_silently(tmp_path: Path) -> None:
    (tmp_path / "broken.yaml").write_text("version: 1\nrobots: [\n")
    assert _complete("panther-ops -i broken.yaml status -r ", tmp_path) == ([], "")
    assert _complete("panther-ops -i missing.yaml status -g ", tmp_path) == ([], "")
    assert _complete("panther-ops status -r ", tmp_path) == ([], "")  # no ./inventory


def test_completing_contacts_no_robot(tmp_path: Path) -> None:
    import socket
    import time

    with socket.socket() as server:  # a robot's sshd would listen here
        server.bind(("127.0.0.1", 0))
        server.listen()
        server.setblocking(False)
        port = server.getsockname()[1]
        inv = tmp_path / "fleet.yaml"
        inv.write_text(f"version: 1\nrobots:\n  r1:\n    host: 127.0.0.1\n    port: {port}\n"
                       f"  r2:\n    host: 127.0.0.1\n    port: {port}\n")
        start = time.monotonic()
        assert _complete(f"panther-ops -i {inv} driver restart -r ", tmp_path) == (["r1", "r2"], "")
        assert time.monotonic() - start < 10
        with pytest.raises(BlockingIOError):
            server.accept()  # nobody connected


def test_bash_completes_robot_names_with_the_installed_script(demo: Path, tmp_path: Path) -> None:
    _install("bash", tmp_path)
    script = tmp_path / ".bash_completions" / "panther-ops.sh"
    probe = (f"cd '{demo}'; source '{script}'; COMP_WORDS=(panther-ops -i demo-fleet status -r panther-0); "
             "COMP_CWORD=5; _panther_ops_completion panther-ops; printf '%s\\n' \"${COMPREPLY[@]}\"")
    got = subprocess.run([_shell("bash"), "-c", probe], env=_env(tmp_path), capture_output=True, text=True,
                         timeout=60, check=True)
    assert got.stdout.split() == ROBOTS and got.stderr == ""


def test_an_i_given_after_the_command_is_the_inventory_in_use(demo: Path, tmp_path: Path) -> None:
    """``-i`` after the command counts, as a run reads it (cli/argv_order.py), and wins over the
    environment."""
    other = tmp_path / "other.yaml"
    other.write_text("version: 1\nrobots:\n  lab-r01:\n    host: 127.0.0.1\n")
    assert _complete("panther-ops status -i demo-fleet -r ", demo)[0] == ROBOTS
    assert _complete("panther-ops config set wheel_type WH02 -r panther-01 --inventory demo-fleet -r ", demo)[0] \
        == ROBOTS[1:]
    assert _complete(f"panther-ops apply -i {other} -r ", demo, {"PANTHER_OPS_INVENTORY": "demo-fleet"})[0] == ["lab-r01"]
    assert _complete("panther-ops status -i demo-fleet -g ", demo)[0] == ["warehouse", "field"]
