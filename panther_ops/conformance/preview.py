"""Releases panther-ops does not support yet, checked as the release it supports nearest to them.

husarion_ugv 2.3.x (ROS 2 Jazzy, husarion/husarion_ugv_ros tags 2.3.0-2.3.2) is refused by
panther-ops today (core/stack.py: ``parse_image`` accepts Humble up to 2.2.x). Its tables
are distilled all the same, and checked *as panther-ops would read the release if it took it
for its base* (2.2.2, the last Humble release, what a fleet migrates from): the validators
of a 2.2.2 robot on 2.3's default files, the 2.2.2 launch-argument catalogue against 2.3's
bringup, the 2.2.2 templates against 2.3's files. Every failing item is a to-do of the issue
that adds the line (`Preview.issue`), listed in `known` under that label; docs/conformance.md
renders these releases in their own section, and docs/jazzy.md says what each item means.

The file kinds are the exception: their rules are chosen by the release (core/kinds,
core/robot/files.py know 2.3), so a preview release's default files and templates are checked
with its own stack (`kinds_stack`), built from the tag as the stack panther-ops will read from
the release's image.

Nothing here makes panther-ops accept a 2.3 robot: `checked_stack` and `kinds_stack` hand
their stacks to the conformance tool only.
"""

from __future__ import annotations

from dataclasses import dataclass

from panther_ops.core.stack import UGV_REPO, Stack, parse_version, stack_from_version
from panther_ops.errors import OpsError


@dataclass(frozen=True)
class Preview:
    """A release line panther-ops does not support yet."""

    line: tuple[int, int]
    """major, minor (2, 3)."""
    distro: str
    base: str
    """The supported release its files are checked against (validators, catalogue, templates)."""
    issue: str
    """The issue that adds the line; the label of its items in `known.FINDINGS`."""
    title: str


PREVIEWS: tuple[Preview, ...] = (
    Preview((2, 3), "jazzy", "2.2.2", "issue #25",
            "husarion_ugv 2.3 on ROS 2 Jazzy (husarion/husarion_ugv_ros tags 2.3.0-2.3.2)"),
)


def supported(tag: str) -> bool:
    """True when panther-ops supports release ``tag`` (core/stack.py)."""
    try:
        stack_from_version(tag)
    except (OpsError, ValueError):
        return False
    return True


def preview_for(tag: str) -> Preview | None:
    """The `Preview` of an unsupported release ``tag``, or None (supported, or no preview of its line)."""
    if supported(tag):
        return None
    try:
        major, minor, _ = parse_version(tag)
    except ValueError:
        return None
    return next((p for p in PREVIEWS if p.line == (major, minor)), None)


def checked_stack(tag: str) -> Stack:
    """The stack the conformance checks use for ``tag``: its own, or its preview's base.

    Raises:
        OpsError: panther-ops does not support ``tag`` and no preview covers it.
        ValueError: ``tag`` is not a version X.Y.Z.
    """
    preview = preview_for(tag)
    return stack_from_version(preview.base if preview else tag)


def kinds_stack(tag: str) -> Stack:
    """The stack whose file-kind rules check ``tag``'s files and templates: its own, also on a
    release panther-ops does not support yet (a preview's stack, as its image would give it).

    Raises:
        OpsError: panther-ops does not support ``tag`` and no preview covers it.
        ValueError: ``tag`` is not a version X.Y.Z.
    """
    preview = preview_for(tag)
    if preview is None:
        return stack_from_version(tag)
    return Stack(image=f"{UGV_REPO}:{preview.distro}-{tag}", distro=preview.distro, version=parse_version(tag),
                 build_date=None)
