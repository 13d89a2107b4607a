"""Issue 14 item 5: the gamepad's parameters (`config push --as joy2twist`) and the controller's
`cmd_vel_timeout`, on the demo fleet (local transport): panther-01 runs panther_ros 2.1.1,
panther-02 2.0.4 (both with the gamepad_controller service), panther-03 husarion_ugv 2.2.2
(config tree, gamepad launched by the driver)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
import yaml

from panther_ops.core.fleet.pipeline import watch_services
from panther_ops.core.fleet.plan import RobotPlan, Verify
from panther_ops.core.fleet.services import WORKING_DIR_LABEL
from tests.badinput.test_file_kinds import JOY2TWIST
from tests.clirun import run

TEMPLATES = Path(__file__).resolve().parents[2] / "templates"
HOME = "home/husarion"
PUSHED = "config/joy2twist/config/pad.yaml"
TREE = "config/husarion_ugv_bringup/config/joy2twist_panther.yaml"


def home(demo: Path, robot: str) -> Path:
    return demo / "robots" / robot / HOME


def snapshot(demo: Path) -> dict[str, bytes]:
    return {str(p.relative_to(demo)): p.read_bytes() for p in sorted(demo.rglob("*")) if p.is_file()}


def pad(tmp_path: Path, text: str = JOY2TWIST) -> Path:
    path = tmp_path / "pad.yaml"
    path.write_text(text)
    return path


def test_push_mounts_and_passes_the_file_on_2_0_and_2_1(demo: Path, tmp_path: Path,
                                                         capsys: pytest.CaptureFixture[str]) -> None:
    file = pad(tmp_path)
    code, out, _ = run(capsys, "-i", str(demo), "config", "push", str(file), "--as", "joy2twist",
                       "-r", "panther-01", "-r", "panther-02", "--yes", "--json")
    assert code == 0, out
    results = {r["robot"]: r for r in json.loads(out)["robots"]}
    assert {r["outcome"] for r in results.values()} == {"changed"}
    for robot in ("panther-01", "panther-02"):
        assert (home(demo, robot) / PUSHED).read_text() == JOY2TWIST
        compose = yaml.safe_load((home(demo, robot) / "compose.yaml").read_text())
        gamepad = compose["services"]["gamepad_controller"]
        assert "joy2twist_params_file:=/config/joy2twist/config/pad.yaml" in gamepad["command"].split()
        assert f"/{HOME}/{PUSHED}:/config/joy2twist/config/pad.yaml:ro" in gamepad["volumes"]
        driver = next(s for n, s in compose["services"].items() if n != "gamepad_controller"
                      and "panther" in str(s.get("image")))
        assert "joy2twist" not in str(driver)  # the driver service is left alone
    # a second run changes nothing
    before = snapshot(demo)
    code, out, _ = run(capsys, "-i", str(demo), "config", "push", str(file), "--as", "joy2twist",
                       "-r", "panther-01", "-r", "panther-02", "--yes", "--json")
    assert code == 0
    assert {r["outcome"] for r in json.loads(out)["robots"]} == {"ok"}
    assert snapshot(demo) == before


def test_push_writes_the_config_tree_file_on_2_2(demo: Path, tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    compose_before = (home(demo, "panther-03") / "compose.yaml").read_bytes()
    code, out, err = run(capsys, "-i", str(demo), "config", "push", str(pad(tmp_path)), "--as", "joy2twist",
                         "-r", "panther-03", "--yes")
    assert code == 0, out + err
    assert (home(demo, "panther-03") / TREE).read_text() == JOY2TWIST
    assert (home(demo, "panther-03") / "compose.yaml").read_bytes() == compose_before
    assert not (home(demo, "panther-03") / "config/joy2twist").exists()


UPSTREAM_PARAMS = "$(ros2 pkg prefix joy2twist)/share/joy2twist/config/joy2twist_panther.yaml"
UPSTREAM_COMMAND = ('    command: >\n      bash -c "ros2 launch joy2twist gamepad_controller.launch.py '
                    f'joy2twist_params_file:={UPSTREAM_PARAMS} namespace:=panther"\n')
"""The gamepad's command of husarion/panther-docker@2.0.4 and @2.1.1:demo/compose.minimal-setup.yaml."""


def upstream_gamepad(demo: Path, robot: str) -> Path:
    """The robot's compose.yaml with the gamepad's command (its last key) written as upstream's."""
    compose = home(demo, robot) / "compose.yaml"
    text = compose.read_text()
    start = text.index("    command: >\n", text.index("  gamepad_controller:"))
    assert yaml.safe_load(text[start:].replace("    command", "command", 1))  # the command, then nothing
    compose.write_text(text[:start] + UPSTREAM_COMMAND)
    return compose


@pytest.mark.parametrize("robot", ["panther-01", "panther-02"])
def test_push_onto_upstreams_bash_c_command_edits_inside_the_script(
        demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], robot: str) -> None:
    compose = upstream_gamepad(demo, robot)
    before = compose.read_text()
    code, out, err = run(capsys, "-i", str(demo), "config", "push", str(pad(tmp_path)), "--as", "joy2twist",
                         "-r", robot, "--yes", "--json")
    assert code == 0, out + err
    assert json.loads(out)["robots"][0]["outcome"] == "changed"
    assert compose.read_text() == before.replace(
        f"joy2twist_params_file:={UPSTREAM_PARAMS} ", "joy2twist_params_file:=/config/joy2twist/config/pad.yaml ") + (
        "    volumes:\n      - /home/husarion/config/joy2twist/config/pad.yaml:/config/joy2twist/config/pad.yaml:ro\n")
    assert (home(demo, robot) / PUSHED).read_text() == JOY2TWIST
    code, out, err = run(capsys, "-i", str(demo), "config", "pull", "joy2twist", "-r", robot)
    assert code == 0 and out == JOY2TWIST
    assert "joy2twist_params_file:=/config/joy2twist/config/pad.yaml" in err
    code, out, _ = run(capsys, "-i", str(demo), "config", "push", str(pad(tmp_path)), "--as", "joy2twist",
                       "-r", robot, "--yes", "--json")
    assert code == 0 and json.loads(out)["robots"][0]["outcome"] == "ok"


class _Container:
    def __init__(self, cmd: list[str]) -> None:
        self.attrs = {"Config": {"Cmd": cmd, "Labels": {WORKING_DIR_LABEL: "/home/husarion"}},
                      "State": {"Status": "running", "Running": True}, "RestartCount": 0}


class _Client:
    def __init__(self, cmd: list[str]) -> None:
        self.containers = self
        self.cmd = cmd

    def list(self, **_: object) -> list[_Container]:
        return [_Container(self.cmd)]


def test_the_check_after_recreate_looks_inside_the_bash_c_script() -> None:
    """docker's Cmd of upstream's gamepad is ["bash", "-c", "<script>"]: the words are the script's."""
    script = ("ros2 launch joy2twist gamepad_controller.launch.py joy2twist_params_file:=/config/joy2twist/config/"
              "pad.yaml namespace:=panther")
    plan = RobotPlan("panther-01", "joy2twist", [], ("gamepad_controller",), verify=[Verify(
        "gamepad_controller", ("joy2twist_params_file:=/config/joy2twist/config/pad.yaml",),
        (f"joy2twist_params_file:={UPSTREAM_PARAMS}",))])
    assert watch_services(_Client(["bash", "-c", script]), plan, 0, "/home/husarion") is None
    old = script.replace("/config/joy2twist/config/pad.yaml", UPSTREAM_PARAMS)
    assert watch_services(_Client(["bash", "-c", old]), plan, 0, "/home/husarion") == (
        "service gamepad_controller: container command lacks joy2twist_params_file:=/config/joy2twist/config/pad.yaml")
    plan.verify[0] = Verify("gamepad_controller", (), (f"joy2twist_params_file:={UPSTREAM_PARAMS}",))
    assert watch_services(_Client(["bash", "-c", old]), plan, 0, "/home/husarion") == (
        f"service gamepad_controller: container command still has joy2twist_params_file:={UPSTREAM_PARAMS}")


def test_pull_returns_what_was_pushed(demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert run(capsys, "-i", str(demo), "config", "push", str(pad(tmp_path)), "--as", "joy2twist",
               "--all", "--yes")[0] == 0
    for robot, where in (("panther-01", "mounted into gamepad_controller"), ("panther-03", "config tree")):
        code, out, err = run(capsys, "-i", str(demo), "config", "pull", "joy2twist", "-r", robot)
        assert code == 0
        assert out == JOY2TWIST
        assert where in err


@pytest.mark.parametrize("robot", ["panther-01", "panther-02"])
def test_pull_of_the_image_default_gives_the_traced_template_saying_so(demo: Path, robot: str,
                                                                       capsys: pytest.CaptureFixture[str]) -> None:
    """panther_ros 2.0.4 / 2.1.1 (issue 24, finding 9): the gamepad uses its image's
    joy2twist_panther.yaml; a demo robot has no container to read it from, so panther-ops' template
    (husarion/joy2twist's file) is handed out, and the note says which file it stands for and why."""
    code, out, err = run(capsys, "-i", str(demo), "config", "pull", "joy2twist", "-r", robot)
    assert code == 0, err
    assert out == (TEMPLATES / "joy2twist/joy2twist_panther.yaml").read_text()
    assert yaml.safe_load(out)["/**"]["ros__parameters"]["button_index_map"]["dead_man_switch"] == 4
    note = " ".join(err.split())
    assert "husarion/joy2twist@2f8ad45:joy2twist/config/joy2twist_panther.yaml" in note
    assert "/ros2_ws/install/joy2twist/share/joy2twist/config/joy2twist_panther.yaml" in note
    assert "could not be read (a demo robot has no image)" in note


def test_bad_file_is_refused_naming_the_key_and_nothing_changes(demo: Path, tmp_path: Path,
                                                                 capsys: pytest.CaptureFixture[str]) -> None:
    before = snapshot(demo)
    bad = pad(tmp_path, JOY2TWIST.replace("dead_man_switch: 4", "dead_man_switch: LB"))
    code, _, err = run(capsys, "-i", str(demo), "config", "push", str(bad), "--as", "joy2twist", "--all", "--yes")
    assert code == 2
    assert "button_index_map.dead_man_switch='LB' must be an integer" in err
    assert snapshot(demo) == before


def test_push_without_a_gamepad_service_is_refused(demo: Path, tmp_path: Path,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    compose = home(demo, "panther-01") / "compose.yaml"
    doc = yaml.safe_load(compose.read_text())
    del doc["services"]["gamepad_controller"]
    compose.write_text(yaml.safe_dump(doc))
    code, out, err = run(capsys, "-i", str(demo), "config", "push", str(pad(tmp_path)), "--as", "joy2twist",
                         "-r", "panther-01", "--yes")
    assert code != 0
    assert "no gamepad service" in out + err
    assert not (home(demo, "panther-01") / PUSHED).exists()


def test_launch_gamepad_on_2_1_points_at_the_gamepad_service(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, _, err = run(capsys, "-i", str(demo), "config", "set", "launch_gamepad", "true", "-r", "panther-01",
                       "--yes")
    assert code == 2
    assert "gamepad_controller" in err and "--as joy2twist" in " ".join(err.split())


def _timeout(demo: Path, robot: str, package: str) -> float:
    path = home(demo, robot) / f"config/{package}/config/WH01_controller.yaml"
    doc = yaml.safe_load(path.read_text())
    section = next(iter(doc.values()))
    key = "drive_controller" if "drive_controller" in section else "panther_base_controller"
    return float(section[key]["ros__parameters"]["cmd_vel_timeout"])


def test_cmd_vel_timeout_is_set_in_the_controller_file(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = run(capsys, "-i", str(demo), "config", "set", "controller.cmd_vel_timeout", "0.3", "--all",
                         "--yes")
    assert code == 0, out + err
    assert _timeout(demo, "panther-01", "panther_controller") == 0.3
    assert _timeout(demo, "panther-02", "panther_controller") == 0.3
    assert _timeout(demo, "panther-03", "husarion_ugv_controller") == 0.3
    code, out, _ = run(capsys, "-i", str(demo), "config", "get", "controller.cmd_vel_timeout", "--all", "--json")
    assert code == 0
    assert {r["data"]["value"] for r in json.loads(out)["robots"]} == {0.3}


@pytest.mark.parametrize("value,says", [("0", "must be a positive number of seconds"),
                                        ("-0.5", "must be a positive number of seconds"),
                                        ("nan", "must be a finite number"), ("soon", "is not a number")])
def test_cmd_vel_timeout_refuses_what_is_not_positive_seconds(demo: Path, capsys: pytest.CaptureFixture[str],
                                                             value: str, says: str) -> None:
    before = snapshot(demo)
    code, _, err = run(capsys, "-i", str(demo), "config", "set", "--all", "--yes", "--",
                       "controller.cmd_vel_timeout", value)
    assert code == 2
    assert "controller.cmd_vel_timeout" in err and says in err
    assert snapshot(demo) == before


# The node's two forms of the gamepad map, as husarion/joy2twist's own Panther and UGV files
# write them (the keys are theirs; the values here are a user's own)
PANTHER_FORM = """/**:
  ros__parameters:
    linear_velocity_factor: {fast: 1.8, regular: 0.9, slow: 0.4}
    angular_velocity_factor: {fast: 1.5, regular: 0.7, slow: 0.3}
    e_stop:
      present: true
      topic: /panther/hardware/e_stop
      reset_srv: /panther/hardware/e_stop_reset
      trigger_srv: /panther/hardware/e_stop_trigger
    button_index_map:
      axis: {angular_z: 2, linear_x: 1, linear_y: 0}
      dead_man_switch: 4
      fast_mode: 7
      slow_mode: 5
      e_stop_reset: 1
      e_stop_trigger: 2
      enable_e_stop_reset: 6
"""
UGV_FORM = """/**:
  ros__parameters:
    cmd_vel_topic: manual/cmd_vel
    cmd_vel_stamped: false
    linear_velocity_factor: {fast: 1.5, regular: 1.0, slow: 0.3}
    angular_velocity_factor: {fast: 1.5, regular: 0.7, slow: 0.3}
    e_stop: {present: true, topic: hardware/e_stop, reset_srv: hardware/e_stop_reset,
             trigger_srv: hardware/e_stop_trigger}
    input_index_map:
      axis: {angular_z: 'A3', linear_x: 'A1', linear_y: 'A0'}
      dead_man_switch: 'B4'
      fast_mode: '!A5'
      slow_mode: 'B5'
      e_stop_reset: 'B0'
      e_stop_trigger: 'B1'
      enable_e_stop_reset: '!A2'
"""


@pytest.mark.parametrize("text", [PANTHER_FORM, UGV_FORM], ids=["button_index_map", "input_index_map"])
def test_both_forms_of_the_nodes_own_files_are_accepted(text: str) -> None:
    from panther_ops.core.kinds import FileKind, check_file

    assert check_file(FileKind.JOY2TWIST, "pad.yaml", text.encode()) == []


@pytest.mark.parametrize(("text", "named"), [
    (UGV_FORM.replace("'A3'", "'C3'"), "input_index_map.axis.angular_z='C3'"),
    (UGV_FORM.replace("cmd_vel_stamped: false", "cmd_vel_stamped: maybe"), "cmd_vel_stamped='maybe'"),
    (PANTHER_FORM.replace("    button_index_map:", "    input_index_map: {dead_man_switch: 'B4'}\n    button_index_map:"),
     "both given"),
], ids=["bad-input", "bad-stamped", "both-maps"])
def test_the_input_form_is_checked_too(text: str, named: str) -> None:
    from panther_ops.core.kinds import FileKind, FileKindError, check_file

    with pytest.raises(FileKindError, match=re.escape(named)):
        check_file(FileKind.JOY2TWIST, "pad.yaml", text.encode())


def _as_ugv(demo: Path, version: str, gamepad_service: bool) -> Path:
    """panther-03 on husarion_ugv ``version``: with 2.2.0's gamepad_controller service (its
    docker/demo/compose.hardware.yaml: ~/config/common/joy2twist.yaml at /joy2twist.yaml), or without."""
    compose = home(demo, "panther-03") / "compose.yaml"
    # the 2.2.0 and 2.2.1 images do not copy joy2twist_panther.yaml into ~/config (husarion_ugv_ros@2.2.1:
    # docker/utils/update_config_directory.sh); the demo's 2.2.2 tree has it
    (home(demo, "panther-03") / TREE).unlink(missing_ok=True)
    doc = yaml.safe_load(compose.read_text())
    driver = doc["services"]["husarion_ugv_ros"]
    driver["image"] = f"husarion/husarion-ugv:humble-{version}-20250331"
    driver["command"] = "ros2 launch husarion_ugv_bringup bringup.launch.py common_dir_path:=/config"
    if gamepad_service:
        doc["services"]["gamepad_controller"] = {
            "image": "husarion/joy2twist:humble-1.0.0-20250131", "container_name": "gamepad_controller",
            "volumes": ["/home/husarion/config/common/joy2twist.yaml:/joy2twist.yaml"],
            "command": "ros2 launch joy2twist gamepad_controller.launch.py joy2twist_params_file:=/joy2twist.yaml"}
    compose.write_text(yaml.safe_dump(doc))
    return compose


def test_on_2_2_0_and_2_2_1_the_gamepad_service_reads_its_mounted_file(
        demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    compose = _as_ugv(demo, "2.2.1", gamepad_service=True)
    before = compose.read_bytes()
    code, out, err = run(capsys, "-i", str(demo), "config", "push", str(pad(tmp_path)), "--as", "joy2twist",
                         "-r", "panther-03", "--yes", "--json")
    assert code == 0, out + err
    r = json.loads(out)["robots"][0]
    assert r["data"]["robot_path"] == "/home/husarion/config/common/joy2twist.yaml"
    assert (home(demo, "panther-03") / "config/common/joy2twist.yaml").read_text() == JOY2TWIST
    assert compose.read_bytes() == before  # the service already reads that file
    assert not (home(demo, "panther-03") / TREE).exists()
    code, out, err = run(capsys, "-i", str(demo), "config", "pull", "joy2twist", "-r", "panther-03")
    assert code == 0 and out == JOY2TWIST and "mounted into gamepad_controller" in err


def test_on_2_2_1_without_a_gamepad_service_the_driver_does_not_launch_one(
        demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    _as_ugv(demo, "2.2.1", gamepad_service=False)
    before = snapshot(demo)
    code, _, err = run(capsys, "-i", str(demo), "config", "push", str(pad(tmp_path)), "--as", "joy2twist",
                       "-r", "panther-03", "--yes")
    assert code == 2
    text = " ".join(err.split())
    assert "launch_gamepad came with husarion_ugv 2.2.2" in text and "gamepad_controller" in text
    assert snapshot(demo) == before
    code, _, err = run(capsys, "-i", str(demo), "config", "set", "launch_gamepad", "true", "-r", "panther-03",
                       "--yes")
    assert code == 2 and "gamepad_controller" in err


def test_on_2_2_2_a_joy2twist_params_file_on_bringup_is_said_to_do_nothing(
        demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    compose = home(demo, "panther-03") / "compose.yaml"
    compose.write_text(compose.read_text().replace("launch_gamepad:=true",
                                                   "launch_gamepad:=true joy2twist_params_file:=/x.yaml"))
    code, out, err = run(capsys, "-i", str(demo), "config", "push", str(pad(tmp_path)), "--as", "joy2twist",
                         "-r", "panther-03", "--yes", "--json")
    assert code == 0, out + err
    r = json.loads(out)["robots"][0]
    assert any("has no effect" in w for w in r["warnings"]), r
    assert (home(demo, "panther-03") / TREE).read_text() == JOY2TWIST
