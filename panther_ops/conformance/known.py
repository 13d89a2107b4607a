"""The conformance failures known today, each tied to the finding of issue #24 that fixes it.

A key is an ``fnmatch`` pattern over a result's id (``<tag>:<check>:<item>``). The report
marks a failure with its finding; tests/conformance/test_conformance.py expects these items to fail
(``xfail(strict=True)``), so the test of an item turns red the day a fix makes it pass:
then delete its line here (and re-run scripts/conformance.py if the fix changed a
validator, so the recorded verdicts follow).

``new`` entries are failures the conformance tool found that issue #24 does not list.
``issue #25`` entries are the items of husarion_ugv 2.3 (Jazzy) that 2.2.2's validators,
catalogue and templates fail on (`preview`): the to-do list of issue #25.
"""

from __future__ import annotations

from fnmatch import fnmatchcase

FINDINGS: dict[str, str] = {
    "finding 1": "husarion_ugv 2.2's own files are refused",
    "finding 2": "controller templates lack the IMU's namespace prefix",
    "finding 3": "where 2.2 reads a default from (image or ~/config tree) is wrong in the catalogue",
    "finding 4": "2.1.1's NMEA launch arguments are missing from the catalogue",
    "finding 5": "templates that are not upstream's, or missing",
    "finding 8": "simulation files",
    "finding 9": "config pull joy2twist has no default to give",
    "new": "found by the conformance tool; not in issue #24's list",
    "issue #25": "husarion_ugv 2.3 (ROS 2 Jazzy) is not supported yet: what 2.2.2's validators, catalogue and "
                 "templates say of 2.3's files (docs/jazzy.md)",
}
"""Label -> what it is: the findings of issue #24 that known failures belong to."""

KNOWN: dict[str, tuple[str, str]] = {
    # issue #25: husarion_ugv 2.3 (Jazzy), checked as on 2.2.2 (preview.py); docs/jazzy.md explains each.
    "2.3.[012]:release:2.3.[012]": ("issue #25", "core/stack.py refuses jazzy images and 2.3+"),
    "2.3.0:launch:animations_config_path": ("issue #25", "2.3.0 reads the animations from the image, as 2.2.0"),
    "2.3.0:launch:launch_gamepad": ("issue #25", "2.3.0 runs the gamepad as its own compose service, as 2.2.0"),
    "2.3.[012]:launch:publish_robot_state": ("issue #25", "gone from controller.launch.py on 2.3"),
    "2.3.2:launch:use_madgwick_filter": ("issue #25", "new argument of controller and load_urdf launch files"),
    "2.3.[012]:templates:compose/husarion-ugv-2.2.2.yaml":
        ("issue #25", "2.3.1/2.3.2: the image tag only; 2.3.0: a separate gamepad_controller service"),
    # the demo's 2.2.2 config tree (templates/config-tree/husarion-ugv-2.2, the preview's base) against 2.3's
    # files; 2.3's own templates are templates/config/husarion-ugv-2.3*.
    "2.3.[012]:templates:config-tree/husarion-ugv-2.2/husarion_ugv_controller/config/WH0[1245]_controller.yaml":
        ("issue #25", "controller limits schema of Jazzy ros2_controllers (2.3.2: and twist_mux_controller)"),
    "2.3.[012]:templates:config-tree/husarion-ugv-2.2/husarion_ugv_localization/config/*_localization*.yaml":
        ("issue #25", "EKF stamped_control (2.3.2: control_timeout 0.2)"),
    "2.3.[012]:templates:config-tree/husarion-ugv-2.2/husarion_ugv_bringup/config/joy2twist_panther.yaml":
        ("issue #25", "2.3.0: no joy2twist file in the tree; 2.3.1: cmd_vel_stamped; "
                      "2.3.2: moved to husarion_ugv_teleop"),
    "2.3.2:templates:config-tree/husarion-ugv-2.2/husarion_ugv_lights/config/[lp]*_animations.yaml":
        ("issue #25", "animations 16 GOAL_FAILED and 17 FLOOD_LIGHT"),
    "2.3.2:templates:config-tree/husarion-ugv-2.2/husarion_ugv_manager/behavior_trees/[Ll]ights*":
        ("issue #25", "Lights tree keyed on twist_mux_controller/source (CheckStringMsg)"),
    "2.3.[02]:tree:panther": ("issue #25", "2.3.0 copies no joy2twist or animations file; 2.3.2 copies "
                                          "joy2twist from husarion_ugv_teleop"),
}
"""Result id pattern -> (label in `FINDINGS`, what in particular)."""


def known(result_id: str) -> tuple[str, str] | None:
    """The label and note of a failing result, or None (not known: a regression or a new finding)."""
    for pattern, entry in KNOWN.items():
        if fnmatchcase(result_id, pattern):
            return entry
    return None
