"""The bad-input corpus: inventory values, selectors, launch argument values, injection
strings in every argument that reaches a robot, lights preview / manager simulation /
scenario inputs and stack versions. Each case: exit 2, the thing named, no traceback, every
file (demo robots, backups, history, the operator's files) byte-identical.
"""

from __future__ import annotations

import gzip
import hashlib
import json
from pathlib import Path

import pytest

from tests.badinput.harness import Case, check_refused

R1 = ["-r", "panther-01", "--yes"]


def esc(text: str) -> str:
    """``text`` as a case's file or inventory content (the harness fills in {demo} and {tmp})."""
    return text.replace("{", "{{").replace("}", "}}")


INJECT = "$(touch /tmp/pwned)"


def inventory(robot: str = "host: panther-07", top: str = "", groups: str = "groups: {field: {}}") -> str:
    """An inventory with one SSH robot (never contacted: the load refuses first)."""
    return esc(f"version: 1\n{top}\n{groups}\nrobots:\n  r1: {{{robot}}}\n")


def inv_case(cid: str, robot: str, names: list[str], *, top: str = "", groups: str = "groups: {field: {}}",
             command: tuple[str, ...] = ("inventory", "validate")) -> Case:
    return Case(cid, list(command), names, inventory=inventory(robot, top, groups))


INVENTORY = [
    inv_case("inv-host-option", 'host: "-oProxyCommand=touch x"', ["robots.r1.host", "-oProxyCommand", "'-'"]),
    inv_case("inv-host-semicolon", 'host: "panther-07;touch x"', ["robots.r1.host", ";"]),
    inv_case("inv-host-space", 'host: "panther 07"', ["robots.r1.host", "whitespace"]),
    inv_case("inv-host-slash", "host: panther/07", ["robots.r1.host", "'/'"]),
    inv_case("inv-host-subst", 'host: "$(id)"', ["robots.r1.host", "$(id)"]),
    inv_case("inv-host-backtick", 'host: "`id`"', ["robots.r1.host", "`"]),
    inv_case("inv-host-newline", 'host: "panther-07\\nProxyCommand x"', ["robots.r1.host"]),
    inv_case("inv-host-pipe", 'host: "a|b"', ["robots.r1.host", "|"]),
    inv_case("inv-host-bad-ipv4", "host: 10.15.20.256", ["robots.r1.host", "10.15.20.256"]),
    inv_case("inv-host-label-dash", "host: -panther", ["robots.r1.host", "-panther"]),
    inv_case("inv-host-label-end-dash", "host: panther-.lan", ["robots.r1.host", "panther-.lan"]),
    inv_case("inv-host-empty", 'host: ""', ["robots.r1.host", "non-empty"]),
    inv_case("inv-host-number", "host: 12", ["robots.r1.host"]),
    inv_case("inv-jump-option", 'host: panther-07, jump: "-J evil"', ["robots.r1.jump", "-J evil"]),
    inv_case("inv-jump-shell", 'host: panther-07, jump: "op@gw;id"', ["robots.r1.jump", ";"]),
    inv_case("inv-jump-space", 'host: panther-07, jump: "op@gw 22"', ["robots.r1.jump", "whitespace"]),
    inv_case("inv-jump-port", 'host: panther-07, jump: "op@gw:70000"', ["robots.r1.jump", "70000"]),
    inv_case("inv-jump-user", 'host: panther-07, jump: "Op$@gw"', ["robots.r1.jump", "Op$"]),
    inv_case("inv-jump-slash", 'host: panther-07, jump: "op@gw/x"', ["robots.r1.jump", "'/'"]),
    inv_case("inv-jump-ipv6-trailing", 'host: panther-07, jump: "op@[fd00::1]x"', ["robots.r1.jump", "']'"]),
    inv_case("inv-jump-ipv6-bad", 'host: panther-07, jump: "op@[fd00::zz]:22"', ["robots.r1.jump", "IPv6"]),
    inv_case("inv-timeout-nan", "host: panther-07, connect_timeout: .nan", ["robots.r1.connect_timeout", "finite"]),
    inv_case("inv-timeout-inf", "host: panther-07, connect_timeout: .inf", ["robots.r1.connect_timeout", "finite"]),
    inv_case("inv-timeout-zero", "host: panther-07, connect_timeout: 0", ["robots.r1.connect_timeout", "> 0"]),
    inv_case("inv-timeout-negative", "host: panther-07, connect_timeout: -5", ["robots.r1.connect_timeout"]),
    inv_case("inv-timeout-text", "host: panther-07, connect_timeout: soon", ["robots.r1.connect_timeout", "soon"]),
    inv_case("inv-timeout-bool", "host: panther-07, connect_timeout: true", ["robots.r1.connect_timeout"]),
    inv_case("inv-command-timeout-nan", "host: panther-07", ["settings.command_timeout", "finite"],
             top="settings: {command_timeout: .nan}"),
    inv_case("inv-defaults-timeout-inf", "host: panther-07", ["defaults.connect_timeout"],
             top="defaults: {connect_timeout: .inf}"),
    inv_case("inv-port", "host: panther-07, port: 70000", ["robots.r1.port", "70000"]),
    inv_case("inv-user", 'host: panther-07, user: "root;id"', ["robots.r1.user", "root;id"]),
    inv_case("inv-stack-future", 'host: panther-07, stack: "9.9.9"', ["robots.r1.stack", "9.9.9"]),
    inv_case("inv-stack-text", "host: panther-07, stack: latest", ["robots.r1.stack", "latest"]),
    inv_case("inv-group-typo", "host: panther-07, groups: [feild]", ["robots.r1.groups", "feild", "did you", "'field'"]),
    inv_case("inv-group-undeclared", "host: panther-07, groups: [lab]", ["robots.r1.groups", "'lab'", "declare"]),
    inv_case("inv-group-typo-status", "host: panther-07, groups: [feild]", ["feild"], command=("status", "--all")),
    Case("inv-recursive-alias", ["inventory", "validate"], ["inventory.yaml", "recursive"],
         inventory=esc("version: 1\nrobots:\n  r1: &r {host: panther-07, vars: {self: *r}}\n")),
    Case("inv-recursive-list", ["status", "--all"], ["inventory.yaml", "recursive"],
         inventory=esc("version: 1\nx: &a [*a]\nrobots:\n  r1: {host: panther-07}\n")),
    Case("inv-alias-bomb", ["inventory", "validate"], ["inventory.yaml", "aliases expanded"],
         inventory=esc("version: 1\n" + "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n"
                       + "".join(f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 10)}]\n" for i in range(1, 9))
                       + "robots:\n  r1: {host: panther-07}\n")),
    Case("inv-deep-nesting", ["inventory", "validate"], ["inventory.yaml", "nested too deeply"],
         inventory=esc("version: 1\nrobots:\n  r1: {host: panther-07, vars: {x: " + "[" * 3000 + "]" * 3000
                       + "}}\n")),
    Case("inv-merge-scalar", ["inventory", "validate"], ["inventory.yaml", "merge key"],
         inventory=esc("version: 1\nrobots:\n  r1: {<<: 5, host: panther-07}\n")),
]

SELECTORS = [
    Case("sel-unknown-robot", ["config", "set", "wheel_type", "WH02", "-r", "panther-99", "--yes"], ["panther-99"]),
    Case("sel-unknown-group", ["config", "set", "wheel_type", "WH02", "-g", "warehous", "--yes"],
         ["'warehous'", "did you mean 'warehouse'"]),
    Case("sel-robot-typo", ["status", "-r", "panther-1"], ["'panther-1'", "did you mean 'panther-01'"]),
    Case("sel-injection-robot", ["status", "-r", INJECT], [INJECT]),
    Case("sel-injection-group", ["status", "-g", "x;id"], ["x;id"]),
    Case("sel-empty-glob", ["driver", "restart", "-r", "", "--yes"], ["''"]),
    Case("sel-none-on-fleet", ["config", "set", "wheel_type", "WH02", "--yes"], ["--robot", "panther-01"]),
    Case("sel-trust-unknown", ["trust", "panther-99;id", "--yes"], ["panther-99;id"]),
    Case("sel-show-unknown", ["inventory", "show", "nobody"], ["nobody"]),
    Case("sel-via-unknown", ["shutdown", "--hosts", "{tmp}/hosts.yaml", "--via", INJECT, "--dry-run"], [INJECT],
         files={"hosts.yaml": "hosts:\n  - ip: 10.15.20.3\n    username: husarion\n"}),
]

ROOT = Path(__file__).resolve().parents[2]
COMPOSE_01 = "demo/robots/panther-01/home/husarion/compose.yaml"
BASH_C_DRIVER = (ROOT / "templates/compose/panther-2.1.1.yaml").read_text().replace(
    "    command: ros2 launch panther_bringup bringup.launch.py\n",
    '    command: bash -c "ros2 launch panther_bringup bringup.launch.py namespace:=panther"\n').encode()
"""panther-01's compose.yaml with the driver run as the gamepad is in husarion/panther-docker's files
(`bash -c "ros2 launch ..."`): a value its double quotes would change cannot be written in it."""
assert b"bash -c \"ros2 launch panther_bringup" in BASH_C_DRIVER


def bash_c_case(cid: str, args: list[str], names: list[str], inventory: str | None = None) -> Case:
    return Case(cid, args, names, files={COMPOSE_01: BASH_C_DRIVER}, inventory=inventory)


LAUNCH_ARGS = [
    Case("arg-newline", ["config", "set", "wheel_type", "WH02\nrm -rf ~", *R1], ["wheel_type", "'\\n'"]),
    Case("arg-newline-forced", ["config", "set", "wheel_type", "WH02\nx", *R1, "--force"], ["wheel_type", "'\\n'"]),
    Case("arg-carriage-return", ["config", "set", "namespace", "panther\rx", *R1], ["namespace", "'\\r'"]),
    Case("arg-escape", ["config", "set", "namespace", "a\x1b[31mb", *R1], ["namespace", "U+001B"]),
    Case("arg-tab", ["config", "set", "launch_args.namespace", "a\tb", *R1, "--force"], ["U+0009"]),
    Case("arg-nul-like", ["config", "set", "namespace", "a\x7fb", *R1], ["namespace", "U+007F"]),
    Case("arg-line-separator", ["config", "set", "namespace", "a\u2028b", *R1], ["namespace", "U+2028"]),
    Case("arg-key-newline-forced", ["config", "set", "no_such\nx", "1", *R1, "--force"], ["no_such\\nx"]),
    Case("arg-key-shell-forced", ["config", "set", "a;id", "1", *R1, "--force"], ["a;id"]),
    Case("arg-injection-value", ["config", "set", "wheel_type", INJECT, *R1], ["wheel_type", INJECT]),
    Case("arg-unknown-key", ["config", "set", "wheel_typ", "WH02", *R1], ["wheel_typ", "wheel_type"]),
    # issue 24 finding 8: WH05 reaches the robot's plan (a 2.2 choice), refused there on a Panther (its
    # ROBOT_MODEL_NAME), and on panther_ros as no choice of the stack
    Case("arg-wh05-on-a-panther-22", ["config", "set", "wheel_type", "WH05", "-r", "panther-03", "--yes"],
         ["WH05", "robot_model is panther"]),
    Case("arg-wh05-on-211", ["config", "set", "wheel_type", "WH05", *R1], ["WH05", "WH01, WH02, WH04, custom"]),
    Case("arg-get-injection-key", ["config", "get", INJECT, "-r", "panther-01"], [INJECT]),
    Case("arg-unset-injection-key", ["config", "unset", "a;id", *R1], ["a;id"]),
    Case("arg-controller-key", ["config", "get", "controller.linear.q.max_velocity", "-r", "panther-01"],
         ["controller.linear.q.max_velocity"]),
    bash_c_case("arg-bash-c-dollar", ["config", "set", "components_config_path", "$(find panther_description)/x.yaml",
                                      *R1],
                ["compose.yaml:38", "components_config_path", "'$(find panther_description)/x.yaml'",
                 "double-quoted bash -c script", "a dollar sign ($)"]),
    # a path argument meets the config-path rule first (issue 23 item 9); the bash -c quoting check
    # behind it has its own tests (tests/robot/test_launchcmd_diff.py)
    bash_c_case("arg-bash-c-double-quote", ["config", "set", "battery_config_path", '/config/a"b.yaml', *R1],
                ["battery_config_path", "'/config/a\"b.yaml'", "not a character of a config path"]),
    bash_c_case("arg-bash-c-backslash", ["config", "set", "battery_config_path", "/config/a\\b.yaml", *R1],
                ["battery_config_path", "'/config/a\\\\b.yaml'", "not a character of a config path"]),
    bash_c_case("arg-bash-c-backquote", ["config", "set", "battery_config_path", "/config/`id`.yaml", *R1],
                ["battery_config_path", "'/config/`id`.yaml'", "not a character of a config path"]),
    bash_c_case("arg-bash-c-apply", ["apply", "--all", "--yes"],
                ["components_config_path", "'$(find panther_description)/config/components.yaml'", "a dollar sign"],
                inventory="version: 1\nrobots:\n  r1:\n    transport: local\n    root: {demo}/robots/panther-01\n"
                "    desired: {{launch_args: {{components_config_path: "
                "\"$(find panther_description)/config/components.yaml\"}}}}\n"),
    Case("arg-apply-newline", ["apply", "--all", "--yes"], ["namespace", "'\\n'"],
         inventory="version: 1\nrobots:\n  r1:\n    transport: local\n    root: {demo}/robots/panther-01\n"
         "    desired: {{launch_args: {{namespace: \"a\\nb\"}}}}\n"),
]

REACHES_ROBOT = [
    Case("robot-rollback-id", ["config", "rollback", "--to", "../../etc", *R1], ["--to", "../../etc"]),
    Case("robot-rollback-injection", ["config", "rollback", "--to", INJECT, *R1], [INJECT]),
    Case("robot-driver-tag", ["driver", "update", "humble-2.1.1;id", *R1], ["humble-2.1.1;id"]),
    Case("robot-push-kind", ["config", "push", "{tmp}/c.yaml", "--as", INJECT, *R1], [INJECT],
         files={"c.yaml": "a: 1\n"}),
    Case("robot-pull-kind", ["config", "pull", "a;id", "-r", "panther-01"], ["a;id"]),
    Case("robot-pull-output", ["config", "pull", "controller", "-r", "panther-01", "--output", "{tmp}/no/dir/c.yaml"],
         ["--output"]),
    Case("robot-lights-param", ["lights", "test", "21", "--param", "0.5\nx", "-r", "panther-01"], ["--param"]),
    Case("robot-lights-id", ["lights", "test", "70000", "-r", "panther-01"], ["70000"]),
    Case("robot-hosts-add-ip", ["shutdown", "hosts", "add", "--ip", "10.15.20.3;id", "--user", "husarion", *R1],
         ["10.15.20.3;id", "IP address"]),
    Case("robot-hosts-add-ip-option", ["shutdown", "hosts", "add", "--ip", "-oProxyCommand=x", "--user", "husarion",
                                       *R1], ["-oProxyCommand=x"]),
    Case("robot-hosts-remove-ip", ["shutdown", "hosts", "remove", "--ip", INJECT, *R1], [INJECT]),
    Case("robot-manager-scenario", ["manager", "deploy", "--sim", "--scenario", INJECT, *R1], [INJECT]),
    Case("robot-manager-scenario-bad", ["manager", "deploy", "--sim", "--scenario", "{tmp}/s.yaml", *R1],
         ["s.yaml", "duration"], files={"s.yaml": "duration: .nan\n"}),
    Case("robot-logs-since", ["driver", "logs", "-r", "panther-01", "--since", "10m;id"], ["10m;id", "duration"]),
    Case("robot-setup-host", ["shutdown", "setup", "--host", INJECT, *R1], [INJECT]),
    Case("robot-setup-user", ["shutdown", "setup", "--host", "10.15.20.3", "--user", "root;id", *R1], ["root;id"]),
    Case("robot-hosts-add-user", ["shutdown", "hosts", "add", "--ip", "10.15.20.4", "--user", "a b", *R1], ["'a b'"]),
    Case("robot-hosts-add-command", ["shutdown", "hosts", "add", "--ip", "10.15.20.4", "--user", "husarion",
                                     "--command", "sudo shutdown now\nrm -rf ~", *R1], ["command"]),
    Case("robot-push-missing", ["config", "push", "{tmp}/none.yaml", "--as", "controller", *R1], ["none.yaml"]),
    Case("robot-lights-deploy-missing", ["lights", "deploy", "{tmp}/none.yaml", *R1], ["none.yaml"]),
    Case("robot-driver-update-jazzy", ["driver", "update", "humble-3.0.0-20250101", *R1], ["3.0.0"]),
    Case("robot-settle-nan", ["config", "set", "wheel_type", "WH02", *R1, "--settle", "nan"], ["--settle"]),
    Case("robot-max-fail-inf", ["config", "set", "wheel_type", "WH02", *R1, "--max-fail", "inf"], ["--max-fail"]),
    Case("robot-shutdown-identity", ["shutdown", "--hosts", "{tmp}/hosts.yaml", "--identity", "{tmp}/nokey",
                                     "--dry-run"], ["--identity", "nokey"],
         files={"hosts.yaml": "hosts:\n  - ip: 10.15.20.3\n    username: husarion\n"}),
]

SCENARIOS = [
    Case(f"scenario-{i}", ["manager", "run", "--sim", "--scenario", "{tmp}/s.yaml", "--duration", "5", "--json"],
         ["s.yaml", *names], files={"s.yaml": esc(text)})
    for i, (text, names) in enumerate([
        ("garbage: [", ["invalid YAML"]),
        ("5\n", ["expected a mapping"]),
        ("duration: abc\n", ["duration"]),
        ("duration: .nan\n", ["duration"]),
        ("duration: 0\n", ["duration"]),
        ("battery: 5\n", ["battery"]),
        ("battery: {capacity: abc}\n", ["battery"]),
        ("robot: {bat_temp: hot}\n", ["robot", "hot"]),
        ("robot: {status: WEIRD}\n", ["WEIRD"]),
        ("params: {cpu.temp.fan_on: hot}\n", ["cpu.temp.fan_on"]),
        ("shutdown_hosts: [{ip: 1.2.3.4, shutdown_delay: x}]\n", ["shutdown_delay"]),
        ("events: 5\n", ["events"]),
        ("events: [{at: .inf}]\n", ["events[0]", "at"]),
        ("events: [{at: 1, set: 5}]\n", ["events[0]", "set"]),
        ("events: [{at: 1, set: {charge: 5}}]\n", ["events[0]", "charge"]),
        ("events: [{at: 1, set: {health: nope}}]\n", ["events[0]", "nope"]),
        ("events: [{at: 1, press: [nope]}]\n", ["events[0]", "nope"]),
        ("events: [{at: 1, set: {bat_temp: [1]}}]\n", ["events[0]"]),
        ("unknown_key: 1\n", ["unknown_key"]),
    ])
] + [
    Case("scenario-missing", ["manager", "run", "--sim", "--scenario", "{tmp}/none.yaml"], ["none.yaml"]),
    Case("scenario-short-unknown", ["manager", "run", "--sim", "--scenario", "low_batery"], ["low_batery",
                                                                                             "low_battery"]),
    Case("scenario-no-sim", ["manager", "run", "--scenario", "low_battery"], ["--sim"]),
    Case("scenario-duration-nan", ["manager", "run", "--sim", "--duration", "nan"], ["--duration"]),
    Case("scenario-bt-alone", ["manager", "run", "--sim", "--lights-bt", "{tmp}/x.btproj"], ["--safety-bt"]),
]

PREVIEW_FILE = "animations:\n  - id: 21\n    name: MY\n    priority: 2\n    animation:\n      both:\n" \
    "        type: panther_lights::ImageAnimation\n        image: $(find panther_lights)/animations/strip01_red.png\n" \
    "        duration: 2\n"

LIGHTS = [
    Case("preview-invalid-yaml", ["lights", "preview", "{tmp}/a.yaml", "--id", "21", "--out", "{tmp}/a.gif"],
         ["a.yaml", "invalid YAML"], files={"a.yaml": "animations: [\n"}),
    Case("preview-missing", ["lights", "preview", "{tmp}/none.yaml", "--id", "21", "--out", "{tmp}/a.gif"],
         ["none.yaml"]),
    Case("preview-unknown-id", ["lights", "preview", "{tmp}/led.yaml", "--id", "99", "--out", "{tmp}/a.gif"],
         ["99"], files={"led.yaml": ""}),
    Case("preview-param-text", ["lights", "preview", "{tmp}/led.yaml", "--id", "9", "--param", "full",
                                "--out", "{tmp}/a.gif"], ["--param", "full"], files={"led.yaml": ""}),
    Case("preview-param-nan", ["lights", "preview", "{tmp}/led.yaml", "--id", "9", "--param", "nan",
                               "--out", "{tmp}/a.gif"], ["--param", "nan"], files={"led.yaml": ""}),
    Case("preview-param-range", ["lights", "preview", "{tmp}/led.yaml", "--id", "9", "--param", "5",
                                 "--out", "{tmp}/a.gif"], ["--param", "0 to 1"], files={"led.yaml": ""}),
    Case("preview-out-dir", ["lights", "preview", "{tmp}/led.yaml", "--id", "9", "--out", "{tmp}/nodir/a.gif"],
         ["--out", "nodir"], files={"led.yaml": ""}),
    Case("preview-out-not-gif", ["lights", "preview", "{tmp}/led.yaml", "--id", "9", "--out", "{tmp}/a.png"],
         ["--out", "a.png"], files={"led.yaml": ""}),
    Case("lights-validate-missing", ["lights", "validate", "{tmp}/none.yaml"], ["none.yaml"]),
    Case("bt-validate-missing", ["bt", "validate", "{tmp}/none.btproj"], ["none.btproj"]),
]

STACKS = [
    Case(f"stack-{name}", ["shutdown", "hosts", "validate", "{tmp}/hosts.yaml", "--stack", value], ["--stack", value],
         files={"hosts.yaml": "hosts:\n  - ip: 10.15.20.3\n    username: husarion\n"})
    for name, value in [("text", "abc"), ("future", "9.9.9"), ("ros1", "1.0.0"), ("short", "2.1"),
                        ("injection", "2.1.1;id"), ("line-2.4", "2.4.0"),
                        ("jazzy-unknown-patch", "2.3.3")]
] + [
    Case("stack-without-file", ["shutdown", "hosts", "validate", "-r", "panther-01", "--stack", "2.1.1"],
         ["--stack", "FILE"]),
]

BOMB = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n" + "".join(
    f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 10)}]\n" for i in range(1, 9))

ALIASES = [
    Case("alias-hosts-recursive", ["shutdown", "hosts", "validate", "{tmp}/h.yaml"], ["h.yaml", "recursive"],
         files={"h.yaml": esc("hosts: &h [{ip: *h}]\n")}),
    Case("alias-hosts-bomb", ["shutdown", "hosts", "validate", "{tmp}/h.yaml"], ["h.yaml", "aliases expanded"],
         files={"h.yaml": esc(BOMB + "hosts: *a8\n")}),
    Case("alias-hosts-add-bomb", ["shutdown", "hosts", "add", "{tmp}/h.yaml", "--ip", "10.15.20.4", "--user",
                                  "husarion", "--yes"], ["h.yaml", "aliases expanded"],
         files={"h.yaml": esc(BOMB + "hosts: *a8\n")}),
    Case("alias-scenario-recursive", ["manager", "run", "--sim", "--scenario", "{tmp}/s.yaml"], ["s.yaml"],
         files={"s.yaml": esc("robot: &r {bat_temp: 1, x: *r}\n")}),
    Case("alias-animations-recursive", ["lights", "validate", "{tmp}/a.yaml"], ["a.yaml"],
         files={"a.yaml": esc("animations: &a [{id: 21, name: *a}]\n")}),
]

LOCAL_01 = "version: 1\nrobots:\n  r1:\n    transport: local\n    root: {demo}/robots/panther-01\n"
WEBUI = [  # desired.webui: the inventory's values (when it loads), a DDS profile the User Computer lacks (at plan)
    Case("webui-desired-port", ["apply", "--all", "--yes"], ["desired.webui.port", "70000", "1 to 65535"],
         inventory=LOCAL_01 + "    desired: {{webui: {{port: 70000}}}}\n"),
    Case("webui-desired-namespace", ["config", "diff", "--all"], ["desired.webui.namespace", "bad ns", "a-z"],
         inventory=LOCAL_01 + "    desired: {{webui: {{namespace: bad ns}}}}\n"),
    Case("webui-desired-domain", ["apply", "--all", "--dry-run"], ["desired.webui.ros.domain-id", "300", "0 to 232"],
         inventory=LOCAL_01 + "    desired: {{webui: {{ros.domain-id: 300}}}}\n"),
    Case("webui-desired-unknown-key", ["apply", "--all", "--yes"], ["desired.webui.colour", "ros.namespace"],
         inventory=LOCAL_01 + "    desired: {{webui: {{colour: red}}}}\n"),
    Case("webui-desired-transport-no-profile", ["apply", "--all", "--yes"],
         ["desired.webui", "ros.transport='my-profile'", "no DDS profile", "--dds-file"],
         inventory=LOCAL_01 + "    desired: {{webui: {{transport: my-profile}}}}\n"),
    Case("webui-apply-transport-injection", ["apply", "--all", "--yes"], ["desired.webui.transport", INJECT],
         inventory=LOCAL_01 + "    desired: {{webui: {{transport: \"" + esc(INJECT) + "\"}}}}\n"),
    # husarion-snap-common@0.13.0: the namespace regex ^[a-z_][0-9a-z_]{0,19}$, zenoh refused, and a
    # DDS profile its check_xml_profile_type detects (declaration, <profiles>/<CycloneDDS> with xmlns)
    Case("webui-desired-namespace-hyphen", ["apply", "--all", "--dry-run"],
         ["desired.webui.namespace", "panther-01", "not starting with a digit"],
         inventory=LOCAL_01 + "    desired: {{webui: {{namespace: panther-01}}}}\n"),
    Case("webui-set-namespace-hyphen", ["webui", "set", "ros.namespace=panther-01", "--all", "--yes"],
         ["ros.namespace", "panther-01", "a-z, 0-9 and '_'"]),
    Case("webui-set-zenoh", ["webui", "set", "ros.transport=rmw_zenoh_cpp", "--all", "--yes"],
         ["ros.transport", "rmw_zenoh_cpp", "zenoh is refused"]),
    Case("webui-dds-file-dds-root", ["webui", "set", "--dds-file", "{tmp}/lab.xml", "--all", "--yes"],
         ["lab.xml", "<profiles>", "not <dds>"], files={"lab.xml": '<?xml version="1.0"?>\n<dds><profiles/></dds>\n'}),
    Case("webui-dds-file-no-declaration", ["webui", "set", "--dds-file", "{tmp}/lab.xml", "--all", "--yes"],
         ["lab.xml", "<?xml version"], files={"lab.xml": '<CycloneDDS xmlns="https://cdds.io/config"/>\n'}),
    Case("webui-dds-file-wrong-xmlns", ["webui", "set", "--dds-file", "{tmp}/lab.xml", "--all", "--yes"],
         ["lab.xml", "xmlns", "fastRTPS_Profiles"],
         files={"lab.xml": '<?xml version="1.0"?>\n<profiles xmlns="http://example.org/x"/>\n'}),
    Case("webui-dds-file-builtin-name", ["webui", "set", "--dds-file", "{tmp}/udp.xml", "--all", "--yes"],
         ["udp.xml", "snap's own transports"],
         files={"udp.xml": '<?xml version="1.0"?>\n<CycloneDDS xmlns="https://cdds.io/config"/>\n'}),
]


# ------------------------------------------------------------------ desired: blocks, checked whole when the inventory loads
DESIRED_COMMANDS = (("validate", ("inventory", "validate")), ("doctor", ("doctor", "--all")),
                    ("apply", ("apply", "--all", "--dry-run")), ("diff", ("config", "diff", "--all")))
"""Every command that reads the desired blocks refuses the same block the same way."""


def desired_inventory(robot: str = "", group: str = "", defaults: str = "") -> str:
    """A local robot (the demo's panther-01, so each command can run on it) in group ``field``,
    with ``desired:`` blocks (flow YAML) on the robot, the group and the defaults."""
    def block(text: str, indent: str) -> str:
        return f"{indent}desired: " + esc("{" + text + "}") + "\n" if text else ""

    return ("version: 1\n" + (f"defaults:\n{block(defaults, '  ')}" if defaults else "")
            + "groups:\n  field:\n" + (block(group, "    ") or "    description: x\n")
            + "robots:\n  r1:\n    transport: local\n    root: {demo}/robots/panther-01\n    groups: [field]\n"
            + block(robot, "    "))


MANAGER_DEPLOY = (("deploy", ("manager", "deploy", "--all", "--dry-run")),)
"""desired.manager's own command: it read the block (and deployed on `enabled: "no"`)."""


def desired_cases(cid: str, names: list[str], *, robot: str = "", group: str = "", defaults: str = "",
                  also: tuple[tuple[str, tuple[str, ...]], ...] = ()) -> list[Case]:
    inv = desired_inventory(robot, group, defaults)
    return [Case(f"desired-{cid}-{name}", list(args), ["inventory.yaml", *names], inventory=inv)
            for name, args in (*DESIRED_COMMANDS, *also)]


DESIRED = [
    # desired.gps: unknown keys, every value whether enabled or not, ports in ASCII digits
    *desired_cases("gps-unknown-key", ["[robots.r1.desired.gps.colour]", "unknown key", "enabled, port, ip"],
                   robot="gps: {enabled: true, colour: red}"),
    *desired_cases("gps-disabled-port", ["[robots.r1.desired.gps.port]", "70000", "1 to 65535"],
                   robot="gps: {enabled: false, port: 70000}"),
    *desired_cases("gps-port-text", ["[robots.r1.desired.gps.port]", "'5000/udp'", "ASCII digits"],
                   robot='gps: {enabled: true, port: "5000/udp"}'),
    *desired_cases("gps-port-fullwidth", ["[robots.r1.desired.gps.port]", "\uff15\uff10\uff10\uff10", "ASCII digits"],
                   robot='gps: {enabled: true, port: "\uff15\uff10\uff10\uff10"}'),
    *desired_cases("gps-enabled-text", ["[robots.r1.desired.gps.enabled]", "'yes please'", "true or false"],
                   robot="gps: {enabled: yes please}"),
    *desired_cases("gps-disabled-ip", ["[robots.r1.desired.gps.ip]", "'10.15.20.256'", "IPv4"],
                   robot="gps: {enabled: false, ip: 10.15.20.256}"),
    *desired_cases("gps-disabled-namespace", ["[robots.r1.desired.gps.namespace]", "'a/b'", "ROS namespace"],
                   robot="gps: {enabled: false, namespace: a/b}"),
    *desired_cases("gps-container-text", ["[robots.r1.desired.gps.container]", "'maybe'", "true or false"],
                   robot="gps: {container: maybe}"),
    *desired_cases("gps-group-port", ["[groups.field.desired.gps.port]", "'5000/udp'", "1 to 65535"],
                   group='gps: {enabled: true, port: "5000/udp"}'),
    *desired_cases("gps-defaults-port", ["[defaults.desired.gps.port]", "0", "1 to 65535"],
                   defaults="gps: {enabled: false, port: 0}"),
    # desired.manager: read only by `manager deploy` before, checked by every command now
    *desired_cases("manager-unknown-key", ["[robots.r1.desired.manager.colour]", "unknown key", "enabled, mode"],
                   robot="manager: {enabled: false, colour: red}"),
    *desired_cases("manager-enabled-text", ["[robots.r1.desired.manager.enabled]", "'no'", "true or false"],
                   robot='manager: {enabled: "no"}', also=MANAGER_DEPLOY),
    *desired_cases("manager-mode", ["[robots.r1.desired.manager.mode]", "'ros1'", "ros2 or sim"],
                   robot="manager: {mode: ros1}",
                   also=MANAGER_DEPLOY),
    *desired_cases("manager-scenario", ["[robots.r1.desired.manager.scenario]", "no_such", "shipped: "],
                   robot="manager: {enabled: false, mode: sim, scenario: no_such}"),
    *desired_cases("manager-param-unknown", ["[robots.r1.desired.manager.params.battery.percent.threshold.lo]",
                                             "not a manager parameter"],
                   robot="manager: {params: {battery.percent.threshold.lo: 0.3}}",
                   also=MANAGER_DEPLOY),
    *desired_cases("manager-param-value", ["[groups.field.desired.manager.params]", "fraction", "7"],
                   group="manager: {enabled: false, params: {battery.percent.threshold.low: 7}}"),
    *desired_cases("manager-hosts-relative", ["[robots.r1.desired.manager.shutdown_hosts]", "'../h.yaml'",
                                              "absolute path"],
                   robot="manager: {shutdown_hosts: ../h.yaml}"),
    # two names of one setting in one block (or merged from two layers): refused naming both
    *desired_cases("manager-param-alias", ["[robots.r1.desired.manager.params.low_battery_threshold_percent]",
                                           "manager.params.battery.percent.threshold.low",
                                           "manager.params.low_battery_threshold_percent", "one manager parameter"],
                   robot="manager: {params: {battery.percent.threshold.low: 0.3, low_battery_threshold_percent: 0.2}}",
                   also=MANAGER_DEPLOY),
    *desired_cases("manager-hosts-twice", ["[robots.r1.desired.manager.params.shutdown_hosts_path]",
                                           "manager.shutdown_hosts and manager.params.shutdown_hosts_path"],
                   robot="manager: {shutdown_hosts: /home/husarion/h.yaml, params: {shutdown_hosts_path: /x.yaml}}",
                   also=MANAGER_DEPLOY),
    *desired_cases("launch-alias", ["[robots.r1.desired.launch_args.animations_config_path]",
                                    "launch_args.led_config_file and launch_args.animations_config_path",
                                    "one launch argument"],
                   robot="launch_args: {led_config_file: /config/a.yaml, animations_config_path: /config/b.yaml}"),
    *desired_cases("controller-alias", ["[robots.r1.desired.controller.controller.linear.x.max_velocity]",
                                        "controller.linear.x.max_velocity and "
                                        "controller.controller.linear.x.max_velocity", "one controller limit"],
                   robot="controller: {linear.x.max_velocity: 1.0, controller.linear.x.max_velocity: 0.5}"),
    # desired.launch_args / controller: what no stack or wheel type takes
    *desired_cases("launch-newline", ["[robots.r1.desired.launch_args.namespace]", "'\\n'", "one line"],
                   robot='launch_args: {namespace: "a\\nb"}'),
    *desired_cases("launch-null", ["[robots.r1.desired.launch_args.wheel_type]", "None", "one value"],
                   robot="launch_args: {wheel_type: null}"),
    *desired_cases("launch-name", ["[robots.r1.desired.launch_args.a;id]", "'a;id'", "letters, digits"],
                   robot='launch_args: {"a;id": 1}'),
    *desired_cases("controller-unknown", ["[robots.r1.desired.controller.linear.x.max_speed]",
                                          "unknown controller limit"],
                   robot="controller: {linear.x.max_speed: 1.0}"),
    *desired_cases("controller-type", ["[defaults.desired.controller.angular.z.max_velocity]", "'fast'",
                                       "not a number"],
                   defaults="controller: {angular.z.max_velocity: fast}"),
    # desired.shutdown_hosts: each entry by the hosts file's one validator
    *desired_cases("hosts-port", ["[robots.r1.desired.shutdown_hosts.0.port]", "70000", "1-65535"],
                   robot="shutdown_hosts: [{ip: 10.15.20.3, username: husarion, port: 70000}]"),
    *desired_cases("hosts-unknown-key", ["[robots.r1.desired.shutdown_hosts.0.colour]", "unknown key"],
                   robot="shutdown_hosts: [{ip: 10.15.20.3, username: husarion, colour: red}]"),
]

# ------------------------------------------------------------------ a local hosts file's backups (--file)
HOSTS = "hosts:\n  - ip: 10.15.20.3\n    username: husarion\n"
BACKUP = "20261122T101500Z-1a2b"


def backup(path: str = "{tmp}/hosts.yaml", bid: str = BACKUP, old: str = HOSTS) -> dict[str, str]:
    """A backup of ``path`` beside hosts.yaml, as `shutdown hosts add hosts.yaml` leaves it."""
    manifest = esc(json.dumps({"id": bid, "created": "2026-11-22T10:15:00+00:00", "command": "shutdown hosts add",
                               "summary": "added", "files": [{"path": "PATH", "backup": "files/0"}]}))
    root = f".panther-ops/backups/{bid}"
    return {"hosts.yaml": HOSTS + "  - ip: 10.15.20.4\n    username: pi\n", f"{root}/files/0": esc(old),
            f"{root}/manifest.json": manifest.replace("PATH", path)}


LOCAL = ["--file", "{tmp}/hosts.yaml"]
ALLOWED_FILE = "shutdown hosts add|remove FILE"
LOCAL_FILES = [
    Case("local-history-directory", ["config", "history", "--file", "{tmp}"], ["--file", "is a directory",
                                                                                ALLOWED_FILE]),
    Case("local-history-no-directory", ["config", "history", "--file", "{tmp}/none/hosts.yaml"],
         ["--file", "none", "does not exist", ALLOWED_FILE]),
    Case("local-history-newline", ["config", "history", "--file", "{tmp}/a\nb.yaml"], ["control character"]),
    Case("local-history-and-robots", ["config", "history", *LOCAL, "--all"], ["--file", "not both"]),
    Case("local-rollback-and-robots", ["config", "rollback", *LOCAL, *R1], ["--file", "not both"]),
    Case("local-rollback-directory", ["config", "rollback", "--file", "{tmp}", "--yes"], ["is a directory"]),
    Case("local-rollback-no-backups", ["config", "rollback", *LOCAL, "--yes"],
         ["no backups of {tmp}/hosts.yaml", ".panther-ops/backups/"], files={"hosts.yaml": HOSTS}),
    Case("local-rollback-id-dotdot", ["config", "rollback", *LOCAL, "--to", "../../etc", "--yes"],
         ["--to", "'../../etc'"], files=backup()),
    Case("local-rollback-id-injection", ["config", "rollback", *LOCAL, "--to", INJECT, "--yes"], [INJECT],
         files=backup()),
    Case("local-rollback-id-unknown", ["config", "rollback", *LOCAL, "--to", "20991231", "--yes"],
         ["'20991231' not found for {tmp}/hosts.yaml", f"newest backups: {BACKUP}"], files=backup()),
    Case("local-rollback-other-file", ["config", "rollback", *LOCAL, "--to", BACKUP, "--yes"],
         [f"backup {BACKUP} is not a backup of {{tmp}}/hosts.yaml", "{tmp}/victim.txt"],
         files={**backup("{tmp}/victim.txt"), "victim.txt": "keep me\n"}),
    Case("local-rollback-invalid-content", ["config", "rollback", *LOCAL, "--yes"],
         ["hosts.yaml", "'10.15.20.3; reboot' is not an IP address"],
         files=backup(old="hosts:\n  - ip: '10.15.20.3; reboot'\n    username: pi\n")),
    # options that mean something only for robots: named, with why (nothing is recreated for a file)
    Case("local-rollback-robot-options", ["config", "rollback", *LOCAL, "--no-restart", "--settle", "9", "-f", "4",
                                          "--yes"],
         ["--no-restart, --settle, --forks mean nothing for --file {tmp}/hosts.yaml", "no container is recreated",
          "leave them out"], files=backup()),
    Case("local-rollback-settle", ["config", "rollback", *LOCAL, "--settle", "1", "--yes"],
         ["--settle means nothing for --file", "leave it out"], files=backup()),
    Case("local-history-forks", ["config", "history", *LOCAL, "--forks", "2"], ["--forks means nothing for --file"],
         files=backup()),
    Case("local-hosts-add-no-restart", ["shutdown", "hosts", "add", "{tmp}/hosts.yaml", "--ip", "10.15.20.9",
                                        "--user", "pi", "--no-restart", "--yes"],
         ["--no-restart means nothing for the local FILE {tmp}/hosts.yaml"], files={"hosts.yaml": HOSTS}),
    Case("local-hosts-remove-forks", ["shutdown", "hosts", "remove", "{tmp}/hosts.yaml", "--ip", "10.15.20.3",
                                      "-f", "3", "--yes"], ["--forks means nothing for the local FILE"],
         files={"hosts.yaml": HOSTS}),
]

# ------------------------------------------------------------------ reimage flash/verify: a bad image and a bad device
# The image is judged first, whatever the device (docs/reimage.md): the image is named, not the device. The
# devices are a regular file, a path that does not exist and a character device: never a block device.
IMAGE = b"\x00" * 4096 + b"not a real card image" * 100
GZ = gzip.compress(IMAGE)
TRUNCATED_GZ = GZ[: len(GZ) // 2]
ZEROS = "0" * 64
OTHER_BMAP = (b'<?xml version="1.0" ?><bmap version="1.0"><ImageSize> 8192 </ImageSize><BlockSize> 4096 </BlockSize>'
              b"<BlocksCount> 2 </BlocksCount><MappedBlocksCount> 1 </MappedBlocksCount>"
              b"<BlockMap><Range> 1 </Range></BlockMap></bmap>")
"""A good bmap (version 1.0: no checksums) of another image than x.img."""
BAD_DEVICES = [("card-file", "{tmp}/card.bin"), ("no-device", "/dev/panther-ops-no-such-card"),
               ("char-device", "/dev/null")]


def _image_cases(dev_id: str, dev: str) -> list[Case]:
    card = {"card.bin": b"card " * 100}
    # --full: the image's checksum is checked before anything (block-mapped flashing checks it as it writes)
    flash = ["reimage", "flash", "{tmp}/x.img", "--device", dev, "--yes", "--full"]
    flash_gz = ["reimage", "flash", "{tmp}/x.img.gz", "--device", dev, "--yes", "--full"]
    mapped = ["reimage", "flash", "{tmp}/x.img", "--device", dev, "--yes"]
    ok_image = {**card, "x.img": IMAGE, "x.img.sha256": f"{hashlib.sha256(IMAGE).hexdigest()}  x.img\n"}
    verify = ["reimage", "verify", "{tmp}/x.img", "--device", dev]
    verify_gz = ["reimage", "verify", "{tmp}/x.img.gz", "--device", dev]
    gz = {**card, "x.img.gz": TRUNCATED_GZ,
          "x.img.gz.sha256": f"{hashlib.sha256(TRUNCATED_GZ).hexdigest()}  x.img.gz\n"}
    wrong_sidecar = {**card, "x.img": IMAGE, "x.img.sha256": f"{ZEROS}  x.img\n"}
    return [
        Case(f"flash-wrong-sha256-{dev_id}", [*flash, "--sha256", ZEROS],
             ["{tmp}/x.img: sha256 is " + hashlib.sha256(IMAGE).hexdigest(), f"--sha256 says {ZEROS}"],
             files={**card, "x.img": IMAGE}),
        Case(f"flash-wrong-sidecar-{dev_id}", flash, ["{tmp}/x.img: sha256 is", f"{{tmp}}/x.img.sha256 says {ZEROS}"],
             files=wrong_sidecar),
        Case(f"flash-sidecar-not-a-hash-{dev_id}", flash, ["x.img.sha256", "'not-a-hash' is not a sha256"],
             files={**card, "x.img": IMAGE, "x.img.sha256": "not-a-hash\n"}),
        Case(f"flash-no-checksum-{dev_id}", flash, ["{tmp}/x.img: no checksum", "--sha256 HASH", "x.img.sha256"],
             files={**card, "x.img": IMAGE}),
        Case(f"flash-truncated-gz-{dev_id}", flash_gz, ["{tmp}/x.img.gz: not a readable .gz file"], files=gz),
        Case(f"flash-name-not-content-{dev_id}", ["reimage", "flash", "{tmp}/x.img.xz", "--device", dev, "--yes",
                                                  "--sha256", ZEROS],
             ["x.img.xz: the name says xz-compressed but the content is uncompressed"],
             files={**card, "x.img.xz": IMAGE}),
        Case(f"verify-wrong-sha256-{dev_id}", [*verify, "--sha256", ZEROS], ["{tmp}/x.img: sha256 is"],
             files={**card, "x.img": IMAGE}),
        Case(f"verify-wrong-sidecar-{dev_id}", verify, [f"{{tmp}}/x.img.sha256 says {ZEROS}"], files=wrong_sidecar),
        Case(f"verify-truncated-gz-{dev_id}", verify_gz, ["{tmp}/x.img.gz: not a readable .gz file"], files=gz),
        Case(f"flash-bmap-not-xml-{dev_id}", mapped, ["{tmp}/x.img.bmap: not a bmap file (not XML"],
             files={**ok_image, "x.img.bmap": "<bmap version='2.0'>"}),
        Case(f"flash-bmap-other-image-{dev_id}", [*mapped, "--bmap", "{tmp}/other.bmap"],
             ["{tmp}/other.bmap: the block map is of an image of 8192 bytes", "not this image's map"],
             files={**ok_image, "other.bmap": OTHER_BMAP}),
        Case(f"flash-bmap-missing-{dev_id}", [*mapped, "--bmap", "{tmp}/none.bmap"],
             ["--bmap {tmp}/none.bmap: no such file"], files=ok_image),
    ]


IMAGES = [case for dev_id, dev in BAD_DEVICES for case in _image_cases(dev_id, dev)]

CASES = (WEBUI + DESIRED + INVENTORY + ALIASES + SELECTORS + LAUNCH_ARGS + REACHES_ROBOT + SCENARIOS + LIGHTS + STACKS
         + LOCAL_FILES + IMAGES)


def test_the_corpus_is_large_and_unique() -> None:
    assert len(CASES) >= 60
    assert len({c.id for c in CASES}) == len(CASES)


@pytest.mark.parametrize("case", CASES, ids=str)
def test_refused(case: Case, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                 monkeypatch: pytest.MonkeyPatch) -> None:
    if case.files.get("led.yaml") == "":  # the stock led_config, copied in
        from panther_ops.core.fleet.templates import template_path

        case = Case(case.id, case.args, case.names,
                    files={"led.yaml": esc(template_path("lights", "led_config.yaml").read_text())},
                    inventory=case.inventory)
    check_refused(case, tmp_path, capsys, monkeypatch)
