"""The inventory's per-robot `user_computer:` (host behind the robot, user, key, port):
parsed with its defaults, and every bad value refused naming the file, line and key."""

from __future__ import annotations

from pathlib import Path

import pytest

from panther_ops.core.fleet.inventory import UserComputer
from panther_ops.core.fleet.inventory_file import load_inventory
from tests.fleet.test_inventory import refused

GOOD = """\
version: 1
robots:
  p1:
    host: panther-01
    user_computer: {}
  p2:
    host: panther-02
    user_computer:
      host: 10.15.20.13
      user: operator
      key: keys/nuc
      port: 2222
  p3: {host: panther-03}
"""


def test_user_computer_defaults_and_values(tmp_path: Path) -> None:
    path = tmp_path / "fleet.yaml"
    path.write_text(GOOD)
    inv = load_inventory(str(path))
    assert inv.robots["p1"].user_computer == UserComputer("10.15.20.3", "husarion", None, 22)
    assert inv.robots["p2"].user_computer == UserComputer("10.15.20.13", "operator",
                                                          str((tmp_path / "keys/nuc").resolve()), 2222)
    assert inv.robots["p3"].user_computer is None


@pytest.mark.parametrize(
    ("value", "key", "what"),
    [
        ("{host: 10.15.20.3; reboot}", "user_computer.host", "not a host name or IP address"),
        ("{host: '-oProxyCommand=x'}", "user_computer.host", "not a host name or IP address"),
        ("{host: 'nuc 1'}", "user_computer.host", "not a host name or IP address"),
        ("{host: '$(id)'}", "user_computer.host", "not a host name or IP address"),
        ("{host: 'a|b'}", "user_computer.host", "not a host name or IP address"),
        ("{user: 'Bad User'}", "user_computer.user", "not a POSIX user name"),
        ("{port: 0}", "user_computer.port", "not a TCP port"),
        ("{key: ''}", "user_computer.key", "path to a private key"),
        ("{password: husarion}", "user_computer.password", "plaintext secrets are not allowed"),
        ("{colour: red}", "user_computer.colour", "unknown key 'colour'"),
        ("[10.15.20.3]", "user_computer", "must be a mapping"),
    ],
)
def test_bad_user_computer_is_refused(tmp_path: Path, value: str, key: str, what: str) -> None:
    message = refused(tmp_path, f"robots:\n  r1:\n    host: a\n    user_computer: {value}\n")
    assert f"[robots.r1.{key}" in message
    assert what in message
