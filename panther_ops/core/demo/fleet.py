"""The embedded demo fleet: local robots that are directories, seeded from templates/.

``panther-ops demo init`` lays out one directory per robot, standing in for its Built-in
Computer's file system, and an inventory for them, so every read-only command and every
configuration change can be tried with no robot. A demo robot has no docker engine; its
docker steps are reported ``skipped``.
"""

from __future__ import annotations

import json
import shutil
from dataclasses import dataclass
from pathlib import Path

from panther_ops.core.fleet.templates import template_path
from panther_ops.core.remote.estop.calls import DEMO_RECORDING
from panther_ops.errors import UsageError


@dataclass(frozen=True)
class DemoRobot:
    name: str
    compose_template: str
    serial: str
    groups: tuple[str, ...]
    e_stop: bool = True
    cmd_vel_publishers: tuple[str, ...] = ()
    webui_running: bool | None = True
    """The recorded WebUI of its User Computer: running, stopped (False), none recorded (None)."""

    @property
    def release(self) -> str:
        """The driver release of its compose template (``2.3.2``)."""
        return self.compose_template.removesuffix(".yaml").rsplit("-", 1)[-1]


DEMO_ROBOTS = (
    DemoRobot("panther-01", "panther-2.1.1.yaml", "PTH0101", ("warehouse",)),
    DemoRobot("panther-02", "panther-2.0.4.yaml", "PTH0102", ("warehouse",),
              cmd_vel_publishers=("teleop_twist_keyboard",), webui_running=None),
    DemoRobot("panther-03", "husarion-ugv-2.2.2.yaml", "PTH0203", ("field",), e_stop=False, webui_running=False),
    DemoRobot("panther-04", "husarion-ugv-2.3.2.yaml", "PTH0304", ("field",), webui_running=False),
)

INVENTORY = """\
# The demo fleet of panther-ops: each robot is a directory standing in for the
# Built-in Computer's file system (transport: local). Real robots look like the
# commented example at the end (docs/inventory.md).
version: 1
defaults:
  user: husarion
groups:
  warehouse:
    description: indoor robots on mecanum wheels
    desired:
      launch_args:
        wheel_type: WH02
  field:
    description: outdoor robots
    desired:
      webui:                    # the WebUI snap on the User Computer (apply, config diff)
        layout: panther
        transport: rmw_cyclonedds_cpp
robots:
{robots}
# A real robot (reached by its Husarnet hostname; every Panther is 10.15.20.2 inside):
#   panther-07:
#     host: panther-07          # or an IP, or a name from ~/.ssh/config
#     identity_file: ~/.ssh/id_ed25519
#     groups: [field]
#   panther-08:
#     host: 10.15.20.2
#     jump: operator@gateway.example.org:22   # reached through the robot's LAN gateway
"""

ENV_21 = """\
PANTHER_ROBOT_VERSION=1.2
PANTHER_SERIAL_NO={serial}
PANTHER_IMU_LOCALIZATION_X=0.168
PANTHER_IMU_LOCALIZATION_Y=0.028
PANTHER_IMU_LOCALIZATION_Z=0.083
SYSTEM_BUILD_VERSION=v2.1.0
"""

ENV_22 = """\
ROBOT_MODEL_NAME=panther
ROBOT_SERIAL_NO={serial}
ROBOT_VERSION=1.2
ROBOT_HW_CONFIG_CORRECT=true
SYSTEM_BUILD_VERSION=v2.2.0
"""

CONFIG_TREE_2_2_2 = (
    "husarion_ugv_bringup/config/joy2twist_panther.yaml",
    *(f"husarion_ugv_controller/config/{w}_controller.yaml" for w in ("WH01", "WH02", "WH04", "WH05")),
    "husarion_ugv_lights/config/user_animations.yaml",
    "husarion_ugv_lights/config/panther_animations.yaml",
    *(f"husarion_ugv_localization/config/{n}.yaml" for n in
      ("enu_localization", "enu_localization_with_gps", "relative_localization", "relative_localization_with_gps")),
    "husarion_ugv_manager/behavior_trees/lights.xml",
    "husarion_ugv_manager/behavior_trees/LightsBT.btproj",
    "husarion_ugv_manager/config/shutdown_hosts.yaml",
    "husarion_ugv_description/config/components.yaml",
)
"""What the husarion_ugv 2.2.2 image copies into ~/config (mounted at /config) for a Panther
(ROBOT_MODEL_NAME=panther): husarion_ugv_ros@2.2.2:docker/utils/update_config_directory.sh
copies joy2twist_${ROBOT_MODEL_NAME}.yaml, the whole husarion_ugv_controller/config and
husarion_ugv_localization/config directories (less nmea_navsat.yaml), user_animations.yaml,
${ROBOT_MODEL_NAME}_animations.yaml, lights.xml, LightsBT.btproj, shutdown_hosts.yaml and
components.yaml. The demo's 2.2.2 robot gets these files from templates/config-tree/husarion-ugv-2.2/."""

CONFIG_TREE_2_3_2 = tuple(
    "husarion_ugv_teleop/config/joy2twist_panther.yaml" if rel.endswith("/joy2twist_panther.yaml") else rel
    for rel in CONFIG_TREE_2_2_2)
"""What the husarion_ugv 2.3.2 image copies into ~/config for a Panther: husarion_ugv_ros@2.3.2:docker/utils/
update_config_directory.sh differs from 2.2.2's in one line, joy2twist_${ROBOT_MODEL_NAME}.yaml is copied from
husarion_ugv_teleop. The demo's 2.3.2 robot gets each file from its release's templates (`family_dirs`: the 2.3
directory, then what 2.3 kept of 2.2's)."""

CONFIG_TREES = {"2.2.2": CONFIG_TREE_2_2_2, "2.3.2": CONFIG_TREE_2_3_2}
"""The demo robots' ~/config trees, by release."""

COMMON_ENV_22 = """\
# env configuration including namespace, domain id, DDS, etc.
ROS_DOMAIN_ID=0
RMW_IMPLEMENTATION=rmw_cyclonedds_cpp
ROBOT_NAMESPACE=panther
"""


def init_demo(dest: Path, *, force: bool = False) -> Path:
    """Create the demo fleet under ``dest``; returns the inventory file written."""
    if dest.exists() and any(dest.iterdir()):
        if not force:
            raise UsageError(f"{dest} already exists and is not empty",
                             hint="use --force to recreate it, or choose another --dest")
        shutil.rmtree(dest)
    dest.mkdir(parents=True, exist_ok=True)
    lines = []
    for robot in DEMO_ROBOTS:
        _lay_out(dest / "robots" / robot.name, robot)
        lines.append(
            f"  {robot.name}:\n    transport: local\n    root: robots/{robot.name}\n"
            f"    groups: [{', '.join(robot.groups)}]"
        )
    inventory = dest / "inventory.yaml"
    inventory.write_text(INVENTORY.format(robots="\n".join(lines)))
    return inventory


def _lay_out(root: Path, robot: DemoRobot) -> None:
    home = root / "home" / "husarion"
    home.mkdir(parents=True)
    shutil.copyfile(template_path("compose", robot.compose_template), home / "compose.yaml")
    (root / "etc").mkdir()
    (root / "etc" / "hostname").write_text(robot.name + "\n")
    (root / "etc" / "os-release").write_text('PRETTY_NAME="Ubuntu 22.04.4 LTS"\nID=ubuntu\n')
    run = root / "run" / "husarion"
    run.mkdir(parents=True)
    if robot.compose_template.startswith("husarion-ugv"):
        (run / "robot_config.env").write_text(ENV_22.format(serial=robot.serial))
        tree = template_path("config-tree", "husarion-ugv-2.2")
        version = robot.release
        for rel in CONFIG_TREES[version]:
            (home / "config" / rel).parent.mkdir(parents=True, exist_ok=True)
            source = tree / rel if version == "2.2.2" else _release_template(version, rel)
            shutil.copyfile(source, home / "config" / rel)
        if (tree / "common" / ".env").is_file():
            (home / "config" / "common").mkdir(parents=True, exist_ok=True)
            shutil.copyfile(tree / "common" / ".env", home / "config" / "common" / ".env")
        common = home / "config" / "common"
        common.mkdir(parents=True, exist_ok=True)
        if not (common / ".env").exists():
            (common / ".env").write_text(COMMON_ENV_22)
    else:
        (run / "panther_config.env").write_text(ENV_21.format(serial=robot.serial))
    (home / ".ssh").mkdir(mode=0o700)
    recording = root / DEMO_RECORDING.lstrip("/")
    recording.parent.mkdir(parents=True)
    recording.write_text(json.dumps(_ros_answers(robot), indent=2) + "\n")


def _release_template(version: str, rel: str) -> Path:
    """The template of ``rel`` (a path under ~/config) for release ``version``: its template directories in order."""
    from panther_ops.core.robot.files import family_dirs
    from panther_ops.core.stack import stack_from_version

    for directory in family_dirs(stack_from_version(version)):
        path = template_path("config", directory, *rel.split("/"))
        if path.is_file():
            return path
    raise UsageError(f"panther-ops has no template of {rel} for husarion_ugv {version}")


def _ros_answers(robot: DemoRobot) -> dict[str, object]:
    """What the robot's driver and its User Computer answered, in their own words (`estop
    status` and `webui status` read it)."""
    # 2.3.2: cmd_vel is the twist mux's input of priority 1, TwistStamped (husarion_ugv_ros@2.3.2:ROS_API.md,
    # husarion_ugv_controller/config/WH01_controller.yaml twist_mux_controller.cmd_vel_inputs.unknown)
    jazzy = robot.release.startswith("2.3.")
    kind = "geometry_msgs/msg/TwistStamped" if jazzy else "geometry_msgs/msg/Twist"
    node = "twist_mux_controller" if jazzy else "drive_controller"
    pubs = "".join(f"Node name: {node}\nNode namespace: /\nTopic type: {kind}\n"
                   "Endpoint type: PUBLISHER\n\n" for node in robot.cmd_vel_publishers)
    # and the mux's other inputs, manual/cmd_vel and autonomous/cmd_vel, have no publisher here
    mux = {f"publishers_{i}": (f"Type: {kind}\n\nPublisher count: 0\n\nSubscription count: 1\n\n"
                               f"Node name: {node}\nNode namespace: /panther\nTopic type: {kind}\n"
                               "Endpoint type: SUBSCRIPTION\n") for i in ("manual", "autonomous")}
    return {
        "namespace": "/panther",
        "status": f"data: {'true' if robot.e_stop else 'false'}\n---\n",
        "publishers": (f"Type: {kind}\n\nPublisher count: {len(robot.cmd_vel_publishers)}\n\n{pubs}"
                       f"Subscription count: 1\n\nNode name: {node}\nNode namespace: /panther\n"
                       f"Topic type: {kind}\nEndpoint type: SUBSCRIPTION\n"),
        **(mux if jazzy else {}),
        **({} if robot.webui_running is None else {"webui": _webui_answers(robot.webui_running)}),
    }


def _webui_answers(running: bool) -> dict[str, object]:
    """`snap list|get -d|services husarion-webui` on the User Computer, and the /ui fetch."""
    config = {"ros": {"domain-id": "0", "localhost-only": "0", "namespace": "panther",
                      "transport": "rmw_cyclonedds_cpp"}, "webui": {"layout": "panther", "port": "8080"}}
    state = ("@@list\nName            Version  Rev  Tracking       Publisher  Notes\n"
             "husarion-webui  1.4.2    42   humble/stable  husarion   -\n@@exit 0\n"
             f"@@get\n{json.dumps(config, indent=1)}\n@@exit 0\n"
             "@@services\nService                 Startup  Current   Notes\n"
             f"husarion-webui.daemon   disabled {'active' if running else 'inactive'}  -\n@@exit 0\n"
             "@@profiles\n@@exit 0\n")
    return {"host": "10.15.20.3", "state": state, "ui_http": 200 if running else None}
