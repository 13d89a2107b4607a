"""The shutdown hosts hints are the next command, filled in (issue 26, finding 3): the robot's
name and the entry's values, not ``-r ROBOT ...``."""

from __future__ import annotations

import shlex
from typing import Any, cast

import pytest

from panther_ops.core.config.robot_config import RobotConfig
from panther_ops.core.kinds import FileKindError
from panther_ops.core.kinds.hostsfile import Edit, Mode, add_host, new_entry
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
