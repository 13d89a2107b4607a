"""Fixtures of the operator-experience tests: a fresh demo fleet."""

from __future__ import annotations

from pathlib import Path

import pytest

from panther_ops.cli.app import main


@pytest.fixture
def demo(tmp_path: Path) -> Path:
    """A fresh demo fleet in ``tmp_path/demo`` (three local robot roots)."""
    assert main(["demo", "init", "--dest", str(tmp_path / "demo")]) == 0
    return tmp_path / "demo"
