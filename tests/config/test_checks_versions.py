"""The robot-less check of `config set` (core/config/checks.py) knows every supported release."""

from __future__ import annotations

import pytest

from panther_ops.core.config.checks import REPRESENTATIVE, precheck
from panther_ops.core.stack import LINES, Generation, stack_from_version
from panther_ops.errors import UsageError


def test_every_generation_and_line_is_represented() -> None:
    stacks = [stack_from_version(v) for v in REPRESENTATIVE]
    assert {s.generation for s in stacks} == set(Generation)
    for line in LINES:
        assert any(line.holds(s.version) and s.distro == line.distro for s in stacks)


def test_a_key_only_jazzy_has_passes_the_check() -> None:
    """husarion_ugv_ros@2.3.2:husarion_ugv_bringup/launch/bringup.launch.py declares use_madgwick_filter:
    the check before any robot is read let it through (each robot's plan then checks its own stack);
    before this fix it refused it naming panther_ros 2.0.0, on a 2.3.2 robot too."""
    precheck({"use_madgwick_filter": "true"})
    with pytest.raises(UsageError, match="use_madgwick_filter"):
        precheck({"use_madgwick_filter": "maybe"})
