"""Per-stack names on 2.0, 2.1 and 2.2 robots (issue 11, finding 11): animation types written for
the robot's stack on every path that deploys animations, the deployed manager's ROS 2
interfaces, and what `manager deploy` checks in the image before the stock manager stands down.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
import yaml

from panther_ops.cli.app import main
from panther_ops.core.config.push import plan_push, read_bundle
from panther_ops.core.fleet.templates import template_path
from panther_ops.core.kinds import FileKind
from tests.unit.test_manager_deploy import ctxs, make_fleet  # noqa: F401 - fixture

EXAMPLE = template_path("lights", "user_animations.example.yaml")
UGV_STYLE = """user_animations:
  - id: 30
    name: UGV_STYLE
    priority: 3
    animations:
      - {type: husarion_ugv_lights::ChargingAnimation, segments: all, animation: {duration: 2}}
      - type: 'husarion_ugv_lights::ImageAnimation'   # kept comment
        segments: rear
        animation:
          image: $(find husarion_ugv_lights)/animations/panther/triangle01_red.png
          duration: 2
"""


def _main_file(plan: Any) -> str:
    edit = next(e for e in plan.edits if e.path.endswith(".yaml") and not e.path.endswith("compose.yaml"))
    return str(edit.after.decode())


@pytest.mark.parametrize(("robot", "package", "find"), [
    ("r20", "panther_lights", "$(find panther_lights)/animations/"),
    ("r21", "panther_lights", "$(find panther_lights)/animations/"),
    ("r22", "husarion_ugv_lights", "$(find husarion_ugv_lights)/animations/panther/"),
])
def test_pushed_animations_use_the_robots_animation_types(ctxs: Any, tmp_path: Path, robot: str,  # noqa: F811
                                                           package: str, find: str) -> None:
    _tmp, cs = ctxs
    ugv = tmp_path / "ugv_style.yaml"
    ugv.write_text(UGV_STYLE)
    # user animations files (the manual's example, a 2.2-style one) and a led config, each as its own kind
    led = Path(__file__).resolve().parents[2] / "templates" / "lights" / "led_config.yaml"
    for source, kind, key in ((EXAMPLE, FileKind.USER_ANIMATIONS, "user_animations"),
                              (ugv, FileKind.USER_ANIMATIONS, "user_animations"),
                              (led, FileKind.LED, "led_animations")):
        plan = plan_push(cs[robot], kind, read_bundle(kind, source))
        text = _main_file(plan)
        types = {a["type"] for anim in yaml.safe_load(text)[key] for a in anim["animations"]}
        assert types <= {f"{package}::ImageAnimation", f"{package}::ChargingAnimation"}, (robot, kind, types)
        images = [a["animation"]["image"] for anim in yaml.safe_load(text)[key]
                  for a in anim["animations"] if "image" in a["animation"]]
        assert images and all(i.startswith(find) for i in images), images
        other = "husarion_ugv_lights::" if package == "panther_lights" else "panther_lights::"
        assert other not in text
        if source == ugv:
            assert "# kept comment" in text  # rewritten as text: comments and layout stay


def test_lights_deploy_on_a_22_robot_writes_husarion_ugv_types(tmp_path: Path,
                                                                capsys: pytest.CaptureFixture[str]) -> None:
    inv = make_fleet(tmp_path, {"r22": ("husarion-ugv-2.2.2.yaml", {})})
    assert inv.robots["r22"]
    capsys.readouterr()
    code = main(["-i", str(tmp_path / "inv.yaml"), "lights", "deploy", str(EXAMPLE), "-r", "r22", "--yes",
                 "--json"])
    out = capsys.readouterr().out
    assert code == 0, out
    doc = json.loads(out)
    assert "husarion_ugv_lights::ImageAnimation" in json.dumps(doc)  # said in the result
    written = [p for p in (tmp_path / "robots/r22/home/husarion/config").rglob("*.yaml")
               if "user_animations" in p.read_text()]
    assert len(written) == 1
    text = written[0].read_text()
    assert "type: husarion_ugv_lights::ImageAnimation" in text and "panther_lights::" not in text


@pytest.mark.parametrize(("version", "msgs", "driver_topic", "lights"), [
    ("2.0.4", "panther_msgs", "driver/motor_controllers_state", "lights/controller/set/animation"),
    ("2.1.1", "panther_msgs", "hardware/motor_controllers_state", "lights/set_animation"),
    ("2.2.2", "husarion_ugv_msgs", "hardware/robot_driver_state", "lights/set_animation"),
])
def test_manager_ros_interfaces_per_stack(version: str, msgs: str, driver_topic: str, lights: str) -> None:
    from panther_ops.manager.adapters.interfaces import interfaces_for, parse_stack

    ros = interfaces_for(parse_stack(version))
    assert ros.msg_package == msgs and ros.driver_state == driver_topic
    assert ros.service("lights/set_animation") == lights
    assert ros.service("hardware/e_stop_trigger") == "hardware/e_stop_trigger"
    assert ros.set_led_animation_type == f"{msgs}/srv/SetLEDAnimation"


def test_manager_entry_point_takes_the_stack(capsys: pytest.CaptureFixture[str]) -> None:
    from panther_ops.manager.__main__ import main as manager_main

    assert manager_main(["--check", "--stack", "2.2.2"]) == 0
    assert "husarion_ugv 2.2 interfaces, husarion_ugv_msgs" in capsys.readouterr().out
    assert manager_main(["--check", "--stack", "2.1.1"]) == 0
    assert "panther_ros 2.1 interfaces, panther_msgs" in capsys.readouterr().out
    assert manager_main(["--check", "--stack", "two"]) == 2
    assert "--stack 'two': expected the robot's stack version" in capsys.readouterr().out


HOSTS_SSH = "hosts:\n  - {ip: 192.0.2.3, username: husarion}\n  - {ip: 192.0.2.4, port: 3003}\n"
SSH_CMD = "ssh -o BatchMode=yes -i /root/.ssh/id_rsa husarion@127.0.0.1 sudo shutdown now"
DBUS_CMD = "dbus-send --system --print-reply --dest=org.freedesktop.login1 /org/freedesktop/login1 x"


@pytest.mark.parametrize(("probe", "hosts", "command", "lost"), [
    ("has python3\n", HOSTS_SSH, SSH_CMD, ["User Computers", "robot itself off (ssh"]),
    ("has python3\nhas ssh\n", HOSTS_SSH, SSH_CMD, []),
    ("has python3\nhas paramiko\n", HOSTS_SSH, DBUS_CMD, ["robot itself off (dbus-send"]),
    ("has python3\nhas paramiko\nhas dbus-send\n", HOSTS_SSH, DBUS_CMD, []),
    ("has python3\nhas dbus-send\n", "hosts:\n  - {ip: 192.0.2.4, port: 3003}\n", DBUS_CMD, []),  # HTTP only
    ("has python3\nhas dbus-send\n", None, DBUS_CMD, []),  # no hosts file: nothing to shut down
])
def test_what_deploy_would_lose(probe: str, hosts: str | None, command: str, lost: list[str]) -> None:
    from panther_ops.core.manager_ops.checks import losses, parse_probe, ssh_hosts

    output = probe + (f"--- panther-ops hosts file ---\n{hosts}" if hosts is not None else "")
    facts = parse_probe("husarion/panther:humble-2.1.1-20240828", output)
    assert facts.hosts_text == hosts
    found = losses(facts, ssh_hosts(facts.hosts_text, "hosts.yaml"), "hosts.yaml", command)
    assert len(found) == len(lost) and all(w in f for w, f in zip(lost, found, strict=True)), found
    if lost and "User Computers" in lost[0]:
        assert "husarion@192.0.2.3:22" in found[0] and "192.0.2.4" not in found[0]


def test_ssh_hosts_without_a_host_key_on_the_robot_would_be_lost() -> None:
    """The stock node (libssh) does not check host keys; the deployed manager refuses unknown ones."""
    import paramiko

    from panther_ops.core.manager_ops.checks import losses, parse_probe, ssh_hosts, unknown_host_keys

    pub = "ssh-ed25519 AAAAC3NzaC1lZDI1NTE5AAAAIOMqqnkVzrm0SdG6UOoqKLsabgH5C9okWi0dh2l9GKJl"
    text = "hosts:\n  - {ip: 192.0.2.3, username: husarion}\n  - {ip: 192.0.2.5, username: pi, port: 2222}\n" \
           "  - {ip: 192.0.2.6, username: root}\n"
    hosts = ssh_hosts(text, "hosts.yaml")
    known = (f"192.0.2.3 {pub}\n"
             f"{paramiko.HostKeys.hash_host('[192.0.2.5]:2222')} {pub}\n"  # hashed, non-default port
             f"192.0.2.6:22 {pub}\n")  # not how ssh names port 22: does not count
    assert [h.ip for h in unknown_host_keys(known, hosts)] == ["192.0.2.6"]
    facts = parse_probe("img", "has ssh\n")
    found = losses(facts, hosts, "hosts.yaml", "", unknown_host_keys(known, hosts))
    assert found == ["shutting down root@192.0.2.6:22 over SSH: no host key in the robot's ~/.ssh/known_hosts "
                     "(the stock manager does not check host keys; this one refuses unknown ones)"]
    assert unknown_host_keys("", hosts) == hosts
