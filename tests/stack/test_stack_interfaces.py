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
from panther_ops.core.config.read import read_and_plan_push
from panther_ops.core.fleet.templates import template_path
from panther_ops.core.kinds import FileKind
from panther_ops.core.robot.push import read_bundle
from tests.manager_ops.test_manager_deploy import ctxs, make_fleet  # noqa: F401 - fixture

EXAMPLE = template_path("lights", "user_animations.example.yaml")
LED_21 = template_path("lights", "led_config.yaml")
LED_22 = template_path("config", "husarion-ugv-2.2", "husarion_ugv_lights", "config", "panther_animations.yaml")
PORTABLE = """user_animations:
  - id: 30
    name: OWN_IMAGE
    priority: 3
    animations:
      - type: 'husarion_ugv_lights::ImageAnimation'   # kept comment
        segments: rear
        animation:
          image: {image}
          duration: 2
"""


def _main_file(plan: Any) -> str:
    edit = next(e for e in plan.edits if e.path.endswith(".yaml") and not e.path.endswith("compose.yaml"))
    return str(edit.after.decode())


def _types(text: str, key: str) -> set[str]:
    return {a["type"] for anim in yaml.safe_load(text)[key] for a in anim["animations"]}


@pytest.mark.parametrize(("robot", "package"), [
    ("r20", "panther_lights"), ("r21", "panther_lights"), ("r22", "husarion_ugv_lights")])
def test_pushed_animations_use_the_robots_animation_types(ctxs: Any, tmp_path: Path, robot: str,  # noqa: F811
                                                           package: str) -> None:
    """ImageAnimation exists in both lights packages: a file with its own images is written with the
    robot's package (panther_ros@2.1.1 / husarion_ugv_ros@2.2.0:*_lights/plugins.xml), as text."""
    _tmp, cs = ctxs
    from PIL import Image

    image = tmp_path / "mine.png"
    Image.new("RGBA", (46, 10), (255, 0, 0, 255)).save(image)
    own = tmp_path / "own.yaml"
    own.write_text(PORTABLE.format(image=image))
    text = _main_file(read_and_plan_push(cs[robot], FileKind.USER_ANIMATIONS, read_bundle(FileKind.USER_ANIMATIONS, own)))
    assert _types(text, "user_animations") == {f"{package}::ImageAnimation"}
    assert "# kept comment" in text  # rewritten as text: comments and layout stay
    # each release's own stock file goes to a robot of that release as it is
    stock = (LED_22 if package == "husarion_ugv_lights" else LED_21)
    text = _main_file(read_and_plan_push(cs[robot], FileKind.LED, read_bundle(FileKind.LED, stock)))
    assert {t.split("::")[0] for t in _types(text, "led_animations")} == {package}


@pytest.mark.parametrize(("robot", "source", "kind", "said"), [
    # 2.2 ships other images, under animations/panther/, and no ChargingAnimation
    ("r22", EXAMPLE, FileKind.USER_ANIMATIONS, "no package panther_lights on husarion_ugv 2.2"),
    ("r22", LED_21, FileKind.LED, "unknown animation type 'panther_lights::ChargingAnimation' on husarion_ugv 2.2"),
    # 2.0/2.1 have no MovingImageAnimation nor husarion_ugv_lights
    ("r21", LED_22, FileKind.LED, "unknown animation type 'husarion_ugv_lights::MovingImageAnimation'"),
    ("r20", LED_22, FileKind.LED, "no package husarion_ugv_lights on panther_ros 2.0-2.1"),
])
def test_another_releases_stock_animations_are_refused_with_the_reason(
        ctxs: Any, robot: str, source: Path, kind: FileKind, said: str) -> None:  # noqa: F811
    from panther_ops.core.kinds import FileKindError

    _tmp, cs = ctxs
    with pytest.raises(FileKindError) as exc:
        read_and_plan_push(cs[robot], kind, read_bundle(kind, source))
    assert said in str(exc.value)


def test_lights_deploy_on_a_22_robot_writes_husarion_ugv_types(tmp_path: Path,
                                                                capsys: pytest.CaptureFixture[str]) -> None:
    from PIL import Image

    inv = make_fleet(tmp_path, {"r22": ("husarion-ugv-2.2.2.yaml", {})})
    assert inv.robots["r22"]
    image = tmp_path / "mine.png"
    Image.new("RGBA", (46, 10), (0, 0, 255, 255)).save(image)
    own = tmp_path / "own.yaml"
    own.write_text(PORTABLE.format(image=image).replace("husarion_ugv_lights::", "panther_lights::"))
    capsys.readouterr()
    code = main(["-i", str(tmp_path / "inv.yaml"), "lights", "deploy", str(own), "-r", "r22", "--yes", "--json"])
    out = capsys.readouterr().out
    assert code == 0, out
    doc = json.loads(out)
    assert "husarion_ugv_lights::ImageAnimation" in json.dumps(doc)  # said in the result
    written = [p for p in (tmp_path / "robots/r22/home/husarion/config").rglob("*.yaml")
               if "user_animations" in p.read_text()]
    assert len(written) == 1
    text = written[0].read_text()
    assert "type: 'husarion_ugv_lights::ImageAnimation'" in text and "panther_lights::" not in text
    # the manual's 2.1 example names panther_lights' images, which a 2.2 image does not have
    code = main(["-i", str(tmp_path / "inv.yaml"), "lights", "deploy", str(EXAMPLE), "-r", "r22", "--yes"])
    assert code == 2
    assert "no package panther_lights on husarion_ugv 2.2" in capsys.readouterr().err


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
