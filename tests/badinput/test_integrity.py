"""Bad-input corpus, issue 23 (integrity of input): values already in a file, numbers that are
not ASCII, and settings given twice.

- A file that is wrong before the edit is refused by the edit that leaves the wrong value as
  it was (the whole file is checked, not only the values given on the command line): the sim
  world's spherical coordinates, a components entry, a shutdown hosts entry.
- Numbers, ports and ids in ASCII digits only (``８０８１`` is 8081 to Python, not to ``snap
  set``, docker compose or Gazebo): every file kind and command option that takes one.
- One setting given twice (``port`` and ``webui.port``; ``ros.transport=`` with
  ``--dds-file``; a launch argument under two of its names; a controller limit with and
  without ``controller.``) is refused naming both, not silently resolved.

Each case: exit 2, the thing named, no traceback, every file byte-identical.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.badinput.harness import Case, check_refused
from tests.badinput.test_inputs import LOCAL_01, esc
from tests.sim_world import WORLD

FW_8081 = "８０８１"  # full-width digits: 8081 to int() and \d, not to snap set
R1 = ["-r", "panther-01", "--yes"]


def world(old: str, new: str) -> str:
    assert old in WORLD, old
    return esc(WORLD.replace(old, new, 1))


def world_set(cid: str, content: str, argv: list[str], names: list[str], *, file: bool = True) -> Case:
    return Case(f"world-{cid}", ["sim", "world", "set", "{tmp}/w.sdf", *argv, "--yes"],
                ["{tmp}/w.sdf", *names] if file else names, files={"w.sdf": content})


LAT = "<latitude_deg>53.1978</latitude_deg>"
WORLD_FILE = [  # finding 2: values already in the file, the edit changing another one
    world_set("lat-200", world(LAT, "<latitude_deg>200</latitude_deg>"), ["--longitude", "20"],
              ["spherical_coordinates.latitude_deg='200'", "-90 to 90", "--latitude"]),
    world_set("lat-dms", world(LAT, "<latitude_deg>53°11'52\"N</latitude_deg>"), ["--longitude", "20"],
              ["spherical_coordinates.latitude_deg=", "degrees, minutes and seconds", "--latitude 53.197778"]),
    world_set("lon-dms-west", world("<longitude_deg>18.3732", "<longitude_deg>18°22'24\"W"), ["--elevation", "5"],
              ["longitude_deg=", "--longitude -18.373333"]),
    world_set("lon-fullwidth", world("<longitude_deg>18.3732", "<longitude_deg>１８.３７３２"), ["--latitude", "50"],
              ["longitude_deg='１８.３７３２'", "ASCII digits", "--longitude"]),
    world_set("elevation-nan", world("<elevation>0", "<elevation>nan"), ["--latitude", "50"],
              ["spherical_coordinates.elevation='nan'", "--elevation"]),
    world_set("lat-empty", world(LAT, "<latitude_deg></latitude_deg>"), ["--longitude", "20"],
              ["spherical_coordinates.latitude_deg=''"]),
    world_set("lat-twice", world(LAT, LAT + "\n      <latitude_deg>52.0</latitude_deg>"), ["--longitude", "20"],
              ["spherical_coordinates.latitude_deg: given twice"]),
    world_set("lat-twice-set", world(LAT, LAT + "\n      <latitude_deg>52.0</latitude_deg>"), ["--latitude", "20"],
              ["spherical_coordinates.latitude_deg: given twice"]),
    world_set("two-blocks", world("    <gravity>", "    <spherical_coordinates><latitude_deg>1</latitude_deg>"
                                                    "</spherical_coordinates>\n    <gravity>"), ["--latitude", "20"],
              ["spherical_coordinates: 2 blocks", "keep one"]),
    world_set("heading-360+", world("<elevation>0</elevation>", "<elevation>0</elevation><heading_deg>400"
                                                              "</heading_deg>"), ["--latitude", "20"],
              ["heading_deg='400'", "-360 to 360", "--heading"]),
    world_set("entity", "<!DOCTYPE sdf [<!ENTITY a \"1\">]>\n" + esc(WORLD.split("\n", 1)[1]), ["--latitude", "20"],
              ["<!ENTITY>"]),
    # finding 3 on the command line: the option's parser
    world_set("option-fullwidth", esc(WORLD), ["--latitude", "５３"], ["'--latitude'", "'５３'", "ASCII digits"],
              file=False),
    world_set("option-underscore", esc(WORLD), ["--elevation", "1_000"], ["'--elevation'", "'1_000'"], file=False),
    world_set("option-inf", esc(WORLD), ["--heading", "inf"], ["'--heading'", "'inf'"], file=False),
]

COMPONENTS = "components:\n  - type: LDR06\n    parent_link: cover_link\n    xyz: {xyz}\n"
SIM_GPS = [  # sim gps add: the whole components file, and its own --xyz / --rpy
    Case("sim-gps-add-xyz-fullwidth-in-file", ["sim", "gps", "add", "{tmp}/c.yaml", "--yes"],
         ["c.yaml", "components[0].xyz='０.1 0.0 0.2'"], files={"c.yaml": COMPONENTS.format(xyz="０.1 0.0 0.2")}),
    Case("sim-gps-add-xyz-ideographic-space", ["sim", "gps", "add", "{tmp}/c.yaml", "--yes"],
         ["c.yaml", "components[0].xyz="], files={"c.yaml": COMPONENTS.format(xyz="0.1\u30000.0 0.2")}),
    Case("sim-gps-add-xyz-underscore", ["sim", "gps", "add", "{tmp}/c.yaml", "--yes"],
         ["c.yaml", "components[0].xyz='1_0 0 0'"], files={"c.yaml": COMPONENTS.format(xyz="1_0 0 0")}),
    Case("sim-gps-add-option-xyz-fullwidth", ["sim", "gps", "add", "{tmp}/c.yaml", "--xyz", "０.185 -0.12 0.0",
                                              "--yes"], ["--xyz", "'０.185 -0.12 0.0'"],
         files={"c.yaml": COMPONENTS.format(xyz="0 0 0")}),
    Case("sim-gps-add-option-rpy-nan", ["sim", "gps", "add", "{tmp}/c.yaml", "--rpy", "nan 0 0", "--yes"],
         ["--rpy", "'nan 0 0'"], files={"c.yaml": COMPONENTS.format(xyz="0 0 0")}),
]

HOSTS_FW = "hosts:\n  - ip: 10.15.20.3\n    username: husarion\n    port: \"２２\"\n"
HOSTS_FILE = [  # a shutdown hosts file: a port in other digits (the manager's int() would take it, yaml-cpp not)
    Case("hosts-validate-port-fullwidth", ["shutdown", "hosts", "validate", "{tmp}/hosts.yaml"],
         ["hosts[0].port", "'２２' is not a TCP port"], files={"hosts.yaml": HOSTS_FW}),
    Case("hosts-shutdown-port-fullwidth", ["shutdown", "--hosts", "{tmp}/hosts.yaml", "--dry-run"],
         ["hosts[0].port", "'２２'"], files={"hosts.yaml": HOSTS_FW}),
    Case("hosts-add-local-file-port-fullwidth", ["shutdown", "hosts", "add", "{tmp}/hosts.yaml", "--ip", "10.15.20.4",
                                                 "--user", "pi", "--yes"],
         ["hosts[0].port", "'２２'"], files={"hosts.yaml": HOSTS_FW}),
    Case("hosts-port-decimal-text", ["shutdown", "hosts", "validate", "{tmp}/hosts.yaml"],
         ["hosts[0].port", "'22.0' is not a TCP port"], files={"hosts.yaml": HOSTS_FW.replace("２２", "22.0")}),
    Case("hosts-timeout-fullwidth", ["shutdown", "hosts", "validate", "{tmp}/hosts.yaml"],
         ["hosts[0].timeout", "'５'"],
         files={"hosts.yaml": "hosts:\n  - ip: 10.15.20.3\n    username: husarion\n    timeout: \"５\"\n"}),
    Case("hosts-add-option-port-fullwidth", ["shutdown", "hosts", "add", "--ip", "10.15.20.4", "--user", "pi",
                                             "--port", "２２", *R1], ["'--port'", "'２２'"]),
    Case("hosts-remove-option-port-fullwidth", ["shutdown", "hosts", "remove", "--ip", "10.15.20.4", "--port", "２２",
                                                *R1], ["'--port'", "'２２'"]),
    Case("hosts-setup-option-port-fullwidth", ["shutdown", "setup", "--host", "10.15.20.4", "--port", "２２", *R1],
         ["'--port'", "'２２'"]),
]

WEBUI_SET = [  # webui set: checked before any robot is contacted
    Case("webui-set-port-fullwidth", ["webui", "set", f"webui.port={FW_8081}", *R1],
         [f"webui.port='{FW_8081}'", "1 to 65535 (ASCII digits 0-9)"]),
    Case("webui-set-port-short-name-fullwidth", ["webui", "set", f"port={FW_8081}", *R1],
         [f"webui.port='{FW_8081}'", "ASCII digits"]),
    Case("webui-set-domain-arabic-indic", ["webui", "set", "ros.domain-id=\u0663", *R1],
         ["ros.domain-id='\u0663'", "0 to 232"]),
    Case("webui-set-port-superscript", ["webui", "set", "webui.port=8\u00b9", *R1], ["webui.port='8\u00b9'"]),
    # finding 4: one key twice
    Case("webui-set-transport-and-dds-file", ["webui", "set", "ros.transport=udp", "--dds-file", "{tmp}/lan.xml",
                                              *R1],
         ["ros.transport=udp", "--dds-file {tmp}/lan.xml", "both set ros.transport", "leave ros.transport out"],
         files={"lan.xml": "<dds><profiles/></dds>\n"}),
    Case("webui-set-short-transport-and-dds-file", ["webui", "set", "transport=shm", "--dds-file", "{tmp}/lan.xml",
                                                    *R1], ["transport=shm", "--dds-file", "both set ros.transport"],
         files={"lan.xml": "<dds><profiles/></dds>\n"}),
    Case("webui-set-port-and-short-name", ["webui", "set", "port=8081", "webui.port=8082", *R1],
         ["port=8081", "webui.port=8082", "both set webui.port"]),
    Case("webui-set-key-twice", ["webui", "set", "webui.layout=a", "webui.layout=b", *R1],
         ["webui.layout=a", "webui.layout=b", "both set webui.layout"]),
]


def desired(block: str) -> str:
    return LOCAL_01 + "    desired: " + esc(block) + "\n"


DESIRED_COMMANDS = (("apply", "--all", "--yes"), ("apply", "--all", "--dry-run"), ("config", "diff", "--all"),
                    ("inventory", "validate"))
DESIRED_BAD: dict[str, tuple[str, list[str]]] = {
    "webui-port-fullwidth": ("{webui: {port: \"" + FW_8081 + "\"}}",
                             ["desired.webui.port", f"'{FW_8081}'", "ASCII digits"]),
    "webui-domain-fullwidth": ("{webui: {ros.domain-id: \"１\"}}", ["desired.webui.ros.domain-id", "'１'"]),
    "webui-port-twice": ("{webui: {port: 8081, webui.port: 8082}}",
                         ["desired.webui.webui.port", "port=8081 and webui.port=8082 both set webui.port",
                          "keep one"]),
    "webui-namespace-twice": ("{webui: {ros.namespace: a, namespace: b}}",
                              ["desired.webui.namespace", "both set ros.namespace"]),
    "webui-transport-twice": ("{webui: {transport: udp, ros.transport: shm}}", ["both set ros.transport"]),
    "controller-limit-twice": ("{controller: {linear.x.max_velocity: 1.0, controller.linear.x.max_velocity: 1.5}}",
                               ["desired.controller.controller.linear.x.max_velocity",
                                "controller.linear.x.max_velocity and controller.controller.linear.x.max_velocity "
                                "are one controller limit"]),
}
DESIRED = [Case(f"desired-{cid}-{'-'.join(w.strip('-') for w in cmd)}", list(cmd), names, inventory=desired(block))
           for cid, (block, names) in DESIRED_BAD.items() for cmd in DESIRED_COMMANDS]
# a launch argument under two of its names: refused when planned (the catalogue knows the names)
DESIRED += [Case(f"desired-launch-arg-twice-{'-'.join(w.strip('-') for w in cmd)}", list(cmd),
                 ["launch_args.user_animations_file and launch_args.user_led_animations_file are one launch "
                  "argument", "keep one"],
                 inventory=desired("{launch_args: {user_animations_file: /config/a.yaml, "
                                   "user_led_animations_file: /config/b.yaml}}"))
            for cmd in DESIRED_COMMANDS[:3]]

OPTIONS = [  # finding 3: numbers, ports and ids given as options, in other scripts' digits (or with '_')
    Case("opt-gps-enable-port", ["gps", "enable", "--port", "５０００", *R1], ["'--port'", "'５０００'"]),
    Case("opt-gps-enable-ip", ["gps", "enable", "--ip", "１０.15.20.2", *R1], ["--ip", "'１０.15.20.2'"]),
    Case("opt-gps-router-set-port", ["gps", "router", "set", "--port", "５０００", *R1], ["'--port'", "'５０００'"]),
    Case("opt-gps-status-port", ["gps", "status", "--port", "５０００", "-r", "panther-01"], ["'--port'"]),
    Case("opt-gps-status-window", ["gps", "status", "--window", "３", "-r", "panther-01"], ["'--window'", "'３'"]),
    Case("opt-gps-listen-udp", ["gps", "listen", "--udp", "127.0.0.1:５０００", "--timeout", "0.2"],
         ["--udp port", "'５０００'"]),
    Case("opt-gps-listen-count", ["gps", "listen", "--udp", "127.0.0.1:5000", "--count", "1_0"],
         ["'--count'", "'1_0'"]),
    Case("opt-lights-test-id", ["lights", "test", "２１", "-r", "panther-01"], ["'２１'", "0 to 65535"]),
    Case("opt-forks", ["status", "--all", "--forks", "５"], ["'--forks'", "'５'"]),
    Case("opt-canary", ["driver", "restart", "--all", "--canary", "１", "--yes"], ["'--canary'", "'１'"]),
    Case("opt-max-fail", ["driver", "restart", "--all", "--max-fail", "５０", "--yes"], ["'--max-fail'"]),
    Case("opt-settle", ["driver", "restart", "--all", "--settle", "５", "--yes"], ["'--settle'", "'５'"]),
    Case("opt-lines", ["driver", "logs", "-r", "panther-01", "--lines", "１０"], ["'--lines'", "'１０'"]),
    Case("opt-since", ["driver", "logs", "-r", "panther-01", "--since", "５m"], ["'５m' is not a duration"]),
    Case("opt-controller-value", ["config", "set", "controller.linear.x.max_velocity", "１.0", *R1],
         ["controller.linear.x.max_velocity='１.0' is not a number", "ASCII digits"]),
    Case("opt-manager-speed", ["manager", "run", "--sim", "--speed", "２"], ["'--speed'", "'２'"]),
    Case("opt-teleop-rate", ["teleop", "-r", "panther-01", "--rate", "１０"], ["'--rate'", "'１０'"]),
    Case("opt-power-budget", ["shutdown", "hosts", "validate", "{tmp}/hosts.yaml", "--power-budget", "１５"],
         ["'--power-budget'"], files={"hosts.yaml": "hosts:\n  - ip: 10.15.20.3\n    username: husarion\n"}),
]

INVENTORY_NUMBERS = [  # the inventory's versions and jump ports (also read by every fleet command)
    Case("inv-jump-port-fullwidth", ["inventory", "validate"], ["robots.r1.jump", "'２２'"],
         inventory=esc("version: 1\nrobots:\n  r1: {host: panther-07, jump: \"op@gw:２２\"}\n")),
    Case("inv-stack-fullwidth", ["status", "--all"], ["robots.r1.stack", "'２.1.1'"],
         inventory=esc("version: 1\nrobots:\n  r1: {host: panther-07, stack: \"２.1.1\"}\n")),
]

CASES = WORLD_FILE + SIM_GPS + HOSTS_FILE + WEBUI_SET + DESIRED + OPTIONS + INVENTORY_NUMBERS


@pytest.mark.parametrize("case", CASES, ids=str)
def test_refused(case: Case, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                 monkeypatch: pytest.MonkeyPatch) -> None:
    check_refused(case, tmp_path, capsys, monkeypatch)
