"""The safety fixes a robot's driver release lacks (`doctor`): read from husarion/husarion_ugv_ros's history.

Two fixes exist only in husarion_ugv 2.3.2 (ROS 2 Jazzy); no Humble release has them:

- soft E-stop: "fix soft e-stop logic (#606)", commit ecd0e8cb on the ``ros2`` line, first in tag
  2.3.2 (husarion_ugv_hardware_interfaces/src/robot_system/system_e_stop.cpp keeps a software
  E-stop latched after the watchdog trips it; gpio_controller.cpp turns the watchdog on before
  the reset's early return). Its Humble backport, #607 (ec6285f2), is on ``humble-devel`` only,
  in no tag.
- battery dead: "battery dead condition update (#596)", commit 6c5d1bbc, first in tag 2.3.2
  (husarion_ugv_battery/include/husarion_ugv_battery/battery/battery.hpp `IsBatteryDead`: the
  voltage must stay between 20 V and 27 V for 2 s, ``kBatteryDeadDetectionTimeout``, before the
  battery counts as dead; before it one reading under 27 V did, as in panther_ros@2.1.1:
  panther_battery/src/battery/adc_battery.cpp). Its Humble backport, #603 (e3579266), is on
  ``humble-devel`` only.

(`git log --oneline 2.2.2..2.3.2`, `git tag --contains <commit>` in the mirror of
husarion_ugv_ros.) So every release before 2.3.2 lacks both: panther_ros 2.0-2.1, husarion_ugv
2.2.x, and 2.3.0/2.3.1 (tagged before the fixes were merged).
"""

from __future__ import annotations

from dataclasses import dataclass

from panther_ops.core.stack import Stack


@dataclass(frozen=True)
class SafetyFix:
    name: str
    prs: str
    first: tuple[int, int, int]
    what: str


FIXED_IMAGE = "husarion/husarion-ugv:jazzy-2.3.2-20260622"
"""husarion_ugv_ros@2.3.2:docker/demo/compose.hardware.yaml's driver image."""

FIXES = (
    SafetyFix("soft E-stop", "husarion_ugv_ros #606/#607", (2, 3, 2),
              "a software E-stop (watchdog) stays latched until reset"),
    SafetyFix("battery-dead debounce", "husarion_ugv_ros #596/#603", (2, 3, 2),
              "the battery counts as dead after 2 s under the limit, not on one low reading"),
)


def missing_fixes(stack: Stack) -> list[SafetyFix]:
    """The fixes of `FIXES` the stack's release lacks."""
    return [f for f in FIXES if stack.version < f.first]


def missing_text(stack: Stack) -> tuple[str, str] | None:
    """(detail, fix) of doctor's warning for ``stack``, or None: it has every fix."""
    missing = missing_fixes(stack)
    if not missing:
        return None
    first = ".".join(map(str, max(f.first for f in missing)))
    names = "; ".join(f"{f.name} ({f.prs}: {f.what})" for f in missing)
    line = "Humble" if stack.distro == "humble" else stack.distro.capitalize()
    return (f"{stack.label()} ({line}) lacks {names}: first released in husarion_ugv {first} (ROS 2 Jazzy); "
            "no Humble release has them",
            f"update the driver to husarion_ugv {first} ({FIXED_IMAGE}); from Humble that is the move to "
            "Jazzy, file by file (docs/jazzy.md)")
