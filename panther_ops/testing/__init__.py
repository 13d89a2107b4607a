"""Test doubles shipped with panther-ops, for your own tests of code built on it.

:class:`~panther_ops.testing.fake_transport.FakeTransport` is a robot without a robot: a
:class:`~panther_ops.transport.base.Transport` over an in-memory file tree
(:class:`~panther_ops.testing.fake_robot.FakeRobot`) that carries out panther-ops' own robot
scripts (reads, the staged write with its backup and compare-and-rename under the write lock,
backup listing and marking) by their rules, and answers every other command from a script
you give it. See docs/develop.md, "How to test".

Nothing in the product imports this package (import-linter holds it); it imports the
transport layer only, never the CLI.
"""

from __future__ import annotations

from panther_ops.testing.fake_robot import FakeFile, FakeRobot, Reply, UnscriptedCommand
from panther_ops.testing.fake_transport import FakeTransport

__all__ = ["FakeFile", "FakeRobot", "FakeTransport", "Reply", "UnscriptedCommand"]
