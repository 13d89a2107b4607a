"""The shutdown hosts hints are the next command, filled in (issue 26, finding 3): the robot's
name and the entry's values, not ``-r ROBOT ...``."""

from __future__ import annotations

import shlex
from pathlib import Path
from typing import Any, cast

import pytest

from panther_ops.cli.app import main
from panther_ops.core.kinds import FileKindError
from panther_ops.core.kinds.hostsfile import Edit, Mode, add_host, new_entry
from panther_ops.core.robot.robot_config import RobotConfig
from panther_ops.core.shutdown.plan import RobotHostsFile, hosts_edit
from panther_ops.core.stack import stack_from_version

GOOD = "hosts:\n  - ip: 10.15.20.3\n    username: husarion\n"
BAD = "hosts:\n  - ip: 10.15.20.3\n    username: husarion\n  - ip: '10.15.20.5; touch x'\n    port: 70000\n"


def _file(text: str) -> RobotHostsFile:
    return RobotHostsFile(text, "/home/husarion/config/hosts.yaml", "mounted", stack_from_version("2.1.1"),
                          cast(RobotConfig, None))


def test_an_entry_in_error_is_named_by_the_remove_command_of_that_robot_and_ip() -> None:
    def editor(text: str, _mode: Mode) -> Edit:
        return add_host(text, new_entry("10.15.20.9", username="pi"))

    with pytest.raises(FileKindError) as caught:
        hosts_edit(_file(BAD), editor, robot="lab-r02")
    hint: Any = caught.value.hint
    assert f"panther-ops shutdown hosts remove -r lab-r02 --ip {shlex.quote('10.15.20.5; touch x')}" in hint
    assert "ROBOT" not in hint and " IP" not in hint


def test_a_good_edit_is_not_refused() -> None:
    edit, warnings = hosts_edit(_file(GOOD), lambda text, _m: add_host(text, new_entry("10.15.20.9", username="pi")),
                                robot="r01")
    assert edit.changed and "10.15.20.9" in edit.text and not warnings


def test_a_mounted_hosts_file_that_is_gone_is_answered_with_the_push_that_replaces_it(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    demo = tmp_path / "demo"
    assert main(["demo", "init", "--dest", str(demo)]) == 0
    compose = demo / "robots/panther-01/home/husarion/compose.yaml"
    mount = "      - /run/husarion/panther_config.yaml:/run/husarion/panther_config.yaml\n"
    launch = "    command: ros2 launch panther_bringup bringup.launch.py"
    text = compose.read_text()
    assert mount + launch in text
    compose.write_text(text.replace(mount + launch, f"{mount}      - /home/husarion/gone.yaml:/config/gone.yaml:ro\n"
                                    f"{launch} shutdown_hosts_config_path:=/config/gone.yaml", 1))
    add = ["-i", str(demo), "shutdown", "hosts", "add", "-r", "panther-01", "--ip", "10.15.20.4", "--user", "husarion",
           "--yes"]
    capsys.readouterr()
    assert main(add) == 2
    err = capsys.readouterr().err
    hint = "panther-ops config push hosts.yaml --as shutdown-hosts -r panther-01"
    assert hint in err and "ROBOT" not in err, err
    # the hint is the next command: run, it lets the add through
    (tmp_path / "hosts.yaml").write_text(GOOD)
    assert main(["-i", str(demo), "config", "push", str(tmp_path / "hosts.yaml"), "--as", "shutdown-hosts",
                 "-r", "panther-01", "--yes"]) == 0
    assert main(add) == 0
