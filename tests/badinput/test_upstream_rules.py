"""Bad-input corpus for the rules of each release (issue 24, finding 1): a file another release's
robot would load, refused on this one with the reason, by every command that carries it; exit 2,
every demo file byte-identical.

Robots of the demo fleet: panther-01 panther_ros 2.1.1, panther-02 2.0.4, panther-03 husarion_ugv 2.2.2.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.badinput.harness import Case, check_refused

TEMPLATES = Path(__file__).resolve().parents[2] / "templates"
WHEEL_21 = (TEMPLATES / "config/panther-2.1/panther_description/config/WH01.yaml").read_text()
WHEEL_22 = (TEMPLATES / "config/husarion-ugv-2.2/husarion_ugv_description/config/WH01.yaml").read_text()
LED_22 = (TEMPLATES / "config/husarion-ugv-2.2/husarion_ugv_lights/config/panther_animations.yaml").read_text()
LED_21 = (TEMPLATES / "config/panther-2.1/panther_lights/config/led_config.yaml").read_text()
USER = """user_animations:
  - id: 21
    name: MINE
    priority: {priority}
    animations:
      - type: {type}
        segments: all
        animation:
          image: {image}
          duration: 2
"""
UGV_IMAGE = "$(find husarion_ugv_lights)/animations/panther/ready_front.png"


def _user(priority: int = 3, type_: str = "husarion_ugv_lights::ImageAnimation", image: str = UGV_IMAGE) -> bytes:
    return USER.format(priority=priority, type=type_, image=image).encode()


def _without(text: str, key: str) -> bytes:
    return "".join(line + "\n" for line in text.splitlines() if not line.startswith(key + ":")).encode()


def _push(kind: str, cid: str, robot: str, content: bytes, names: list[str]) -> Case:
    return Case(f"push-{kind}-{cid}-{robot}", ["config", "push", "{tmp}/mine.yaml", "--as", kind, "-r", robot,
                                               "--yes"], ["mine.yaml", *names], files={"mine.yaml": content})


CASES: list[Case] = [
    # wheel files: the keys the release's URDF reads
    _push("wheel", "22-file-on-21", "panther-01", WHEEL_22.encode(), ["wheel_separation is required on panther_ros 2.1.1"]),
    _push("wheel", "21-file-on-22", "panther-03", WHEEL_21.encode(),
          ["mount_point_offset is required on husarion_ugv 2.2.2", "husarion_ugv_description/urdf/common/wheel.urdf.xacro"]),
    _push("wheel", "no-width", "panther-02", _without(WHEEL_21, "wheel_width"),
          ["wheel_width is required on panther_ros 2.0.4"]),
    _push("wheel", "no-mass", "panther-03", _without(WHEEL_22, "mass"), ["mass is required on husarion_ugv 2.2.2"]),
    _push("wheel", "neither", "panther-03", _without(_without(WHEEL_22, "mount_point_offset").decode(),
                                                     "wheel_separation"),
          ["wheel_separation (panther_ros 2.0-2.1) or mount_point_offset (husarion_ugv 2.2) is required"]),
    # animations: the release's plugins, priorities and stock images
    _push("led", "22-stock-on-21", "panther-01", LED_22.encode(),
          ["unknown animation type 'husarion_ugv_lights::MovingImageAnimation' on panther_ros 2.0-2.1"]),
    _push("led", "21-stock-on-22", "panther-03", LED_21.encode(),
          ["unknown animation type 'panther_lights::ChargingAnimation' on husarion_ugv 2.2"]),
    _push("led", "priority-9", "panther-03", LED_22.replace("priority: 0", "priority: 9", 1).encode(),
          ["priority 9 is not 0, 1, 2 or 3 (husarion_ugv 2.2)"]),
]
for cmd in (["config", "push", "{tmp}/mine.yaml", "--as", "user-animations"], ["lights", "deploy", "{tmp}/mine.yaml"]):
    for cid, robot, content, names in (
            ("priority-0", "panther-03", _user(priority=0),
             ["priority 0 is reserved for system animations on husarion_ugv 2.2", "priority 1, 2 or 3"]),
            ("priority-1", "panther-01", _user(priority=1, type_="panther_lights::ImageAnimation",
                                               image="$(find panther_lights)/animations/strip01_red.png"),
             ["priority 1 is reserved for system animations on panther_ros 2.0-2.1"]),
            ("image-not-shipped", "panther-03",
             _user(image="$(find husarion_ugv_lights)/animations/panther/triangle01_red.png"),
             ["triangle01_red.png is not one of the images husarion_ugv_lights ships", "ready_front.png"]),
            ("package-of-21-on-22", "panther-03",
             _user(image="$(find panther_lights)/animations/strip01_red.png"),
             ["there is no package panther_lights on husarion_ugv 2.2"]),
            ("moving-on-20", "panther-02", _user(type_="husarion_ugv_lights::MovingImageAnimation"),
             ["unknown animation type 'husarion_ugv_lights::MovingImageAnimation' on panther_ros 2.0-2.1"]),
            ("charging-on-22", "panther-03", _user(type_="panther_lights::ChargingAnimation"),
             ["unknown animation type 'panther_lights::ChargingAnimation' on husarion_ugv 2.2"])):
        CASES.append(Case(f"{cmd[0]}-{cmd[1]}-{cid}-{robot}", [*cmd, "-r", robot, "--yes"], ["mine.yaml", *names],
                          files={"mine.yaml": content}))
# lights validate takes the release to check for
CASES += [
    Case("lights-validate-stack-word", ["lights", "validate", "{tmp}/mine.yaml", "--stack", "two"],
         ["--stack 'two' is not a version"], files={"mine.yaml": _user()}),
    Case("lights-validate-stack-21", ["lights", "validate", "{tmp}/mine.yaml", "--stack", "2.1.1"],
         ["mine.yaml", "animations refused (1 error,"], files={"mine.yaml": _user()}),  # the finding: on stdout
]
# BT projects: Parallel and Delay with ports BehaviorTree.CPP refuses
PROJECT = '<?xml version="1.0"?>\n<root BTCPP_format="4">\n  <include path="lights.xml"/>\n</root>\n'
for cid, node, names in (
        ("parallel-word", '<Parallel success_count="all"><AlwaysSuccess/></Parallel>',
         ["<Parallel> port 'success_count'", "expected int"]),
        ("parallel-unreachable", '<Parallel success_count="3"><AlwaysSuccess/></Parallel>',
         ["<Parallel> success_count=3 with 1 children: it can never succeed"]),
        ("delay-no-msec", "<Delay><AlwaysSuccess/></Delay>", ["<Delay> needs port 'delay_msec'"])):
    lights = f'<?xml version="1.0"?>\n<root BTCPP_format="4">\n<BehaviorTree ID="Lights">{node}</BehaviorTree>\n</root>\n'
    for robot in ("panther-01", "panther-03"):
        CASES.append(Case(f"push-bt-lights-{cid}-{robot}", ["config", "push", "{tmp}/proj/My.btproj", "--as",
                                                            "bt-lights", "-r", robot, "--yes"], names,
                          files={"proj/My.btproj": PROJECT.encode(), "proj/lights.xml": lights.encode()}))
    CASES.append(Case(f"bt-validate-{cid}", ["bt", "validate", "{tmp}/proj/My.btproj"],
                      ["My.btproj", "BT project refused (1 error,"],  # the finding itself: on stdout
                      files={"proj/My.btproj": PROJECT.encode(), "proj/lights.xml": lights.encode()}))


@pytest.mark.parametrize("case", CASES, ids=str)
def test_refused(case: Case, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                 monkeypatch: pytest.MonkeyPatch) -> None:
    check_refused(case, tmp_path, capsys, monkeypatch)


def test_case_ids_are_unique() -> None:
    assert len({c.id for c in CASES}) == len(CASES)
