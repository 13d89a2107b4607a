"""The demo fleet's robots as fake robots (panther_ops.testing): the same files, in memory."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from panther_ops.core.demo.fleet import init_demo
from panther_ops.core.fleet.inventory import Inventory
from panther_ops.core.fleet.inventory_file import load_inventory
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.testing import FakeRobot, FakeTransport


@pytest.fixture
def demo(tmp_path: Path) -> Inventory:
    return load_inventory(str(init_demo(tmp_path / "demo")))


@pytest.fixture
def fake_ctx(demo: Inventory) -> Iterator[Callable[..., RobotContext]]:
    """``fake_ctx(name, **robot_kw)``: a context whose transport is a fake robot holding the demo
    robot's files."""
    opened: list[FakeTransport] = []

    def make(name: str, **kw: object) -> RobotContext:
        robot = demo.robots[name]
        assert robot.root is not None
        transport = FakeTransport(FakeRobot.from_directory(robot.root, **kw), name)
        transport.connect()
        opened.append(transport)
        return RobotContext(robot, transport, demo)

    yield make
    for t in opened:
        t.close()


def fake_of(ctx: RobotContext) -> FakeRobot:
    assert isinstance(ctx.transport, FakeTransport)
    return ctx.transport.robot
