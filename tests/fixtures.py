"""Fixtures shared by the tests of every feature folder (a plugin of tests/conftest.py): the demo fleet."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from panther_ops.cli.app import main
from panther_ops.core.fleet.inventory import Inventory
from panther_ops.core.fleet.inventory_file import load_inventory
from panther_ops.core.fleet.runner import Connections
from tests.sshd import LoopbackSshd, missing


@pytest.fixture
def demo(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A fresh demo fleet in ``tmp_path/demo`` (local robot roots), with its own cache directory."""
    monkeypatch.setenv("PANTHER_OPS_CACHE_DIR", str(tmp_path / "cache"))
    assert main(["demo", "init", "--dest", str(tmp_path / "demo")]) == 0
    return tmp_path / "demo"


@pytest.fixture
def demo_connections(tmp_path: Path) -> Iterator[tuple[Inventory, Connections]]:
    """A fresh demo fleet (local robot roots) and its connections, closed afterwards."""
    assert main(["demo", "init", "--dest", str(tmp_path / "demo")]) == 0
    inv = load_inventory(str(tmp_path / "demo"))
    with Connections(inv) as conns:
        yield inv, conns


@pytest.fixture
def sshd(tmp_path: Path) -> Iterator[LoopbackSshd]:
    """A real OpenSSH sshd on loopback for this test (skipped where sshd is missing)."""
    why = missing()
    if why:
        pytest.skip(why)
    server = LoopbackSshd(tmp_path / "sshd")
    yield server
    server.close()
