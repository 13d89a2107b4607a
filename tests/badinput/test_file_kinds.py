"""Bad-input corpus: every command that carries a file kind, with the contents that kind's one
validator refuses (issue 11, findings 1, 2, 6, 8, 12; issue 24), injection strings and paths that
leave their directory. Each case: exit 2, the file or key named, no traceback, every file of
the demo fleet (and of the operator) byte-identical.

Robots of the demo fleet: panther-01 runs panther_ros 2.1.1 (WH01), panther-02 2.0.4,
panther-03 husarion_ugv 2.2.2 (config tree, HTTP shutdown hosts).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.badinput.harness import Case, check_refused

TEMPLATES = Path(__file__).resolve().parents[2] / "templates"
WH01 = (TEMPLATES / "config/panther-2.1/panther_controller/config/WH01_controller.yaml").read_text()
WHEEL = (TEMPLATES / "config/panther-2.1/panther_description/config/WH01.yaml").read_text()
LIGHTS_XML = (TEMPLATES / "behavior_trees/lights.xml").read_text()
SAFETY_XML = (TEMPLATES / "behavior_trees/safety.xml").read_text()
SHUTDOWN_XML = (TEMPLATES / "behavior_trees/shutdown.xml").read_text()
HOSTS_TREE = "demo/robots/panther-03/home/husarion/config/husarion_ugv_manager/config/shutdown_hosts.yaml"


def _ctrl(old: str, new: str, text: str = WH01) -> bytes:
    assert old in text, old
    return text.replace(old, new, 1).encode()


# ------------------------------------------------------------------ controller files
CONTROLLER_BAD: dict[str, tuple[bytes, list[str]]] = {
    "fast": (_ctrl("max_velocity: 2.0", "max_velocity: fast"), ["max_velocity='fast' is not a number"]),
    "maybe": (_ctrl("has_velocity_limits: true", "has_velocity_limits: maybe"),
              ["has_velocity_limits='maybe' is not a boolean"]),
    "quoted-bool": (_ctrl("has_velocity_limits: true", 'has_velocity_limits: "true"'),
                    ["has_velocity_limits='true' is not a boolean"]),
    "integer": (_ctrl("max_velocity: 2.0", "max_velocity: 2"), ["max_velocity=2 is an integer"]),
    "above-limit": (_ctrl("max_velocity: 2.0", "max_velocity: 3.0"), ["exceeds the WH01 limit of 2.0"]),
    "angular-above": (_ctrl("max_velocity: 4.0", "max_velocity: 9.0"), ["angular.z.max_velocity=9.0"]),
    "negative-max": (_ctrl("max_acceleration: 2.7", "max_acceleration: -1.0"), ["must not be negative"]),
    "nan": (_ctrl("max_velocity: 2.0", "max_velocity: .nan"), ["must be a finite number"]),
    "linear-y-on-wh01": (_ctrl("      angular:\n", "        y:\n          max_velocity: 1.0\n      angular:\n"),
                         ["linear.y limits exist only for the mecanum wheels WH02"]),
    "unknown-axis": (_ctrl("      angular:\n", "        w:\n          max_velocity: 1.0\n      angular:\n"),
                     ["controller.linear.w: not an axis"]),
    "unknown-limit": (_ctrl("max_jerk: 0.0 # m/s^3", "max_speed: 1.0"), ["unknown controller limit"]),
    "wheel-radius-negative": (_ctrl("wheel_radius: 0.1825", "wheel_radius: -0.1825"),
                              ["wheel_radius=-0.1825 must be a finite number > 0"]),
    "wheel-radius-int": (_ctrl("wheel_radius: 0.1825", "wheel_radius: 1"), ["wheel_radius=1 is an integer"]),
    "old-key": (_ctrl("  drive_controller:\n    ros__parameters:\n      left",
                      "  panther_base_controller:\n    ros__parameters:\n      left"),
                ["configures panther_base_controller but"]),
    "not-a-mapping": (b"- just\n- a list\n", ["not a mapping"]),
    "not-yaml": (b"/**:\n  drive_controller: [\n", ["not valid YAML"]),
    "binary": (b"\x89PNG\r\n\x1a\n\x00\x00\xff\xfe", ["not a UTF-8 text file"]),
    "no-section": (b"/**:\n  something_else:\n    ros__parameters: {}\n", ["no drive_controller"]),
}

# ------------------------------------------------------------------ wheel, components, battery
WHEEL_BAD: dict[str, tuple[bytes, list[str]]] = {
    "radius-word": (WHEEL.replace("wheel_radius: 0.1825", "wheel_radius: fast").encode(), ["wheel_radius='fast'"]),
    "radius-negative": (WHEEL.replace("wheel_radius: 0.1825", "wheel_radius: -1").encode(), ["wheel_radius=-1"]),
    "radius-missing": (WHEEL.replace("wheel_radius: 0.1825\n", "").encode(), ["wheel_radius is required"]),
    "mecanum-maybe": (WHEEL.replace("mecanum: False", "mecanum: maybe").encode(), ["mecanum='maybe'"]),
    "unknown-key": ((WHEEL + "turbo: true\n").encode(), ["turbo: unknown key"]),
    "inertia-list": (WHEEL.replace("inertia: { ixx: 0.022510, iyy: 0.034850, izz: 0.022510 }",
                                   "inertia: [1, 2, 3]").encode(), ["inertia=[1, 2, 3] must be a mapping"]),
    "folder-escape": (WHEEL.replace("folder_path: meshes/WH01", "folder_path: ../../../etc").encode(),
                      ["folder_path='../../../etc'"]),
    "mass-zero": (WHEEL.replace("mass: 3.0", "mass: 0").encode(), ["mass=0 must be a finite number > 0"]),
}
COMPONENTS_BAD: dict[str, tuple[bytes, list[str]]] = {
    "not-a-list": (b"components: LDR06\n", ["components='LDR06' must be a list"]),
    "type-injection": (b"components:\n  - type: '$(rm -rf /)'\n    parent_link: cover_link\n",
                       ["components[0].type='$(rm -rf /)'"]),
    "xyz-words": (b"components:\n  - type: LDR06\n    parent_link: cover_link\n    xyz: a b c\n",
                  ["components[0].xyz='a b c'"]),
    "link-injection": (b"components:\n  - type: LDR06\n    parent_link: 'cover_link; x'\n",
                       ["components[0].parent_link='cover_link; x'"]),
    "unknown-key": (b"components:\n  - type: LDR06\n    parent_link: cover_link\n    colour: red\n",
                    ["components[0].colour: unknown key"]),
    "no-parent": (b"components:\n  - type: LDR06\n", ["components[0].parent_link is required"]),
}
BATTERY_BAD: dict[str, tuple[bytes, list[str]]] = {
    "capacity-negative": (b"capacity: -5.0\n", ["capacity=-5.0 must be a finite number > 0"]),
    "percent-on-2.1": (b"initial_charge_percentage: 70.0\n", ["initial_charge_percentage=70.0 is outside 0-1"]),
    "discharging-maybe": (b"simulate_discharging: maybe\n", ["simulate_discharging='maybe'"]),
    "power-nan": (b"power_load: .nan\n", ["power_load=nan must be a finite number > 0"]),
    "unknown-key": (b"voltage: 48.0\n", ["voltage: unknown key"]),
    "list": (b"- 1\n- 2\n", ["must be a YAML mapping"]),
}

# ------------------------------------------------------------------ gamepad (joy2twist) parameters
JOY2TWIST = """joy2twist_node:
  ros__parameters:
    linear_velocity_factor:
      fast: 1.0
      regular: 0.5
      slow: 0.2
    angular_velocity_factor:
      fast: 1.0
      regular: 0.5
      slow: 0.2
    button_index_map:
      axis:
        angular_z: 0
        linear_x: 4
        linear_y: 3
      dead_man_switch: 4
      fast_mode: 7
      slow_mode: 6
      e_stop_reset: 0
      e_stop_trigger: 1
      enable_e_stop_reset: 6
    e_stop:
      present: true
      reset_srv: hardware/e_stop_reset
      trigger_srv: hardware/e_stop_trigger
"""


def _joy(old: str, new: str) -> bytes:
    assert old in JOY2TWIST, old
    return JOY2TWIST.replace(old, new, 1).encode()


JOY2TWIST_BAD: dict[str, tuple[bytes, list[str]]] = {
    "factor-text": (_joy("slow: 0.2", "slow: fast"), ["linear_velocity_factor.slow='fast' must be a floating"]),
    "factor-int": (_joy("fast: 1.0", "fast: 1"), ["linear_velocity_factor.fast=1 must be a floating"]),
    "factor-negative": (_joy("regular: 0.5", "regular: -0.5"), ["regular=-0.5 must be a finite number >= 0"]),
    "factor-nan": (_joy("regular: 0.5", "regular: .nan"), ["must be a finite number >= 0"]),
    "unknown-mode": (_joy("slow: 0.2", "slow: 0.2\n      turbo: 2.0"), ["linear_velocity_factor.turbo: unknown key"]),
    "index-float": (_joy("linear_x: 4", "linear_x: 4.5"), ["axis.linear_x=4.5 must be an integer"]),
    "index-negative": (_joy("dead_man_switch: 4", "dead_man_switch: -1"), ["dead_man_switch=-1 must be an index"]),
    "index-bool": (_joy("fast_mode: 7", "fast_mode: true"), ["fast_mode=True must be an integer"]),
    "unknown-button": (_joy("fast_mode: 7", "turbo_mode: 7"), ["button_index_map.turbo_mode: unknown key"]),
    "unknown-axis": (_joy("linear_y: 3", "linear_z: 3"), ["axis.linear_z: unknown key"]),
    "unknown-param": (_joy("    e_stop:\n", "    max_speed: 2.0\n    e_stop:\n"),
                      ["ros__parameters.max_speed: unknown key"]),
    "present-maybe": (_joy("present: true", "present: maybe"), ["e_stop.present='maybe' must be true or false"]),
    "srv-space": (_joy("reset_srv: hardware/e_stop_reset", "reset_srv: bad srv"), ["reset_srv='bad srv'"]),
    # issue 23 item 5: names by rcl's rules (core/parse/ros_names.py), not only "no whitespace"
    "srv-dash": (_joy("reset_srv: hardware/e_stop_reset", "reset_srv: hardware/e-stop-reset"),
                 ["e_stop.reset_srv='hardware/e-stop-reset'", "not a valid ROS service name", "'-' is not allowed"]),
    "srv-digit": (_joy("trigger_srv: hardware/e_stop_trigger", "trigger_srv: hardware/2trigger"),
                  ["e_stop.trigger_srv='hardware/2trigger'", "the token '2trigger' starts with a digit"]),
    "srv-double-slash": (_joy("trigger_srv: hardware/e_stop_trigger", "trigger_srv: hardware//e_stop_trigger"),
                         ["e_stop.trigger_srv='hardware//e_stop_trigger'", "'//'"]),
    "srv-substitution": (_joy("reset_srv: hardware/e_stop_reset", "reset_srv: '{robot}/e_stop_reset'"),
                         ["e_stop.reset_srv='{{robot}}/e_stop_reset'", "unknown substitution {{robot}}"]),
    "topic-tilde": (_joy("present: true", "present: true\n      topic: hardware/e_stop~"),
                    ["e_stop.topic='hardware/e_stop~'", "not a valid ROS topic name", "'~'"]),
    "topic-number": (_joy("present: true", "present: true\n      topic: 5"),
                     ["e_stop.topic=5", "a non-empty text"]),
    "cmd-vel-trailing-slash": (_joy("    e_stop:\n", "    cmd_vel_topic: cmd_vel/\n    e_stop:\n"),
                               ["cmd_vel_topic='cmd_vel/'", "it ends with '/'"]),
    "cmd-vel-semicolon": (_joy("    e_stop:\n", "    cmd_vel_topic: 'cmd_vel;reboot'\n    e_stop:\n"),
                          ["cmd_vel_topic='cmd_vel;reboot'", "';' is not allowed"]),
    "wrong-node": (_joy("joy2twist_node:", "teleop_node:"), ["teleop_node: unknown node"]),
    "axis-not-mapping": (_joy("      axis:\n        angular_z: 0\n        linear_x: 4\n        linear_y: 3\n",
                              "      axis: 0\n"), ["button_index_map.axis=0 must be a mapping"]),
    "list": (b"- 1\n- 2\n", ["must be a YAML mapping"]),
    "not-yaml": (b"joy2twist_node: [\n", ["not valid YAML"]),
}

# ------------------------------------------------------------------ animations and LED config
USER_ANIM = """user_animations:
  - id: {id}
    name: MINE
    priority: {priority}
    animations:
      - type: {type}
        segments: {segments}
        animation:
          image: {image}
          duration: {duration}
          repeat: {repeat}
          brightness: {brightness}
          color: {color}
"""
GOOD = {"id": 21, "priority": 2, "type": "panther_lights::ImageAnimation", "segments": "all",
        "image": "$(find panther_lights)/animations/strip01_red.png", "duration": 2, "repeat": 2,
        "brightness": 1.0, "color": "0xffff00"}


def _anim(**changes: object) -> bytes:
    return USER_ANIM.format(**{**GOOD, **changes}).encode()


ANIM_BAD: dict[str, tuple[bytes, list[str]]] = {
    "reserved-id": (_anim(id=5), ["ID 5 is reserved", "anim-id-reserved"]),
    "priority-1": (_anim(priority=1), ["priority 1 is reserved", "anim-priority-reserved"]),
    "priority-7": (_anim(priority=7), ["priority 7 is not 1, 2 or 3"]),
    "unknown-segment": (_anim(segments="roof"), ["segments 'roof' is not a group", "anim-segments-unknown"]),
    "sixty-seconds": (_anim(duration=30, repeat=2), ["duration x repeat = 60 s", "anim-too-long"]),
    "brightness": (_anim(brightness=2.5), ["brightness 2.5 is outside [0, 1]"]),
    "colour-word": (_anim(color="red"), ["color 'red' is not a hex RGB"]),
    "relative-image": (_anim(image="animations/x.png"), ["image path 'animations/x.png' must be absolute"]),
    "missing-stock-image": (_anim(image="$(find panther_lights)/animations/no_such.png"), ["anim-image-not-found"]),
    "own-package-type": (_anim(type="panther_lights::FireworksAnimation"), ["anim-type-unknown"]),
    "type-no-package": (_anim(type="Fireworks"), ["unknown animation type 'Fireworks'"]),
    "duration-zero": (_anim(duration=0), ["duration must be a positive number"]),
    "repeat-zero": (_anim(repeat=0), ["repeat must be a positive integer"]),
    "no-list": (b"animations: []\n", ["no 'user_animations' list"]),
    "not-yaml": (b"user_animations: [\n", ["not valid YAML"]),
}
LED_CONFIG = (TEMPLATES / "config/panther-2.1/panther_lights/config/led_config.yaml").read_text()
LED_BAD: dict[str, tuple[bytes, list[str]]] = {
    "range-outside": (LED_CONFIG.replace("led_range: 45-0", "led_range: 60-0", 1).encode(),
                      ["led_range 60-0 is outside panel 2", "segment-range-outside"]),
    "unknown-channel": (LED_CONFIG.replace("channel: 2\n    led_range", "channel: 7\n    led_range", 1).encode(),
                        ["uses channel 7", "segment-channel-unknown"]),
    "user-file-as-led": (_anim(), ["no 'led_animations' list"]),
}

# ------------------------------------------------------------------ shutdown hosts
HOSTS_BAD: dict[str, tuple[bytes, list[str]]] = {
    "ip-injection": (b'hosts:\n  - ip: "10.15.20.5; touch x"\n    username: husarion\n',
                     ["hosts[0].ip", "'10.15.20.5; touch x' is not an IP address or host name"]),
    "port-70000": (b"hosts:\n  - ip: 10.15.20.5\n    username: husarion\n    port: 70000\n",
                   ["hosts[0].port", "70000 is not a TCP port"]),
    "ip-option": (b'hosts:\n  - ip: "-oProxyCommand=touch x"\n    username: husarion\n',
                  ["'-oProxyCommand=touch x' is not an IP address"]),
    "ip-subst": (b'hosts:\n  - ip: "$(touch x)"\n    username: husarion\n', ["'$(touch x)' is not an IP"]),
    "user-injection": (b'hosts:\n  - ip: 10.15.20.5\n    username: "root; rm -rf /"\n',
                       ["hosts[0].username", "is not a POSIX user name"]),
    "command-newline": (b'hosts:\n  - ip: 10.15.20.5\n    username: pi\n    command: "sudo shutdown now\\nrm -rf /"\n',
                        ["hosts[0].command", "must be a one-line command"]),
    "timeout-negative": (b"hosts:\n  - ip: 10.15.20.5\n    username: pi\n    timeout: -1\n",
                         ["hosts[0].timeout", "-1 is not a number of seconds > 0"]),
    "timeout-nan": (b"hosts:\n  - ip: 10.15.20.5\n    username: pi\n    timeout: .nan\n",
                    ["hosts[0].timeout"]),
    "duplicate": (b"hosts:\n  - ip: 10.15.20.5\n    username: pi\n  - ip: 10.15.20.5\n    username: pi\n",
                  ["hosts[1]", "duplicate of hosts[0]"]),
    "unknown-key": (b"hosts:\n  - ip: 10.15.20.5\n    username: pi\n    sudo: yes\n", ["hosts[0].sudo", "unknown key"]),
    "http-on-ssh-robot": (b"hosts:\n  - ip: 10.15.20.5\n    port: 3003\n", ["no username"]),
    "not-a-list": (b"hosts: 10.15.20.5\n", ["hosts", "must be a list of hosts"]),
    "ping-maybe": (b"hosts:\n  - ip: 10.15.20.5\n    username: pi\n    ping_for_success: maybe\n",
                   ["hosts[0].ping_for_success"]),
}


def _push(kind: str, cid: str, content: bytes, names: list[str], robot: str = "panther-01",
          filename: str = "bad.yaml") -> Case:
    return Case(f"push-{kind}-{cid}-{robot}", ["config", "push", "{tmp}/" + filename, "--as", kind, "-r", robot,
                                               "--yes"],
                [filename, *names], files={filename: content})


CASES: list[Case] = []
for cid, (content, names) in CONTROLLER_BAD.items():
    CASES.append(_push("controller", cid, content, names))
for cid in ("fast", "maybe", "integer", "not-yaml", "binary"):
    CASES.append(_push("controller", cid, *CONTROLLER_BAD[cid], robot="panther-02"))
    CASES.append(_push("controller", cid, *CONTROLLER_BAD[cid], robot="panther-03"))
CASES.append(_push("controller", "dry-run", *CONTROLLER_BAD["above-limit"]))
# issue 24 finding 2: an IMU broadcaster that does not read the namespaced robot's IMU (${ns}imu)
_FLAG = "      use_namespace_as_sensor_name_prefix: true\n"
for robot, tree in (("panther-01", "panther-2.1/panther_controller"), ("panther-02", "panther-2.0/panther_controller"),
                    ("panther-03", "husarion-ugv-2.2/husarion_ugv_controller")):
    stock = (TEMPLATES / "config" / tree / "config/WH01_controller.yaml").read_text()
    old_form = stock.replace(_FLAG, "").replace("<namespace>/imu", "imu")  # sensor_name: imu, no prefix flag
    CASES.append(_push("controller", "imu-not-namespaced", old_form.encode(),
                       ["imu_broadcaster", "'panther/imu'", "the IMU would not start"], robot=robot))
for cid, (content, names) in WHEEL_BAD.items():
    CASES.append(_push("wheel", cid, content, names))
for cid, (content, names) in COMPONENTS_BAD.items():
    CASES.append(_push("components", cid, content, names))
for cid, (content, names) in BATTERY_BAD.items():
    CASES.append(_push("battery", cid, content, names))
# issue 24 finding 8: panther_ros 2.0.1+ reads a 0-1 fraction and every key of the file (gazebo.urdf.xacro)
_BATTERY_20 = (TEMPLATES / "config/panther-2.0/panther_gazebo/config/battery_plugin_config.yaml").read_text()
CASES.append(_push("battery", "percent-on-2.0.4", _BATTERY_20.replace("initial_charge_percentage: 0.7",
                                                                     "initial_charge_percentage: 70.0").encode(),
                   ["initial_charge_percentage=70.0 is outside 0-1"], robot="panther-02"))
CASES.append(_push("battery", "no-capacity-on-2.0.4", _BATTERY_20.replace("capacity: 20.0 # [Ah]\n", "").encode(),
                   ["capacity is required"], robot="panther-02"))
for cid, (content, names) in JOY2TWIST_BAD.items():
    CASES.append(_push("joy2twist", cid, content, names))
for cid in ("factor-text", "index-float", "unknown-button", "srv-dash", "cmd-vel-semicolon"):
    CASES.append(_push("joy2twist", cid, *JOY2TWIST_BAD[cid], robot="panther-02"))
    CASES.append(_push("joy2twist", cid, *JOY2TWIST_BAD[cid], robot="panther-03"))
for cid, (content, names) in ANIM_BAD.items():
    CASES.append(_push("user-animations", cid, content, names))
    CASES.append(Case(f"lights-deploy-{cid}", ["lights", "deploy", "{tmp}/bad.yaml", "-r", "panther-01", "--yes"],
                      ["bad.yaml", *names], files={"bad.yaml": content}))
for cid, (content, names) in LED_BAD.items():
    CASES.append(_push("led", cid, content, names))
for cid, (content, names) in HOSTS_BAD.items():
    CASES.append(_push("shutdown-hosts", cid, content, names))
CASES.append(_push("shutdown-hosts", "ssh-on-http-robot", b"hosts:\n  - ip: 10.15.20.5\n    username: pi\n",
                   ["shuts computers down over HTTP"], robot="panther-03"))
CASES.append(_push("shutdown-hosts", "secret-ref-on-robot",
                   b"hosts:\n  - ip: 10.15.20.5\n    port: 3003\n    secret: {env: NUC}\n",
                   ["hosts[0].secret", "is for local files"], robot="panther-03"))
# file names that would end up in the driver's command
for cid, filename in (("semicolon", "c;touch x.yaml"), ("space", "my ctrl.yaml"), ("subst", "$(id).yaml"),
                      ("newline", "a\nb.yaml")):
    CASES.append(Case(f"push-name-{cid}", ["config", "push", "{tmp}/" + filename, "--as", "controller",
                                           "-r", "panther-01", "--yes"],
                      ["becomes a path in the driver's command"], files={filename: WH01.encode()}))

# ------------------------------------------------------------------ BT projects
LIGHTS_PROJ = '<?xml version="1.0"?>\n<root BTCPP_format="4">\n  <include path="{inc}"/>\n</root>\n'
SAFETY_PROJ = ('<?xml version="1.0"?>\n<root BTCPP_format="4">\n  <include path="safety.xml"/>\n'
               '  <include path="shutdown.xml"/>\n</root>\n')
UNKNOWN_NODE = LIGHTS_XML.replace("<TickAfterTimeout ", "<LaunchRockets ", 1).replace(
    "</TickAfterTimeout>", "</LaunchRockets>", 1)


def _bt(cid: str, kind: str, files: dict[str, bytes], names: list[str]) -> Case:
    return Case(f"push-{kind}-{cid}", ["config", "push", "{tmp}/proj/My.btproj", "--as", kind, "-r", "panther-01",
                                       "--yes"], names, files={f"proj/{k}": v for k, v in files.items()})


for kind in ("bt-lights", "bt-safety"):
    CASES += [
        _bt("include-dotdot", kind, {"My.btproj": LIGHTS_PROJ.replace("{inc}", "../../../.ssh/authorized_keys")
                                     .encode()}, ["../../../.ssh/authorized_keys", "leaves the project's directory"]),
        _bt("include-sibling", kind, {"My.btproj": LIGHTS_PROJ.replace("{inc}", "../outside.xml").encode()},
            ["../outside.xml", "leaves the project's directory"]),
        _bt("include-absolute", kind, {"My.btproj": LIGHTS_PROJ.replace("{inc}", "/etc/passwd").encode()},
            ["/etc/passwd", "is not relative to the project's directory"]),
        _bt("include-home", kind, {"My.btproj": LIGHTS_PROJ.replace("{inc}", "~/.ssh/id_rsa").encode()},
            ["~/.ssh/id_rsa", "is not relative"]),
        _bt("nested-escape", kind, {"My.btproj": LIGHTS_PROJ.replace("{inc}", "sub/a.xml").encode(),
                                    "sub/a.xml": LIGHTS_PROJ.replace("{inc}", "../../x.xml").encode()},
            ["../../x.xml", "leaves the project's directory"]),
        _bt("missing-include", kind, {"My.btproj": LIGHTS_PROJ.replace("{inc}", "nope.xml").encode()},
            ["My.btproj", "bt-project-unreadable"]),
        _bt("unknown-node", kind, {"My.btproj": LIGHTS_PROJ.replace("{inc}", "lights.xml").encode(),
                                   "lights.xml": UNKNOWN_NODE.encode()}, ["unknown node <LaunchRockets>"]),
        _bt("no-safety-tree", kind, {"My.btproj": LIGHTS_PROJ.replace("{inc}", "shutdown.xml").encode(),
                                     "shutdown.xml": SHUTDOWN_XML.encode()}, ["'Safety' is missing"]),
        _bt("malformed", kind, {"My.btproj": b"<root BTCPP_format='4'><include path='a.xml'></root>"},
            ["My.btproj", "not readable XML"]),
    ]
CASES.append(Case("push-bt-not-btproj", ["config", "push", "{tmp}/lights.xml", "--as", "bt-lights", "-r",
                                         "panther-01", "--yes"], ["lights.xml", "by its .btproj file"],
                  files={"lights.xml": LIGHTS_XML.encode()}))
CASES.append(_bt("lights-as-safety", "bt-safety", {"My.btproj": LIGHTS_PROJ.replace("{inc}", "lights.xml").encode(),
                                                   "lights.xml": LIGHTS_XML.encode()},
                 ["a project for bt-safety needs", "missing: Safety, Shutdown"]))
CASES.append(_bt("safety-as-lights", "bt-lights", {"My.btproj": SAFETY_PROJ.encode(), "safety.xml": SAFETY_XML.encode(),
                                                   "shutdown.xml": SHUTDOWN_XML.encode()},
                 ["a project for bt-lights needs", "missing: Lights"]))
CASES.append(_bt("no-shutdown-tree", "bt-safety", {"My.btproj": LIGHTS_PROJ.replace("{inc}", "safety.xml").encode(),
                                                   "safety.xml": SAFETY_XML.encode()}, ["'Shutdown' is missing"]))

# ------------------------------------------------------------------ shutdown hosts add/remove (finding 8)
INVALID_EXISTING = b"hosts:\n  - ip: 10.15.20.3\n    port: 99999\n"
CASES += [
    Case("hosts-add-robot-keeps-invalid", ["shutdown", "hosts", "add", "-r", "panther-03", "--ip", "10.15.20.9",
                                           "--http", "--yes"],
         ["shutdown_hosts.yaml", "hosts[0].port", "99999 is not a TCP port"], files={HOSTS_TREE: INVALID_EXISTING}),
    Case("hosts-add-robot-keeps-injection", ["shutdown", "hosts", "add", "-r", "panther-03", "--ip", "10.15.20.9",
                                             "--http", "--yes"],
         ["hosts[0].ip", "'10.15.20.3;reboot' is not an IP"],
         files={HOSTS_TREE: b"hosts:\n  - ip: '10.15.20.3;reboot'\n    port: 3003\n"}),
    Case("hosts-remove-robot-keeps-invalid", ["shutdown", "hosts", "remove", "-r", "panther-03", "--ip",
                                              "10.15.20.4", "--yes"],
         ["hosts[0].port", "99999"],
         files={HOSTS_TREE: INVALID_EXISTING + b"  - ip: 10.15.20.4\n    port: 3003\n"}),
    Case("hosts-add-robot-not-yaml", ["shutdown", "hosts", "add", "-r", "panther-03", "--ip", "10.15.20.9",
                                      "--http", "--yes"],
         ["/home/husarion/config/husarion_ugv_manager/config/shutdown_hosts.yaml", "not valid YAML"],
         files={HOSTS_TREE: b"hosts: [\n  - ip: {\n"}),
    Case("hosts-add-local-keeps-invalid", ["shutdown", "hosts", "add", "{tmp}/hosts.yaml", "--ip", "10.15.20.9",
                                           "--user", "pi", "--yes"],
         ["hosts.yaml", "hosts[0].port", "99999 is not a TCP port"],
         files={"hosts.yaml": b"hosts:\n  - ip: 10.15.20.3\n    username: husarion\n    port: 99999\n"}),
    Case("hosts-remove-local-keeps-invalid", ["shutdown", "hosts", "remove", "{tmp}/hosts.yaml", "--ip",
                                              "10.15.20.4", "--yes"],
         ["hosts.yaml", "hosts[0].username"],
         files={"hosts.yaml": b"hosts:\n  - ip: 10.15.20.3\n    username: 'a b'\n  - ip: 10.15.20.4\n"
                b"    username: pi\n"}),
    Case("hosts-add-ip-injection", ["shutdown", "hosts", "add", "-r", "panther-01", "--ip", "10.0.0.1;reboot",
                                    "--user", "pi", "--yes"], ["10.0.0.1;reboot"]),
    Case("hosts-add-port", ["shutdown", "hosts", "add", "-r", "panther-01", "--ip", "10.0.0.1", "--user", "pi",
                            "--port", "70000", "--yes"], ["70000"]),
    Case("hosts-add-user-injection", ["shutdown", "hosts", "add", "-r", "panther-01", "--ip", "10.0.0.1",
                                      "--user", "pi;reboot", "--yes"], ["pi;reboot"]),
    Case("hosts-add-command-newline", ["shutdown", "hosts", "add", "-r", "panther-01", "--ip", "10.0.0.1",
                                       "--user", "pi", "--command", "poweroff\nrm -rf /", "--yes"],
         ["host.command", "one-line command"]),
]

# ------------------------------------------------------------------ confinement and messages (findings 2, 6)
DEMO_INV = """version: 1
robots:
  panther-01:
    transport: local
    root: {demo}/robots/panther-01
    compose_file: {compose}
"""
for cid, compose, named in (("dotdot", "~/../../../x/compose.yaml", "~/../../../x/compose.yaml"),
                            ("dotdot-abs", "/home/husarion/../../etc/compose.yaml", "holds '..'"),
                            ("relative", "compose.yaml", "must be absolute or start with ~/"),
                            ("tab", "~/comp\\tose.yaml", "control character")):
    CASES.append(Case(f"compose-file-{cid}", ["config", "set", "wheel_type", "WH02", "-r", "panther-01", "--yes"],
                      ["compose_file", named], inventory=DEMO_INV.replace("{compose}", f'"{compose}"')))
for cid, to in (("dotdot", "../../../etc"), ("slash", "2026/x"), ("space", "a b")):
    CASES.append(Case(f"rollback-to-{cid}", ["config", "rollback", "--to", to, "-r", "panther-01", "--yes"],
                      ["backup id", to]))
CASES.append(Case("log-level-on-2.2", ["config", "set", "log_level", "LOUD", "-r", "panther-03", "--yes"],
                  ["log_level='LOUD' is not an allowed value", "DEBUG"]))


# ------------------------------------------------------------------ manager deploy and apply carry kinds too
for cid, hosts, named in (("ip", b"hosts:\n  - ip: '10.15.20.3;reboot'\n    port: 3003\n", "'10.15.20.3;reboot'"),
                          ("port", INVALID_EXISTING, "99999 is not a TCP port"),
                          ("ssh-entry", b"hosts:\n  - ip: 10.15.20.3\n    username: husarion\n", "over HTTP")):
    CASES.append(Case(f"manager-deploy-hosts-{cid}", ["manager", "deploy", "-r", "panther-03", "--yes"],
                      ["shutdown_hosts.yaml", named], files={HOSTS_TREE: hosts}))
APPLY_INV = """version: 1
robots:
  panther-01:
    transport: local
    root: {demo}/robots/panther-01
    desired:
      controller:
        linear.x.{key}: {value}
"""
for key, value, named in (("max_velocity", "fast", "max_velocity='fast' is not a number"),
                          ("max_velocity", "9.0", "exceeds the WH01 limit of 2.0"),
                          ("has_velocity_limits", "maybe", "has_velocity_limits='maybe' is not a boolean"),
                          ("max_speed", "1.0", "unknown controller limit")):
    CASES.append(Case(f"apply-controller-{key}-{value}", ["apply", "-r", "panther-01", "--yes"], [named],
                      inventory=APPLY_INV.replace("{key}", key).replace("{value}", value)))

# an image path that names a local file which is not an image: it is not sent to the robot
NOT_IMAGE = USER_ANIM.format(**{**GOOD, "image": "{tmp}/keys/id_rsa.png"})
for cmd in (["config", "push", "{tmp}/anims.yaml", "--as", "user-animations"], ["lights", "deploy", "{tmp}/anims.yaml"]):
    CASES.append(Case(f"{cmd[0]}-{cmd[1]}-image-not-an-image", [*cmd, "-r", "panther-01", "--yes"],
                      ["anims.yaml", "id_rsa.png is not a PNG, JPEG or GIF file"],
                      files={"anims.yaml": NOT_IMAGE, "keys/id_rsa.png": b"-----BEGIN OPENSSH PRIVATE KEY-----\n"}))


@pytest.mark.parametrize("case", CASES, ids=str)
def test_refused(case: Case, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                 monkeypatch: pytest.MonkeyPatch) -> None:
    err = check_refused(case, tmp_path, capsys, monkeypatch)
    assert "nothing" in err or "refused" in err or "error" in err.lower()  # click's "Error: Invalid value for"


def test_the_corpus_is_large_enough() -> None:
    assert len(CASES) >= 100
    assert len({c.id for c in CASES}) == len(CASES)
