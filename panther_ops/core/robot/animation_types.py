"""LED animation types spelled for the robot's stack, on every path that deploys an animations
file (`config push --as user-animations|led`, `lights deploy`: both through `push.plan_push`),
before the file is checked against the robot's release.

The plugin class ``ImageAnimation`` exists in both lights packages: panther_ros 2.0/2.1 name it
``panther_lights::ImageAnimation`` (panther_ros@2.1.1:panther_lights/plugins.xml), husarion_ugv
2.2 ``husarion_ugv_lights::ImageAnimation`` (husarion_ugv_ros@2.2.0:husarion_ugv_lights/plugins.xml).
A file written for one is rewritten for the other, as text (comments, order and quoting kept).
``ChargingAnimation`` exists only in panther_lights and ``MovingImageAnimation`` only in
husarion_ugv_lights: they are spelled for panther_ros when written for the other package, never
invented for 2.2, and the release's check refuses what it does not have. Stock image paths are
not rewritten: the two packages ship different images (``animations/<name>.png`` on 2.0/2.1,
``animations/<model>/<name>.png`` with other names on 2.2).
"""

from __future__ import annotations

import re

from panther_ops.core.stack import Family, Stack

PACKAGES = {Family.PANTHER_ROS: "panther_lights", Family.HUSARION_UGV: "husarion_ugv_lights"}
SHARED = {Family.PANTHER_ROS: ("ImageAnimation", "ChargingAnimation"), Family.HUSARION_UGV: ("ImageAnimation",)}
"""Classes a file written for the other package can be moved to, per target family."""
_TYPE = re.compile(r"(\btype:\s*['\"]?)(panther_lights|husarion_ugv_lights)::(ImageAnimation|ChargingAnimation)\b")


def for_stack(text: str, stack: Stack) -> tuple[str, list[str]]:
    """``text`` with the animation types of ``stack`` where that stack has the class; what was changed."""
    package = PACKAGES[stack.family]
    changed: list[str] = []

    def sub_type(m: re.Match[str]) -> str:
        if m.group(2) == package or m.group(3) not in SHARED[stack.family]:
            return m.group(0)
        changed.append(f"{m.group(2)}::{m.group(3)} -> {package}::{m.group(3)}")
        return f"{m.group(1)}{package}::{m.group(3)}"

    out = _TYPE.sub(sub_type, text)
    return out, sorted(set(changed), key=changed.index)
