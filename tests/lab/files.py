"""Contents of the files a simulated robot and the lab's operator side are made of.

Pure functions (text in, text out) except for the host-file readers at the top, so the
shape of every generated file can be checked without root.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import yaml

from panther_ops.transport.hostkeys import known_hosts_name

if TYPE_CHECKING:
    from .lab import Robot

REPO = Path(__file__).resolve().parents[2]
TEMPLATES = REPO / "templates" / "compose"
DATA = Path(__file__).resolve().parent / "data"

USER = "husarion"
UID = 1000
GID = 1000
HOME = f"/home/{USER}"


# ---------------------------------------------------------------------------------------
# Stack images
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class StackImage:
    """One driver stack a lab robot can run (one compose template)."""

    key: str  # "2.1.1"
    template: str  # file name in templates/compose
    system_build_version: str  # SYSTEM_BUILD_VERSION of the robot's OS (lab assumption <2.2)

    @property
    def ugv(self) -> bool:
        """husarion_ugv 2.2+ layout (robot_config.env, /home/husarion/config)."""
        return tuple(int(x) for x in self.key.split(".")) >= (2, 2, 0)

    @property
    def distro(self) -> str:
        """The image's ROS 2 distro: jazzy for husarion_ugv 2.3 (husarion_ugv_ros@2.3.2:docker/Dockerfile.hardware
        `ARG ROS_DISTRO=jazzy`), else humble."""
        return "jazzy" if tuple(int(x) for x in self.key.split(".")) >= (2, 3, 0) else "humble"

    @property
    def group(self) -> str:
        return f"stack-{self.key}"

    def template_text(self) -> str:
        return (TEMPLATES / self.template).read_text()

    def images(self) -> list[str]:
        return re.findall(r"^\s*image:\s*(\S+)", self.template_text(), flags=re.M)


STACKS = {
    "2.0.4": StackImage("2.0.4", "panther-2.0.4.yaml", "v2.0.0"),
    "2.1.1": StackImage("2.1.1", "panther-2.1.1.yaml", "v2.1.0"),
    "2.2.2": StackImage("2.2.2", "husarion-ugv-2.2.2.yaml", "v2.2.0"),
    # ROS 2 Jazzy; the OS gate is still v2.2.0 (husarion_ugv_ros@2.3.2:husarion_ugv_bringup/launch/bringup.launch.py
    # MIN_REQUIRED_OS_VERSION): the same Built-in Computer OS as 2.2.2
    "2.3.2": StackImage("2.3.2", "husarion-ugv-2.3.2.yaml", "v2.2.0"),
}
_ALIASES = {"2.0": "2.0.4", "2.1": "2.1.1", "2.2": "2.2.2", "2.3": "2.3.2"}


def stack(key: str) -> StackImage:
    """`2.0`, `2.0.4`, `2.1`, `2.1.1`, `2.2`, `2.2.2`, `2.3`, `2.3.2` -> the lab's stack image."""
    k = _ALIASES.get(key.strip(), key.strip())
    if k not in STACKS:
        raise ValueError(f"unknown image version {key!r}: use one of 2.0, 2.1.1, 2.2, 2.3.2")
    return STACKS[k]


def all_image_tags() -> list[str]:
    """Every image tag used by the compose templates (driver and gamepad images)."""
    tags: list[str] = []
    for s in STACKS.values():
        tags += [t for t in s.images() if t not in tags]
    return tags


# ---------------------------------------------------------------------------------------
# Compose file made runnable in the lab
# ---------------------------------------------------------------------------------------
#: keys removed from every service: they name hardware the lab lacks
DROPPED_KEYS = ("devices", "device_cgroup_rules")
#: volume entries removed: the host paths do not exist in the lab
DROPPED_VOLUME_SOURCES = ("/sys/bus/iio", "/run/dbus")


def lab_compose(text: str, *, drop_ulimits: bool = False) -> str:
    """The template with only what cannot exist in the lab removed, line by line.

    Everything else (anchors, comments, command, the id_rsa and /run/husarion mounts,
    restart: always, security_opt, ...) is kept byte for byte. `ulimits` (rtprio 99,
    memlock) is kept too unless `drop_ulimits`: on a machine whose root lacks
    CAP_SYS_RESOURCE runc cannot raise those hard limits and no container would start.
    """
    keys = DROPPED_KEYS + (("ulimits",) if drop_ulimits else ())
    drop_key = re.compile(r"^(" + "|".join(keys) + r"):\s*(#.*)?$")
    out: list[str] = []
    skip_indent: int | None = None
    for line in text.splitlines(keepends=True):
        body = line.lstrip(" ")
        indent = len(line) - len(body)
        if skip_indent is not None:
            if not body.strip():
                continue
            if indent > skip_indent or (indent == skip_indent and body.startswith("- ")):
                continue
            skip_indent = None
        if drop_key.match(body):
            skip_indent = indent
            continue
        if body.startswith("- ") and any(src in body for src in DROPPED_VOLUME_SOURCES):
            continue
        out.append(line)
    result = "".join(out)
    doc = yaml.safe_load(result)  # still valid YAML with the same services
    assert set(doc["services"]) == set(yaml.safe_load(text)["services"])
    return result


# ---------------------------------------------------------------------------------------
# Accounts (the robot's own /etc/passwd, group, shadow; the host's are only read)
# ---------------------------------------------------------------------------------------
def robot_passwd(host_passwd: str) -> str:
    keep = []
    for line in host_passwd.splitlines():
        f = line.split(":")
        if len(f) < 7 or f[0] == USER or f[2] == str(UID):
            continue
        keep.append(line)
    keep.append(f"{USER}:x:{UID}:{GID}:Husarion,,,:{HOME}:/bin/bash")
    return "\n".join(keep) + "\n"


def robot_group(host_group: str) -> str:
    lines = []
    have_docker = False
    used = set()
    for line in host_group.splitlines():
        f = line.split(":")
        if len(f) < 4 or f[0] == USER or f[2] == str(GID):
            continue
        used.add(f[2])
        if f[0] == "docker":
            have_docker = True
            members = [m for m in f[3].split(",") if m]
            f[3] = ",".join([*members, USER])
        lines.append(":".join(f))
    if not have_docker:
        gid = next(g for g in range(999, 100, -1) if str(g) not in used)
        lines.append(f"docker:x:{gid}:{USER}")
    lines.append(f"{USER}:x:{GID}:")
    return "\n".join(lines) + "\n"


def robot_shadow(passwd: str, husarion_hash: str = "*") -> str:
    """A shadow file for the robot's passwd: every account locked (`*`), no host hash copied.

    `*` rather than `!`: sshd with `UsePAM no` refuses accounts whose field starts with `!`.
    """
    out = []
    for line in passwd.splitlines():
        name = line.split(":", 1)[0]
        pw = husarion_hash if name == USER else "*"
        out.append(f"{name}:{pw}:19900:0:99999:7:::")
    return "\n".join(out) + "\n"


# ---------------------------------------------------------------------------------------
# sshd
# ---------------------------------------------------------------------------------------
def sshd_config(ip: str, *, password: bool = False, setenv: dict[str, str] | None = None,
                port: int = 22) -> str:
    lines = [
        "# sshd of one panther-ops lab robot (tests/lab); robot view of the paths",
        f"ListenAddress {ip}:{port}",
        "HostKey /etc/ssh/ssh_host_ed25519_key",
        "PidFile /run/sshd.pid",
        "AuthorizedKeysFile .ssh/authorized_keys",
        "PubkeyAuthentication yes",
        f"PasswordAuthentication {'yes' if password else 'no'}",
        "KbdInteractiveAuthentication no",
        "PermitEmptyPasswords no",
        "UsePAM no",
        "PermitRootLogin no",
        f"AllowUsers {USER}",
        "LogLevel VERBOSE",
        "X11Forwarding no",
        "PrintMotd no",
        "AcceptEnv LANG LC_*",
        "Subsystem sftp /usr/lib/openssh/sftp-server",
    ]
    if setenv:
        lines.append("SetEnv " + " ".join(f"{k}={v}" for k, v in setenv.items()))
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------------------
# Robot configuration (what the Built-in Computer's OS provides)
# ---------------------------------------------------------------------------------------
def robot_env(st: StackImage, serial: str) -> tuple[str, str, str, str]:
    """(env path, env text, yaml path, yaml text) under /run/husarion for this stack."""
    if st.ugv:
        env = (
            "# Robot configuration from EEPROM (panther-ops lab stand-in)\n"
            "ROBOT_MODEL_NAME=panther\n"
            f"ROBOT_SERIAL_NO={serial}\n"
            "ROBOT_VERSION=1.2\n"
            f"SYSTEM_BUILD_VERSION={st.system_build_version}\n"
        )
        yml = (
            "# Robot configuration from EEPROM (panther-ops lab stand-in)\n"
            "robot_model_name: panther\n"
            f'robot_serial_no: "{serial}"\n'
            "robot_version: 1.2\n"
            f"system_build_version: {st.system_build_version}\n"
        )
        return "/run/husarion/robot_config.env", env, "/run/husarion/robot_config.yaml", yml
    env = (
        f"# Setup envs from eeprom (panther-ops lab stand-in)\nPANTHER_ROBOT_VERSION=1.2\nPANTHER_SERIAL_NO={serial}\n"
    )
    yml = f'# Robot configuration from EEPROM (panther-ops lab stand-in)\npanther_version: 1.2\nserial_no: "{serial}"\n'
    return "/run/husarion/panther_config.env", env, "/run/husarion/panther_config.yaml", yml


def login_profile(st: StackImage, skel_profile: str) -> str:
    """~/.profile: Debian's skeleton plus the robot's environment in every login shell."""
    env_path = robot_env(st, "")[0]
    return (
        skel_profile.rstrip("\n")
        + "\n\n# panther-ops lab: the robot's configuration in the login environment\n"
        + f"if [ -f {env_path} ]; then\n    set -a\n    . {env_path}\n    set +a\nfi\n"
        + f"export SYSTEM_BUILD_VERSION=${{SYSTEM_BUILD_VERSION:-{st.system_build_version}}}\n"
    )


def _drive_params(wheel: str) -> str:
    """The drive controller's wheel geometry and frames, as every release's controller file has them
    (husarion_ugv_ros@2.2.2 and @2.3.2:husarion_ugv_controller/config/{WH01,WH04}_controller.yaml)."""
    sep, radius, mult = {"WH01": (0.697, 0.1825, 1.5), "WH04": (0.616, 0.1016, 1.0)}.get(wheel, (0.697, 0.1825, 1.5))
    return f"""      left_wheel_names: [fl_wheel_joint, rl_wheel_joint]
      right_wheel_names: [fr_wheel_joint, rr_wheel_joint]
      wheel_separation: {sep}
      wheel_radius: {radius}
      wheel_separation_multiplier: {mult}
      publish_rate: 100.0
      odom_frame_id: odom
      base_frame_id: base_link
      enable_odom_tf: false
      cmd_vel_timeout: 0.2
"""


def _controller_yaml(drive: str, wheel: str) -> str:
    # the limits of husarion_ugv_ros@2.2.2:husarion_ugv_controller/config/{WH01,WH04}_controller.yaml
    v, a, w, b = {"WH04": (1.1, 1.5, 2.2, 3.2)}.get(wheel, (2.0, 2.7, 4.0, 5.74))
    # the IMU broadcaster as husarion_ugv_ros@2.2.2:husarion_ugv_controller/config/WH01_controller.yaml has it
    return f"""# {wheel}_controller.yaml (panther-ops lab stand-in of the husarion_ugv_controller file)
/**:
  controller_manager:
    ros__parameters:
      update_rate: 100
      joint_state_broadcaster:
        type: joint_state_broadcaster/JointStateBroadcaster
      {drive}:
        type: diff_drive_controller/DiffDriveController
      imu_broadcaster:
        type: imu_sensor_broadcaster/IMUSensorBroadcaster

  imu_broadcaster:
    ros__parameters:
      sensor_name: <namespace>/imu
      frame_id: <namespace>/imu_link

  {drive}:
    ros__parameters:
{_drive_params(wheel)}      linear:
        x:
          has_velocity_limits: true
          has_acceleration_limits: true
          max_velocity: {v}
          max_acceleration: {a}
      angular:
        z:
          has_velocity_limits: true
          has_acceleration_limits: true
          max_velocity: {w}
          max_acceleration: {b}
"""


def _jazzy_controller_yaml(wheel: str) -> str:
    """2.3.2's controller file shape (husarion_ugv_ros@2.3.2:husarion_ugv_controller/config/WH01_controller.yaml):
    the Jazzy limits schema, the IMU covariance placeholder filled at launch, and the twist mux's inputs."""
    axes = "".join(
        f"      {axis}:\n        {sub}:\n          max_velocity: {v}\n          min_velocity: -{v}\n"
        f"          max_acceleration: {a}\n          max_deceleration: -{a}\n          max_acceleration_reverse: -{a}\n"
        f"          max_deceleration_reverse: {a}\n          max_jerk: .NAN\n          min_jerk: .NAN\n"
        for axis, sub, v, a in (("linear", "x", 2.0, 2.7), ("angular", "z", 4.0, 5.74)))
    inputs = "".join(f"        {name}:\n          topic: {topic}\n          timeout: 0.2\n          priority: {prio}\n"
                     for name, topic, prio in (("manual", "manual/cmd_vel", 100), ("autonomous", "autonomous/cmd_vel", 10),
                                               ("unknown", "cmd_vel", 1)))
    return f"""# {wheel}_controller.yaml (panther-ops lab stand-in of the husarion_ugv_controller file, 2.3.2)
/**:
  controller_manager:
    ros__parameters:
      update_rate: 100
      joint_state_broadcaster:
        type: joint_state_broadcaster/JointStateBroadcaster
      drive_controller:
        type: diff_drive_controller/DiffDriveController
      imu_broadcaster:
        type: imu_sensor_broadcaster/IMUSensorBroadcaster
      twist_mux_controller:
        type: twist_mux_controller/TwistMuxController

  imu_broadcaster:
    ros__parameters:
      sensor_name: <namespace>/imu
      frame_id: <namespace>/imu_link
      static_covariance_orientation: <static_covariance_orientation>

  drive_controller:
    ros__parameters:
{_drive_params(wheel)}      publish_limited_velocity: false
{axes}
  twist_mux_controller:
    ros__parameters:
      holonomic: false
      cmd_vel_inputs:
{inputs}      command_interface_linear_x: drive_controller/linear/velocity
      command_interface_angular_z: drive_controller/angular/velocity
"""


def ugv_config_tree(namespace: str = "panther", st: StackImage | None = None) -> dict[str, str]:
    """/home/husarion/config for 2.2+ robots: relative path -> content (stand-in contents).

    On 2.3.2 (``st``) the image copies joy2twist from husarion_ugv_teleop, where it publishes stamped twists
    on manual/cmd_vel (husarion_ugv_ros@2.3.2:docker/utils/update_config_directory.sh,
    husarion_ugv_teleop/config/joy2twist_panther.yaml), and the controller files have 2.3.2's shape."""
    jazzy = st is not None and st.distro == "jazzy"
    joy2twist = ("husarion_ugv_teleop/config/joy2twist_panther.yaml" if jazzy
                 else "husarion_ugv_bringup/config/joy2twist_panther.yaml")
    stamped = "    cmd_vel_topic: manual/cmd_vel\n    cmd_vel_stamped: true\n" if jazzy else ""
    tree = {
        "common/.env": (f"ROS_DOMAIN_ID=0\nRMW_IMPLEMENTATION=rmw_cyclonedds_cpp\nROBOT_NAMESPACE={namespace}\n"),
        joy2twist: (
            "# panther-ops lab stand-in (husarion_ugv_ros@2.2.2:husarion_ugv_bringup/config/joy2twist_panther.yaml's "
            "form; 2.3.2: husarion_ugv_teleop's)\n/**:\n  ros__parameters:\n" + stamped +
            "    linear_velocity_factor:\n      fast: 1.0\n      regular: 0.5\n      slow: 0.2\n"
        ),
        "husarion_ugv_description/config/components.yaml": "components: []\n",
        "husarion_ugv_lights/config/user_animations.yaml": "user_animations: []\n",
        "husarion_ugv_lights/config/panther_animations.yaml": (
            "# panther-ops lab stand-in\npanels:\n  - channel: 1\n    number_of_leds: 46\n"
            "  - channel: 2\n    number_of_leds: 46\nsegments: []\nsegments_map: {}\n"
            "led_animations: []\n"
        ),
        "husarion_ugv_localization/config/relative_localization.yaml": (
            "# panther-ops lab stand-in\n/**:\n  ekf_filter:\n    ros__parameters:\n      frequency: 25.0\n"
        ),
        "husarion_ugv_manager/behavior_trees/lights.xml": (
            '<?xml version="1.0"?>\n<!-- panther-ops lab stand-in -->\n'
            '<root BTCPP_format="4" main_tree_to_execute="Lights">\n'
            '  <BehaviorTree ID="Lights"><AlwaysSuccess/></BehaviorTree>\n</root>\n'
        ),
        "husarion_ugv_manager/behavior_trees/LightsBT.btproj": (
            '<?xml version="1.0"?>\n<!-- panther-ops lab stand-in -->\n'
            '<root BTCPP_format="4" project_name="LightsBT">\n'
            '  <include path="lights.xml"/>\n</root>\n'
        ),
        # the real default names 10.15.20.3; the lab keeps it empty (no traffic outside the lab)
        "husarion_ugv_manager/config/shutdown_hosts.yaml": (
            "# panther-ops lab: no user computer to shut down\nhosts: []\n"
        ),
    }
    for wheel in ("WH01", "WH04"):
        tree[f"husarion_ugv_controller/config/{wheel}_controller.yaml"] = (
            _jazzy_controller_yaml(wheel) if jazzy else _controller_yaml("drive_controller", wheel))
    return tree


def etc_hosts(name: str, ip: str) -> str:
    return f"127.0.0.1\tlocalhost\n127.0.1.1\t{name}\n{ip}\t{name}\n::1\tlocalhost ip6-localhost ip6-loopback\n"


SUDOERS = (
    "# panther-ops lab: as on the Built-in Computer for the shutdown of hosts\n"
    f"{USER} ALL=(ALL) NOPASSWD: /sbin/poweroff, /sbin/reboot, /sbin/shutdown\n"
)


# ---------------------------------------------------------------------------------------
# Keys
# ---------------------------------------------------------------------------------------
def ed25519_keypair(comment: str = "") -> tuple[bytes, str]:
    """(private key in OpenSSH format, public key line)."""
    from cryptography.hazmat.primitives import serialization as ser
    from cryptography.hazmat.primitives.asymmetric import ed25519

    key = ed25519.Ed25519PrivateKey.generate()
    priv = key.private_bytes(ser.Encoding.PEM, ser.PrivateFormat.OpenSSH, ser.NoEncryption())
    pub = key.public_key().public_bytes(ser.Encoding.OpenSSH, ser.PublicFormat.OpenSSH).decode()
    return priv, (f"{pub} {comment}".strip())


def rsa_keypair(comment: str = "") -> tuple[bytes, str]:
    from cryptography.hazmat.primitives import serialization as ser
    from cryptography.hazmat.primitives.asymmetric import rsa

    key = rsa.generate_private_key(public_exponent=65537, key_size=2048)
    priv = key.private_bytes(ser.Encoding.PEM, ser.PrivateFormat.OpenSSH, ser.NoEncryption())
    pub = key.public_key().public_bytes(ser.Encoding.OpenSSH, ser.PublicFormat.OpenSSH).decode()
    return priv, (f"{pub} {comment}".strip())


def fingerprint(public_line: str) -> str:
    """OpenSSH SHA256 fingerprint (`SHA256:…`, as `ssh-keygen -l` prints) of a public key line."""
    import base64
    import hashlib

    blob = base64.b64decode(public_line.split()[1])
    digest = base64.b64encode(hashlib.sha256(blob).digest()).decode().rstrip("=")
    return f"SHA256:{digest}"


def public_key_of(private_pem: bytes) -> str:
    from cryptography.hazmat.primitives import serialization as ser

    key = ser.load_ssh_private_key(private_pem, password=None)
    return key.public_key().public_bytes(ser.Encoding.OpenSSH, ser.PublicFormat.OpenSSH).decode()


# ---------------------------------------------------------------------------------------
# Operator side: inventory.yaml, ssh_config, known_hosts
# ---------------------------------------------------------------------------------------
def inventory_groups(robot: Robot) -> tuple[str, ...]:
    """The inventory groups of a lab robot: ``lab`` and its stack's (``stack-2.2.2``)."""
    return ("lab", robot.stack.group)


def inventory_yaml(robots: list[Robot]) -> str:
    lines = [
        "version: 1",
        "settings:",
        "  ssh_config: ssh_config        # relative to this file",
        "  known_hosts: known_hosts",
        "defaults:",
        f"  user: {USER}",
        "  identity_file: id_ed25519",
        "groups:",
        *(f"  {g}: {{}}" for g in dict.fromkeys(g for r in robots for g in inventory_groups(r))),
        "robots:",
    ]
    for r in robots:
        lines += [
            f"  {r.name}:",
            f"    host: {r.host}",
            f"    port: {r.port}",
            f"    groups: [{', '.join(inventory_groups(r))}]",
        ]
        if r.jump:
            lines.append(f"    jump: {r.jump}")
    return "\n".join(lines) + "\n"


def known_hosts(robots: list[Robot], host_keys: Mapping[str, str]) -> str:
    """``host_keys``: each robot's host key by name (``ssh-ed25519 AAAA...``)."""
    return "".join(f"{known_hosts_name(r.host, r.port)} {host_keys[r.name]}\n" for r in robots)


def ssh_config(robots: list[Robot], identity: Path, known: Path) -> str:
    blocks = [f"# panther-ops test lab: ssh -F {identity.parent / 'ssh_config'} <robot>\n"]
    for r in robots:
        lines = [
            f"Host {r.name}",
            f"    HostName {r.host}",
            f"    User {USER}",
            f"    Port {r.port}",
            f"    IdentityFile {identity}",
            "    IdentitiesOnly yes",
            f"    UserKnownHostsFile {known}",
            "    GlobalKnownHostsFile /dev/null",
            "    StrictHostKeyChecking yes",
            "    ConnectTimeout 5",
        ]
        if r.jump:
            lines.append(f"    ProxyJump {r.jump}")
        blocks.append("\n".join(lines) + "\n")
    return "\n".join(blocks)
