"""Fixtures shared by the unit tests."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from panther_ops.cli.app import main
from panther_ops.core.fleet.inventory import Inventory
from panther_ops.core.fleet.inventory_file import load_inventory
from panther_ops.core.fleet.runner import Connections


@pytest.fixture
def demo_connections(tmp_path: Path) -> Iterator[tuple[Inventory, Connections]]:
    """A fresh demo fleet (local robot roots) and its connections, closed afterwards."""
    assert main(["demo", "init", "--dest", str(tmp_path / "demo")]) == 0
    inv = load_inventory(str(tmp_path / "demo"))
    with Connections(inv) as conns:
        yield inv, conns
