"""Bad-input corpus, issue 23 items 5, 9 and 10: ROS names (namespaces, topics, services) by
rcl's rules in every command and file that takes one, launch-argument paths (characters, '..',
mounts), and chained shutdown commands. Each case: exit 2, the value named with what is
allowed, no traceback, every file of the demo fleet byte-identical.

Robots of the demo fleet: panther-01 runs panther_ros 2.1.1 (no /config volume), panther-02
2.0.4, panther-03 husarion_ugv 2.2.2 (the config tree mounted at /config).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.badinput.harness import Case, check_refused

TEMPLATES = Path(__file__).resolve().parents[2] / "templates"
COMPOSE_211 = (TEMPLATES / "compose/panther-2.1.1.yaml").read_text()
COMPOSE_01 = "demo/robots/panther-01/home/husarion/compose.yaml"
R1 = ["-r", "panther-01", "--yes"]
R3 = ["-r", "panther-03", "--yes"]
LOCAL_01 = "version: 1\nrobots:\n  r1:\n    transport: local\n    root: {demo}/robots/panther-01\n"
LOCAL_03 = "version: 1\nrobots:\n  r3:\n    transport: local\n    root: {demo}/robots/panther-03\n"
NS_RULES = "ASCII letters, digits, '_' and '/'"


def _compose_01(old: str, new: str) -> dict[str, str | bytes]:
    """panther-01's compose.yaml with one change (bytes: the harness leaves its braces alone)."""
    assert old in COMPOSE_211, old
    return {COMPOSE_01: COMPOSE_211.replace(old, new, 1).encode()}


# ------------------------------------------------------------------ namespaces (item 5)
NAMESPACES = [
    Case("ns-set-dash", ["config", "set", "namespace", "e-stop", *R1], ["namespace='e-stop'", "'-' is not allowed",
                                                                          NS_RULES]),
    Case("ns-set-dash-forced", ["config", "set", "namespace", "e-stop", *R1, "--force"],
         ["namespace='e-stop'", "'-' is not allowed", "--force does not write it"]),
    Case("ns-set-digit-forced", ["config", "set", "namespace", "fleet/2nd", *R3, "--force"],
         ["namespace='fleet/2nd'", "the token '2nd' starts with a digit"]),
    Case("ns-set-double-slash-forced", ["config", "set", "namespace", "fleet//a", *R1, "--force"],
         ["'fleet//a'", "'//'"]),
    Case("ns-set-tilde-forced", ["config", "set", "namespace", "~/x", *R1, "--force"],
         ["namespace='~/x'", "'~' is not allowed in a namespace"]),
    Case("ns-set-everywhere-forced", ["config", "set", "namespace", "robot-7", *R3, "--everywhere", "--force"],
         ["namespace='robot-7'", "'-' is not allowed"]),
    Case("ns-apply-desired-forced", ["apply", "--all", "--yes", "--force"], ["namespace='e-stop'", "'-'"],
         inventory=LOCAL_01 + "    desired: {{launch_args: {{namespace: e-stop}}}}\n"),
    Case("ns-inventory", ["inventory", "validate"], ["namespace", "'e-stop'", "'-' is not allowed"],
         inventory=LOCAL_01 + "    namespace: e-stop\n"),
    Case("ns-inventory-global", ["inventory", "validate"], ["namespace", "leave namespace out"],
         inventory=LOCAL_01 + "    namespace: /\n"),
    Case("ns-gps-option", ["gps", "enable", "--namespace", "e-stop", *R1], ["--namespace 'e-stop'", "'-'"]),
    Case("ns-gps-option-tokens", ["gps", "enable", "--namespace", "fleet/panther", *R1],
         ["--namespace 'fleet/panther'", "one namespace token"]),
    Case("ns-gps-desired", ["apply", "--all", "--yes"], ["'2robot'", "starts with a digit"],
         inventory=LOCAL_01 + "    desired: {{gps: {{enabled: true, namespace: 2robot}}}}\n"),
    Case("ns-gps-robot", ["gps", "enable", *R1], ["the robot's namespace 'e-stop'", "'-'", "--namespace"],
         files=_compose_01("ROBOT_NAMESPACE=panther", "ROBOT_NAMESPACE=e-stop")),
    Case("ns-webui-set", ["webui", "set", "ros.namespace=e-stop", *R1], ["ros.namespace='e-stop'", "'-'"]),
    Case("ns-webui-set-digit", ["webui", "set", "ros.namespace=2robot", *R1], ["ros.namespace='2robot'",
                                                                              "starts with a digit"]),
    Case("ns-webui-desired", ["config", "diff", "--all"], ["desired.webui", "'e-stop'", "'-' is not allowed"],
         inventory=LOCAL_01 + "    desired: {{webui: {{namespace: e-stop}}}}\n"),
]
# the whole compose file is checked, namespaces no command changed included: every command that writes it
BAD_ENV = _compose_01("ROBOT_NAMESPACE=panther", "ROBOT_NAMESPACE=e-stop")
BAD_GAMEPAD = _compose_01(' namespace:=panther"', ' namespace:=2panther"')  # inside the gamepad's bash -c
WRITES_COMPOSE = {
    "config-set": ["config", "set", "wheel_type", "WH02", *R1],
    "config-push": ["config", "push", "{tmp}/WH01_controller.yaml", "--as", "controller", *R1],
    "config-set-controller": ["config", "set", "controller.linear.x.max_velocity", "1.5", *R1],
    "driver-update": ["driver", "update", "humble-2.1.2-20241125", *R1],
}
CONTROLLER = (TEMPLATES / "config/panther-2.1/panther_controller/config/WH01_controller.yaml").read_bytes()
for cid, args in WRITES_COMPOSE.items():
    NAMESPACES.append(Case(f"ns-compose-env-{cid}", args, ["compose.yaml", "environment.ROBOT_NAMESPACE='e-stop'",
                                                             "'-' is not allowed"],
                           files={**BAD_ENV, "WH01_controller.yaml": CONTROLLER}))
    NAMESPACES.append(Case(f"ns-compose-gamepad-{cid}", args,
                           ["compose.yaml", "services.gamepad_controller.command: namespace:='2panther'",
                            "starts with a digit"], files={**BAD_GAMEPAD, "WH01_controller.yaml": CONTROLLER}))

# a BT project's service_name ports are ROS service names too (bt validate and config push --as bt-*)
BT = TEMPLATES / "behavior_trees"
LIGHTS_BAD = (BT / "lights.xml").read_text().replace('service_name="lights/set_animation"',
                                                     'service_name="lights/set-animation"', 1)
SAFETY_BAD = (BT / "safety.xml").read_text().replace('service_name="hardware/e_stop_trigger"',
                                                     'service_name="hardware/e_stop trigger"', 1)
assert "set-animation" in LIGHTS_BAD and "e_stop trigger" in SAFETY_BAD
BT_LIGHTS = {"proj/PantherLightsBT.btproj": (BT / "PantherLightsBT.btproj").read_bytes(),
             "proj/lights.xml": LIGHTS_BAD.encode()}
BT_SAFETY = {"proj/PantherSafetyBT.btproj": (BT / "PantherSafetyBT.btproj").read_bytes(),
             "proj/safety.xml": SAFETY_BAD.encode(), "proj/shutdown.xml": (BT / "shutdown.xml").read_bytes()}
LIGHTS_NAMED = ["<CallSetLedAnimationService> service_name='lights/set-animation'", "'-' is not allowed"]
SAFETY_NAMED = ["service_name='hardware/e_stop trigger'", "' ' is not allowed"]
NAMESPACES += [
    # bt validate lists its findings on stdout (tests/parse/test_ros_names.py reads them); stderr has the verdict
    Case("bt-validate-lights-service", ["bt", "validate", "{tmp}/proj/PantherLightsBT.btproj"],
         ["PantherLightsBT.btproj: BT project refused (1 error,"], files=BT_LIGHTS),
    Case("bt-validate-safety-service", ["bt", "validate", "{tmp}/proj/PantherSafetyBT.btproj"],
         ["PantherSafetyBT.btproj: BT project refused (1 error,"], files=BT_SAFETY),
    Case("bt-push-lights-service", ["config", "push", "{tmp}/proj/PantherLightsBT.btproj", "--as", "bt-lights", *R1],
         ["PantherLightsBT.btproj", *LIGHTS_NAMED], files=BT_LIGHTS),
    Case("bt-push-safety-service", ["config", "push", "{tmp}/proj/PantherSafetyBT.btproj", "--as", "bt-safety", *R3],
         ["PantherSafetyBT.btproj", *SAFETY_NAMED], files=BT_SAFETY),
]


# ------------------------------------------------------------------ launch-argument paths (item 9)
COMPOSE_222 = (TEMPLATES / "compose/husarion-ugv-2.2.2.yaml").read_text()
COMPOSE_03 = "demo/robots/panther-03/home/husarion/compose.yaml"
PATH_CHARS = "ASCII letters, digits, '_', '.', '+', '-' and '/'"
MOUNTS_03 = "/run/husarion/robot_config.env, /run/husarion/robot_config.yaml, /run/dbus/system_bus_socket, " \
            "/sys/bus/iio/devices, /root/.ssh/id_rsa, /config"
PATHS: list[Case] = []
for cid, value, bad in (("semicolon", "/config/a;reboot.yaml", "';'"), ("space", "/config/my wheel.yaml", "' '"),
                        ("subst", "/config/$(id).yaml", "'$'"), ("backtick", "/config/`id`.yaml", "'`'"),
                        ("and", "/config/a&&b.yaml", "'&'"), ("pipe", "/config/a|b.yaml", "'|'"),
                        ("quote", "/config/it's.yaml", '"\'"'), ("unicode", "/config/wheel\u00e9.yaml", "'\u00e9'"),
                        ("tilde", "/config/~wheel.yaml", "'~'"), ("colon", "/config/a:b.yaml", "':'"),
                        ("find-space", "$(find panther_description)/config/my wheel.yaml", "' '")):
    for arg, robot in (("wheel_config_path", R1), ("controller_config_path", R3)):
        PATHS.append(Case(f"path-{cid}-{arg}", ["config", "set", arg, value, *robot], [arg, bad, PATH_CHARS]))
    PATHS.append(Case(f"path-{cid}-forced", ["config", "set", "components_config_path", value, *R3, "--force"],
                      ["components_config_path", bad, PATH_CHARS]))
PATHS += [
    Case("path-dotdot", ["config", "set", "controller_config_path", "/config/../root/.ssh/id_rsa", *R3, "--force"],
         ["controller_config_path='/config/../root/.ssh/id_rsa' holds '..'"]),
    Case("path-apply-semicolon", ["apply", "--all", "--yes"], ["wheel_config_path", "';'", PATH_CHARS],
         inventory=LOCAL_03 + "    desired: {{launch_args: {{wheel_config_path: '/config/a;b.yaml'}}}}\n"),
    # a path no volume mounts and not in the image: named with the mounts
    Case("path-unmounted-03", ["config", "set", "controller_config_path", "/home/husarion/c.yaml", *R3],
         ["controller_config_path=/home/husarion/c.yaml is neither inside a volume", MOUNTS_03,
          "the driver cannot open it"]),
    Case("path-unmounted-01", ["config", "set", "wheel_config_path", "/config/WH01.yaml", *R1],
         ["wheel_config_path=/config/WH01.yaml is neither inside a volume", "/root/.ssh/id_rsa",
          "/run/husarion/panther_config.env", "/ros2_ws, /opt/ros"]),
    Case("path-unmounted-dir", ["config", "set", "common_dir_path", "/etc/husarion", *R3],
         ["common_dir_path=/etc/husarion is neither inside a volume", MOUNTS_03]),
    Case("path-unmounted-apply", ["apply", "--all", "--yes"], ["led_config_file=/config/leds.yaml is neither inside"],
         inventory=LOCAL_01 + "    desired: {{launch_args: {{led_config_file: /config/leds.yaml}}}}\n"),
]
# the whole command is checked: a path already in it that no volume mounts refuses an unrelated change
UNMOUNTED_03 = {COMPOSE_03: COMPOSE_222.replace("launch_gamepad:=true",
                                                "launch_gamepad:=true controller_config_path:=/tmp/c.yaml", 1).encode()}
for cid, args in (("config-set", ["config", "set", "log_level", "DEBUG", *R3]),
                  ("config-set-bool", ["config", "set", "use_ekf", "false", *R3]),
                  ("gps-enable", ["gps", "enable", "--port", "5001", *R3])):
    PATHS.append(Case(f"path-kept-unmounted-{cid}", args,
                      ["controller_config_path=/tmp/c.yaml is neither inside a volume", MOUNTS_03],
                      files=UNMOUNTED_03))


# ------------------------------------------------------------------ shutdown hosts commands (item 10)
# chaining (';', '&&', '||', '|', '&') is a warning (tests/shutdown/test_shutdown_cli.py): the host's login shell
# runs the chain; a control character other than a newline was let through and is refused now
HOSTS: list[Case] = []
ONE_LINE = "must be a one-line command of printable text"
for cid, char, shown in (("cr", "\r", "U+000D"), ("escape", "\x1b", "U+001B"), ("vtab", "\x0b", "U+000B"),
                         ("line-separator", "\u2028", "U+2028"), ("zero-width", "\u200b", "U+200B")):
    text = f'hosts:\n  - ip: 192.0.2.5\n    username: pi\n    command: "sudo shutdown now{char.encode("unicode_escape").decode()}"\n'
    files: dict[str, str | bytes] = {"h.yaml": text.encode()}
    HOSTS += [
        Case(f"hosts-validate-{cid}", ["shutdown", "hosts", "validate", "{tmp}/h.yaml"],
             ["h.yaml", "hosts[0].command", ONE_LINE, shown], files=files),
        Case(f"hosts-push-{cid}", ["config", "push", "{tmp}/h.yaml", "--as", "shutdown-hosts", *R1],
             ["h.yaml", "hosts[0].command", ONE_LINE, shown], files=files),
        Case(f"hosts-run-{cid}", ["shutdown", "--hosts", "{tmp}/h.yaml", "--yes"], ["hosts[0].command", shown],
             files=files),
        Case(f"hosts-add-local-keeps-{cid}", ["shutdown", "hosts", "add", "{tmp}/h.yaml", "--ip", "10.15.20.9",
                                              "--user", "pi", "--yes"], ["h.yaml", "hosts[0].command", shown],
             files=files),
        Case(f"hosts-add-option-{cid}", ["shutdown", "hosts", "add", "-r", "panther-01", "--ip", "10.15.20.9",
                                         "--user", "pi", "--command", f"sudo shutdown now{char}", "--yes"],
             ["host.command", ONE_LINE, shown]),
    ]


CASES = NAMESPACES + PATHS + HOSTS


@pytest.mark.parametrize("case", CASES, ids=str)
def test_refused(case: Case, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                 monkeypatch: pytest.MonkeyPatch) -> None:
    check_refused(case, tmp_path, capsys, monkeypatch)
