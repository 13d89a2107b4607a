"""LED animation types and stock images spelled for the robot's stack, on every path that
deploys an animations file (`config push --as user-animations|led`, `lights deploy`: both
through `push.plan_push`).

panther_ros 2.0/2.1 load the plugins ``panther_lights::ImageAnimation`` and
``panther_lights::ChargingAnimation`` and ship their images in ``$(find panther_lights)/animations/``;
husarion_ugv 2.2 names them ``husarion_ugv_lights::ImageAnimation`` /
``husarion_ugv_lights::ChargingAnimation`` (husarion_ugv_lights/plugins.xml) with the Panther's
images in ``$(find husarion_ugv_lights)/animations/panther/``. A file written for one is
rewritten for the other, as text (comments, order and quoting kept); other types (custom
plugins, 2.2's MovingImageAnimation) are left as they are.
"""

from __future__ import annotations

import re

from panther_ops.core.stack import Family, Stack

STOCK_TYPES = ("ImageAnimation", "ChargingAnimation")
PACKAGES = {Family.PANTHER_ROS: "panther_lights", Family.HUSARION_UGV: "husarion_ugv_lights"}
_TYPE = re.compile(r"(\btype:\s*['\"]?)(panther_lights|husarion_ugv_lights)::(ImageAnimation|ChargingAnimation)\b")
_IMG_PANTHER = re.compile(r"\$\(find panther_lights\)/animations/(?=[^/\s'\"]+\.png)")
_IMG_UGV = re.compile(r"\$\(find husarion_ugv_lights\)/animations/panther/(?=[^/\s'\"]+\.png)")


def for_stack(text: str, stack: Stack) -> tuple[str, list[str]]:
    """``text`` with the stock animation types and images of ``stack``; what was changed."""
    package = PACKAGES[stack.family]
    changed: list[str] = []

    def sub_type(m: re.Match[str]) -> str:
        if m.group(2) == package:
            return m.group(0)
        changed.append(f"{m.group(2)}::{m.group(3)} -> {package}::{m.group(3)}")
        return f"{m.group(1)}{package}::{m.group(3)}"

    out = _TYPE.sub(sub_type, text)
    if stack.family is Family.HUSARION_UGV:
        out, n = _IMG_PANTHER.subn("$(find husarion_ugv_lights)/animations/panther/", out)
        what = "$(find panther_lights)/animations/ -> $(find husarion_ugv_lights)/animations/panther/"
    else:
        out, n = _IMG_UGV.subn("$(find panther_lights)/animations/", out)
        what = "$(find husarion_ugv_lights)/animations/panther/ -> $(find panther_lights)/animations/"
    changed += [what] * n
    return out, sorted(set(changed), key=changed.index)
