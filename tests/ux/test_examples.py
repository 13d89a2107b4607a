"""Every example of --help and of docs/ runs on the demo fleet, or is marked as needing a robot
reached over SSH (issue 16, finding 4 and Deliver); and a command's output piped and on a
pseudo-terminal differs only in styling."""

from __future__ import annotations

import json
import os
import re
import shutil
from pathlib import Path

import pytest

from panther_ops.cli.app import main
from tests.badinput.test_file_kinds import JOY2TWIST
from tests.sim_world import WORLD
from tests.unit.test_custom_wheels import custom_controller, custom_wheel

from .examples import AFTER, EXPECTED_EXIT, ROOT, Example, doc_examples, help_examples, needs_a_robot
from .termrun import on_pty, piped, plain

EXAMPLES = help_examples() + doc_examples()
ON_DEMO = [e for e in EXAMPLES if needs_a_robot(e) is None]
ON_A_ROBOT = [e for e in EXAMPLES if needs_a_robot(e) is not None]
NO_INVENTORY = ("demo", "bt", "manager run", "lights validate", "lights preview", "shutdown hosts validate")

BAD_HOSTS = "hosts:\n  - ip: not an address\n    username: Husarion\n"
GOOD_HOSTS = "hosts:\n  - ip: 10.15.20.3\n    username: husarion\n"
BAD_ANIMATIONS = "user_animations:\n  - id: 5\n    animation: {}\n"
BAD_PUSHED_HOSTS = "hosts:\n  - ip: '10.15.20.5; touch x'\n    username: husarion\n    port: 70000\n"
BAD_BATTERY = "simulate_discharging: true\ninitial_charge_percentage: 140\n"
ESCAPING_BTPROJ = ('<?xml version="1.0"?>\n<root BTCPP_format="4" project_format="1.0">\n'
                   '  <include path="../../../.ssh/authorized_keys"/>\n</root>\n')


@pytest.fixture
def workspace(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A directory as a reader of the examples would have: the demo fleet as demo-fleet/, the
    shipped templates/, and the files the examples name (my_controller.yaml, ...)."""
    assert main(["demo", "init", "--dest", str(tmp_path / "demo-fleet")]) == 0
    (tmp_path / "templates").symlink_to(ROOT / "templates")
    shutil.copytree(ROOT / "templates" / "behavior_trees", tmp_path / "my_trees")
    lights = ROOT / "templates" / "lights"
    shutil.copytree(lights / "animations", tmp_path / "animations")
    for name in ("my_animations.yaml", "my_awesome_user_animations.yaml"):
        shutil.copy(lights / "user_animations.example.yaml", tmp_path / name)
    (tmp_path / "bad_animations.yaml").write_text(BAD_ANIMATIONS)
    (tmp_path / "bad.yaml").write_text(BAD_HOSTS)
    (tmp_path / "my_hosts.yaml").write_text(GOOD_HOSTS)
    (tmp_path / "hosts.yaml").write_text(GOOD_HOSTS + "  - ip: 10.15.20.9\n    username: pi\n")
    (tmp_path / "bad_hosts.yaml").write_text(BAD_PUSHED_HOSTS)
    (tmp_path / "chained.yaml").write_text("hosts:\n  - ip: 10.15.20.3\n    username: husarion\n"
                                           "    command: sync && sudo shutdown now\n")
    config = ROOT / "templates" / "config" / "panther-2.1"  # a simulation workspace's files (docs/gps.md)
    shutil.copy(config / "panther_description" / "config" / "components.yaml", tmp_path / "components.yaml")
    shutil.copy(config / "panther_gazebo" / "config" / "battery_plugin_config.yaml",
                tmp_path / "battery_plugin_config.yaml")
    (tmp_path / "my_world.sdf").write_text(WORLD)
    (tmp_path / "w.sdf").write_text(WORLD)
    (tmp_path / "dms.sdf").write_text(WORLD.replace("53.1978", "53°11'52\"N"))  # docs/gps.md: refused, with the fix
    (tmp_path / "bad_battery.yaml").write_text(BAD_BATTERY)
    wh01_20 = ROOT / "templates/config/panther-2.0/panther_controller/config/WH01_controller.yaml"
    (tmp_path / "no_prefix_controller.yaml").write_text(  # docs/configuration.md: the IMU under a namespace
        wh01_20.read_text().replace("      use_namespace_as_sensor_name_prefix: true\n", ""))
    (tmp_path / "my_wheels.yaml").write_bytes(custom_wheel("2.1.1"))  # docs/configuration.md: custom wheels
    (tmp_path / "my_wheels_controller.yaml").write_bytes(custom_controller("2.1.1"))
    (tmp_path / "pad.yaml").write_text(JOY2TWIST)
    (tmp_path / "bad_pad.yaml").write_text(JOY2TWIST.replace("dead_man_switch: 4", "dead_man_switch: LB"))
    (tmp_path / "bad_srv_pad.yaml").write_text(JOY2TWIST.replace("reset_srv: hardware/e_stop_reset",
                                                                 "reset_srv: hardware/e-stop-reset"))
    (tmp_path / "proj").mkdir()
    (tmp_path / "proj" / "My.btproj").write_text(ESCAPING_BTPROJ)
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("NUC_SECRET", "a-long-shared-secret-for-the-nuc")
    # the reader's simulation (docs/gps.md): Gazebo's CLI, a stand-in serving the recharge
    # services of a panther without a namespace and of one spawned under 'panther'
    (tmp_path / "gz-services").write_text("".join(
        f"/model/{m}/battery/{b}/recharge/{a}\n" for m, b in (("panther", "battery"), ("panther", "panther/battery"))
        for a in ("start", "stop")))
    monkeypatch.setenv("PATH", f"{ROOT / 'tests' / 'standins'}:{os.environ['PATH']}")
    monkeypatch.setenv("PANTHER_OPS_STANDIN_GZ_SERVICES", str(tmp_path / "gz-services"))
    monkeypatch.setenv("PANTHER_OPS_STANDIN_GZ_CALLS", str(tmp_path / "gz-calls"))
    assert main(["-i", "demo-fleet", "config", "pull", "controller", "-r", "panther-01", "-o",
                 "my_controller.yaml"]) == 0
    # hosts.yaml (GOOD_HOSTS) with a backup beside it, for `config history|rollback --file hosts.yaml`
    assert main(["shutdown", "hosts", "remove", "hosts.yaml", "--ip", "10.15.20.9", "--yes"]) == 0
    assert (tmp_path / "hosts.yaml").read_text() == GOOD_HOSTS
    return tmp_path


def _argv(example: Example) -> list[str]:
    """The example's arguments on the demo fleet: its -i (the reader's own inventory) becomes
    demo-fleet; one without -i gets it (as $PANTHER_OPS_INVENTORY would)."""
    argv = example.argv
    if "-i" in argv:
        at = argv.index("-i")
        return [*argv[:at], "-i", "demo-fleet", *argv[at + 2:]]
    if " ".join(argv).startswith(NO_INVENTORY):
        return argv
    return ["-i", "demo-fleet", *argv]


@pytest.mark.parametrize("example", ON_DEMO, ids=[f"{e.where}: {e.line}" for e in ON_DEMO])
def test_example_runs_on_the_demo_fleet(example: Example, workspace: Path,
                                        capsys: pytest.CaptureFixture[str]) -> None:
    for before in AFTER.get(example.line, ()):
        _run(Example(example.where, before), workspace, capsys)
    _run(example, workspace, capsys)


DOCS_IN_ORDER = sorted({e.where.split(":")[0] for e in ON_DEMO if not e.where.startswith("--help")})


@pytest.mark.parametrize("doc", DOCS_IN_ORDER)
def test_a_docs_examples_run_in_order_on_one_demo_fleet(doc: str, workspace: Path,
                                                        capsys: pytest.CaptureFixture[str]) -> None:
    """As a reader follows a page: each example after the ones above it (``config set wheel_type
    WH02 -g warehouse --yes``, then a controller limit that WH02 allows)."""
    for example in [e for e in ON_DEMO if e.where.split(":")[0] == doc]:
        _run(example, workspace, capsys)


def _run(example: Example, workspace: Path, capsys: pytest.CaptureFixture[str]) -> None:
    if example.argv[:2] == ["demo", "init"]:
        (workspace / "fresh").mkdir(exist_ok=True)
        shutil.rmtree(workspace / "fresh" / "demo-fleet", ignore_errors=True)
        with pytest.MonkeyPatch.context() as mp:
            mp.chdir(workspace / "fresh")
            assert main(example.argv) == 0
            assert (workspace / "fresh" / "demo-fleet" / "inventory.yaml").is_file()
        return
    capsys.readouterr()
    code = main(_argv(example))
    out, err = capsys.readouterr()
    if code == 2 and "confirmation" in err and "--yes" not in example.argv:
        # on a terminal the example asks first; the operator's "y" is --yes
        code = main([*_argv(example), "--yes"])
        out, err = capsys.readouterr()
    assert code == EXPECTED_EXIT.get(example.line, 0), f"{example.where}: {example.line}\n{out}\n{err}"
    assert "internal error" not in err and "Traceback" not in err
    if "| jq" in example.line:  # --json: exactly one JSON document on stdout
        assert json.loads(out) is not None
    if "| grep calls" in example.line:
        assert "calls=" in out


def test_every_example_is_run_or_marked() -> None:
    """The collection is not empty and every example is accounted for (run, or with a reason)."""
    assert len(EXAMPLES) >= 100
    assert {e.where.split(":")[0] for e in EXAMPLES} >= {"docs/commands.md", "README.md", "docs/manager.md"}
    assert sum(1 for e in EXAMPLES if e.where.startswith("--help")) >= 45
    assert all(needs_a_robot(e) for e in ON_A_ROBOT)
    assert len(ON_DEMO) >= 70


READ_ONLY = (["status", "--all"], ["config", "get", "wheel_type", "--all"], ["driver", "status", "--all"],
             ["config", "diff", "--all"], ["inventory", "list"], ["config", "set", "wheel_type", "WH02", "--all",
                                                                    "--dry-run"],
             ["manager", "status", "--all"], ["shutdown", "check", "--all"], ["doctor", "--all"],
             ["config", "pull", "controller", "-r", "panther-01"], ["inventory", "show", "panther-01"],
             ["shutdown", "hosts", "list", "-r", "panther-01"], ["driver", "versions", "--all"],
             ["bt", "validate", "templates/behavior_trees/PantherSafetyBT.btproj"],
             ["lights", "validate", "my_animations.yaml"], ["config", "history", "--all"],
             ["gps", "status", "--all"], ["estop", "status", "--all"], ["webui", "status", "--all"],
             ["webui", "url", "--all"], ["reimage", "plan", "--all"], ["gps", "enable", "--all", "--dry-run"],
             ["apply", "--all", "--dry-run"], ["manager", "logs", "--all"])


@pytest.mark.parametrize("args", READ_ONLY, ids=[" ".join(a) for a in READ_ONLY])
def test_piped_and_on_a_terminal_differ_only_in_styling(args: list[str], workspace: Path) -> None:
    argv = ["-i", "demo-fleet", *args]
    pipe = piped(argv, cwd=workspace)
    term = on_pty(argv, cols=160, cwd=workspace, stderr_pipe=True)  # stdout on the terminal, as wide as a pipe
    assert pipe.code == term.code
    assert "\x1b[" not in pipe.out
    shown = [_unmeasured(line) for line in plain(term.out).splitlines()]
    assert shown == [_unmeasured(line) for line in pipe.out.splitlines()]
    assert "\x1b[" not in term.err  # stderr was piped there


def _unmeasured(line: str) -> str:
    """The line without what two runs measure differently (clock offsets, free space, times)."""
    return re.sub(r"[+-]?\d+(\.\d+)?", "N", line).rstrip()
