"""Fixtures for the runtime manager tests.

Nothing here powers anything off or talks to another machine: an autouse guard refuses any
socket connection that is not to the loopback interface. Host addresses in these tests are
RFC 5737 documentation addresses (192.0.2.x), used as data by test doubles only.
"""

from __future__ import annotations

import ipaddress
import socket
from collections.abc import Iterator
from typing import Any

import py_trees
import pytest

from panther_ops.manager.clock import ManualClock
from tests.manager.doubles import FakeRobotIO


@pytest.fixture(autouse=True)
def loopback_only(monkeypatch: pytest.MonkeyPatch) -> None:
    """Refuse every connection that does not go to 127.0.0.1 / ::1."""
    original = socket.socket.connect

    def guarded(self: socket.socket, address: Any) -> Any:
        host = address[0] if isinstance(address, tuple) else address
        inet = self.family in (socket.AF_INET, socket.AF_INET6)
        if inet and not ipaddress.ip_address(host).is_loopback:
            raise AssertionError(f"a test tried to connect to {address}")
        return original(self, address)

    monkeypatch.setattr(socket.socket, "connect", guarded)


@pytest.fixture(autouse=True)
def clean_blackboard() -> Iterator[None]:
    yield
    py_trees.blackboard.Blackboard.clear()


@pytest.fixture
def clock() -> ManualClock:
    return ManualClock()


@pytest.fixture
def io() -> FakeRobotIO:
    return FakeRobotIO()
