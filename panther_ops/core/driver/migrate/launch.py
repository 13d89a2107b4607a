"""The driver's launch arguments (compose.yaml ``command:``), 2.2 -> 2.3.

Sources: husarion_ugv_ros@2.2.2 vs @2.3.1/@2.3.2:husarion_ugv_controller/launch/controller.launch.py
(``publish_robot_state``, default True, gone on every 2.3 tag: 2.3 always publishes the robot
state); @2.3.2:husarion_ugv_bringup/launch/bringup.launch.py includes husarion_ugv_teleop's
teleop.launch.py with ``launch_gamepad: True``, so on 2.3.2 the gamepad always runs whatever the
command says. Every other argument of 2.2.2's catalogue is equal on 2.3.1 and 2.3.2
(docs/jazzy.md).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from panther_ops.core.driver.migrate.translated import MUX_SINCE, MigrationRefused

_FALSE = ("false", "0", "no", "off")


@dataclass(frozen=True)
class LaunchMigration:
    """Arguments the 2.3 command no longer has, and what the plan says of the command."""

    dropped: tuple[str, ...]
    notes: tuple[str, ...]


def migrate_launch(args: Mapping[str, str], target: tuple[int, int, int], compose_path: str) -> LaunchMigration:
    """What happens to a 2.2 command's arguments on husarion_ugv ``target``.

    Raises:
        MigrationRefused: ``publish_robot_state:=false`` (2.3 always publishes it), or
            ``launch_gamepad:=false`` on 2.3.2 (its teleop always runs the gamepad).
    """
    dropped: list[str] = []
    notes: list[str] = []
    if "publish_robot_state" in args:
        value = args["publish_robot_state"]
        if value.strip().lower() in _FALSE:
            raise MigrationRefused(
                f"publish_robot_state:={value} cannot be carried over: husarion_ugv 2.3 has no such argument and "
                "always publishes the robot description and TF", path=compose_path, key="publish_robot_state",
                hint="remove publish_robot_state:=false (panther-ops config unset publish_robot_state) and stop "
                     "whatever publishes the robot state instead, then migrate")
        dropped.append("publish_robot_state")
        notes.append(f"launch argument publish_robot_state:={value} removed: 2.3 always publishes the robot state")
    gamepad = args.get("launch_gamepad")
    if target >= MUX_SINCE:
        if gamepad is not None and gamepad.strip().lower() in _FALSE:
            raise MigrationRefused(
                f"launch_gamepad:={gamepad} cannot be carried over: husarion_ugv 2.3.2's bringup always starts the "
                "gamepad (husarion_ugv_teleop, launch_gamepad: True)", path=compose_path, key="launch_gamepad",
                hint="remove launch_gamepad:=false (panther-ops config unset launch_gamepad) knowing the gamepad "
                     "will drive the robot on 2.3.2, or migrate to 2.3.1")
        if gamepad is None:
            notes.append("the gamepad (joy2twist) runs on 2.3.2 whatever the command says; this robot did not "
                         "start it on 2.2 (no launch_gamepad:=true)")
    return LaunchMigration(tuple(dropped), tuple(notes))
