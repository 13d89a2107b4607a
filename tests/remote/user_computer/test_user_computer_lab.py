"""Issue-14 User Computers on the lab: computers (namespaces with a real sshd and sudo) on a
robot's LAN, which only the robot reaches, logged into with fabric through the robot's one
open connection; sudo with a password (fabric's watcher), passwordless sudo, strict host
keys (an unknown computer key is refused, never added)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from panther_ops.core.fleet.inventory_file import load_inventory
from panther_ops.core.fleet.runner import Connections, RobotContext
from panther_ops.core.remote.user_computer.access import open_session
from panther_ops.errors import TransportError, UnreachableError
from panther_ops.secret import Secret
from panther_ops.transport.base import Command
from tests.lab import Lab
from tests.lab.computers import ComputerSpec
from tests.labtools import computers_lab, user_computer_inventory

pytestmark = pytest.mark.lab

U1_PASSWORD = "u1-lab-sudo-password"


@pytest.fixture(scope="module")
def ulab() -> Iterator[Lab]:
    with computers_lab(
        ComputerSpec("u1", behind="r01", password=U1_PASSWORD, admin="group"),  # sudo asks for the password
        ComputerSpec("u2", behind="r01", admin="nopasswd"),
    ) as lab:
        yield lab


def inventory(lab: Lab, tmp: Path, computer: str, *, computer_keys: bool = True) -> Path:
    """The lab's inventory with r01's user_computer set (absolute paths)."""
    return user_computer_inventory(lab, tmp / "inventory.yaml", {"r01": computer}, user="husarion",
                                   computer_keys=computer_keys)


def session(path: Path, password: str | None) -> tuple[Connections, Any]:
    inv = load_inventory(str(path))
    robot = inv.robots["r01"]
    conns = Connections(inv)
    ctx = RobotContext(robot, conns.get(robot), inv)
    return conns, open_session(ctx, Secret(password) if password is not None else None)


def test_computer_behind_the_robot_is_not_reachable_from_here(ulab: Lab) -> None:
    import socket

    with pytest.raises(OSError):
        socket.create_connection((ulab.computer("u1").ip, 22), timeout=1).close()


def test_password_sudo_through_the_robots_one_connection(ulab: Lab, tmp_path: Path) -> None:
    before = ulab.sshd_connections("r01")
    conns, s = session(inventory(ulab, tmp_path, "u1"), U1_PASSWORD)
    try:
        assert ulab.sshd_connections("r01") == before + 1  # the robot: one connection, the computer rides it
        res = s.run(Command.of("hostname"))
        assert res.ok and res.stdout.strip() == "u1"
        res = s.sudo(Command.of("id", "-u"))
        assert res.ok and res.stdout.strip().splitlines()[-1] == "0"
        assert U1_PASSWORD not in res.stdout + res.stderr  # the watcher's answer is never shown
        # a second command on the same session: no new connection to the robot
        assert s.sudo(Command.of("sh", "-c", "echo $(id -un) > /tmp/panther-ops-sudo-check")).ok
        assert ulab.exec("u1", ["cat", "/tmp/panther-ops-sudo-check"]).stdout.strip() == "root"
        assert ulab.sshd_connections("r01") == before + 1
    finally:
        s.close()
        conns.close()


def test_wrong_password_is_refused_and_no_password_fails_without_hanging(ulab: Lab, tmp_path: Path) -> None:
    path = inventory(ulab, tmp_path, "u1")
    conns, s = session(path, "not-the-password")
    try:
        with pytest.raises(TransportError, match="sudo refused the password"):
            s.sudo(Command.of("id", "-u"), timeout=20)
    finally:
        s.close()
        conns.close()
    conns, s = session(path, None)
    try:
        res = s.sudo(Command.of("id", "-u"), timeout=20)
        assert not res.ok and "password is required" in res.stderr
    finally:
        s.close()
        conns.close()


def test_passwordless_sudo_needs_no_password(ulab: Lab, tmp_path: Path) -> None:
    conns, s = session(inventory(ulab, tmp_path, "u2"), None)
    try:
        res = s.sudo(Command.of("id", "-u"))
        assert res.ok and res.stdout.strip() == "0"
    finally:
        s.close()
        conns.close()


def test_unknown_host_key_is_refused_not_added(ulab: Lab, tmp_path: Path) -> None:
    path = inventory(ulab, tmp_path, "u2", computer_keys=False)
    known = ulab.known_hosts_path.read_text()
    with pytest.raises(UnreachableError, match="host key not known"):
        session(path, None)
    assert ulab.known_hosts_path.read_text() == known
