"""ComposeFile: driver service, launch command forms, image, volumes, environment, services."""

from __future__ import annotations

from pathlib import Path

import pytest

from panther_ops.core.robot.compose import ComposeError, ComposeFile, Volume, image_repo, is_driver_image
from panther_ops.core.robot.launchcmd import CommandForm
from panther_ops.core.yaml.diff import changed_lines
from panther_ops.core.yaml.document import DocumentError
from panther_ops.errors import InputError, RemoteStateError, UsageError

ROOT = Path(__file__).resolve().parents[2]
C20 = (ROOT / "templates/compose/panther-2.0.4.yaml").read_text()
C21 = (ROOT / "templates/compose/panther-2.1.1.yaml").read_text()
C22 = (ROOT / "templates/compose/husarion-ugv-2.2.2.yaml").read_text()
INPUTS = ROOT / "tests/golden/inputs"


def compose(text: str) -> ComposeFile:
    return ComposeFile.parse(text, "/home/husarion/compose.yaml")


def test_driver_service_and_stack_of_the_templates() -> None:
    for text, service, version in ((C20, "panther_ros", (2, 0, 4)), (C21, "panther_ros", (2, 1, 1)),
                                   (C22, "husarion_ugv_ros", (2, 2, 2))):
        c = compose(text)
        assert c.driver_service() == service
        assert c.stack().version == version
        assert c.driver_image.startswith("husarion/")


def test_driver_found_by_image_when_renamed() -> None:
    c = compose("services:\n  robot:\n    image: registry.local:5000/husarion/panther:humble-2.1.1-20240828\n"
                "  gps:\n    image: husarion/nmea-gps:humble-2.0.1\n")
    assert c.driver_service() == "robot"
    assert image_repo("registry.local:5000/husarion/panther:humble-2.1.1") == "husarion/panther"
    assert not is_driver_image("husarion/panther-gazebo:humble-2.1.1")


def test_no_driver_service_is_a_clear_error() -> None:
    c = compose("services:\n  gps:\n    image: husarion/nmea-gps:humble\n")
    with pytest.raises(ComposeError) as err:
        c.driver_service()
    assert "panther_ros or husarion_ugv_ros" in str(err.value) and "services here: gps" in str(err.value)
    assert isinstance(err.value, InputError)


def test_several_driver_images_are_ambiguous() -> None:
    c = compose("services:\n  a:\n    image: husarion/panther:humble-2.1.1\n  b:\n    image: husarion/panther:humble-2.0.4\n")
    with pytest.raises(ComposeError, match="several services"):
        c.driver_service()


def test_not_a_mapping_and_bad_yaml() -> None:
    with pytest.raises(ComposeError):
        compose("- a\n")
    with pytest.raises(DocumentError):
        compose("services: [\n")


def test_unsupported_stack_from_image() -> None:
    c = compose("services:\n  panther_ros:\n    image: husarion/husarion-ugv:kilted-2.4.0-20260101\n")
    with pytest.raises(RemoteStateError, match=r"kilted 2\.4\.0"):
        c.stack()
    jazzy = compose("services:\n  husarion_ugv_ros:\n    image: husarion/husarion-ugv:jazzy-2.3.2-20260622\n")
    assert jazzy.stack().version_str == "2.3.2" and jazzy.stack().jazzy


# ------------------------------------------------------------------ command


def test_command_forms_are_parsed() -> None:
    string = compose(C20).command()
    assert (string.form, string.package, string.launch_file, string.args) == (
        CommandForm.STRING, "panther_bringup", "bringup.launch.py", {"namespace": "panther"})
    folded = compose((INPUTS / "compose-2.1-folded-command.yaml").read_text()).command()
    assert folded.form is CommandForm.BLOCK and folded.style == ">"
    assert folded.args["led_config_file"] == "$(find panther_lights)/config/led_config.yaml"
    assert folded.args["launch_nmea_gps"] == "True"
    flow = compose((INPUTS / "compose-2.1-list-command.yaml").read_text()).command()
    assert flow.form is CommandForm.LIST and flow.style == "flow" and flow.args["wheel_type"] == "WH02"
    block = compose((INPUTS / "compose-2.1-block-list-command.yaml").read_text()).command()
    assert block.form is CommandForm.LIST and block.style == "block" and list(block.args) == ["namespace", "use_ekf"]
    gamepad = compose(C21).command("gamepad_controller")
    assert gamepad.args["joy2twist_params_file"].startswith("$(ros2 pkg prefix joy2twist)/share")


def test_args_property_is_the_drivers() -> None:
    assert compose(C22).args == {"common_dir_path": "/config", "launch_gamepad": "true"}


def test_command_errors() -> None:
    c = compose("services:\n  panther_ros:\n    image: husarion/panther:humble-2.1.1-20240828\n")
    with pytest.raises(ComposeError, match="has no command"):
        c.command()
    c = compose("services:\n  panther_ros:\n    image: husarion/panther:humble-2.1.1-20240828\n"
                "    command: bash -c 'exec ros2 launch panther_bringup bringup.launch.py'\n")
    with pytest.raises(InputError, match="not `ros2 launch"):
        c.set_arg("wheel_type", "WH02")
    c = compose("services:\n  panther_ros:\n    image: husarion/panther:humble-2.1.1-20240828\n"
                "    command: bash -c '. /x.sh && ros2 launch panther_bringup bringup.launch.py'\n")
    with pytest.raises(InputError, match="more than one command"):
        c.set_arg("wheel_type", "WH02")
    with pytest.raises(UsageError):
        compose(C21).set_arg("bad name", "x")


def test_set_arg_in_quoted_string_keeps_the_quotes() -> None:
    text = ('services:\n  panther_ros:\n    image: husarion/panther:humble-2.1.1-20240828\n'
            '    command: "ros2 launch panther_bringup bringup.launch.py wheel_type:=WH01"\n')
    c = compose(text)
    c.set_arg("wheel_type", "WH04")
    c.set_arg("namespace", "p")
    assert c.text().endswith('    command: "ros2 launch panther_bringup bringup.launch.py wheel_type:=WH04 namespace:=p"\n')


def test_plain_command_becomes_quoted_when_it_must() -> None:
    c = compose(C21)
    c.set_arg("namespace", "a #b")
    assert "command: 'ros2 launch panther_bringup bringup.launch.py namespace:=''a #b'''" in c.text()
    assert c.args["namespace"] == "a #b"
    assert any("quoted" in n for n in c.notes)


def test_raw_word_is_written_verbatim() -> None:
    c = compose(C21)
    c.set_arg("params", "$(ros2 pkg prefix x)/p.yaml", raw=True)
    assert "params:=$(ros2 pkg prefix x)/p.yaml" in c.text()
    with pytest.raises(UsageError):
        c.set_arg("params", "a b", raw=True)


def test_repeated_argument_last_one_wins_and_unset_removes_all() -> None:
    text = ("services:\n  panther_ros:\n    image: husarion/panther:humble-2.1.1-20240828\n"
            "    command: ros2 launch panther_bringup bringup.launch.py a:=1 b:=2 a:=3\n")
    c = compose(text)
    assert c.args == {"b": "2", "a": "3"}
    c.set_arg("a", "4")
    assert c.text().endswith("a:=1 b:=2 a:=4\n")
    assert c.unset_arg("a") is True
    assert c.text().endswith("bringup.launch.py b:=2\n")
    assert c.unset_arg("a") is False


# ------------------------------------------------------------------ image


def test_set_image_validates_driver_images() -> None:
    c = compose(C21)
    with pytest.raises(UsageError, match="not a release panther-ops knows"):
        c.set_image("husarion/husarion-ugv:jazzy-2.4.0-20270101")
    assert c.set_image_tag("humble-2.1.2-20241125") and c.driver_image == "husarion/panther:humble-2.1.2-20241125"
    assert c.set_image("husarion/husarion-ugv:jazzy-2.4.0-20270101", force=True)
    assert c.set_image("husarion/joy2twist:humble-1.0.1", "gamepad_controller")
    assert c.image("gamepad_controller") == "husarion/joy2twist:humble-1.0.1"


# ------------------------------------------------------------------ volumes


def test_list_volumes_short_and_long() -> None:
    vols = compose(C21).list_volumes()
    assert vols[1] == Volume("/sys/bus/iio/devices", "/sys/bus/iio/devices", True, "ro", False, 1)
    assert vols[1].spec() == "/sys/bus/iio/devices:/sys/bus/iio/devices:ro"
    long = compose((INPUTS / "compose-2.1-block-list-command.yaml").read_text()).list_volumes()
    assert [v.long_syntax for v in long] == [True, True] and long[1].read_only


def test_add_volume_is_idempotent_and_updates_in_place() -> None:
    c = compose(C21)
    assert c.add_volume("~/.ssh/id_rsa", "/root/.ssh/id_rsa") is False
    assert c.add_volume("/home/husarion/.ssh/id_ed25519", "/root/.ssh/id_rsa", ro=True) is True
    assert changed_lines(c.diff()) == [
        "-      - ~/.ssh/id_rsa:/root/.ssh/id_rsa",
        "+      - /home/husarion/.ssh/id_ed25519:/root/.ssh/id_rsa:ro",
    ]
    with pytest.raises(UsageError):
        c.add_volume("/x", "relative/path")
    assert c.remove_volume("/nowhere") is False


def test_volumes_created_when_the_service_has_none() -> None:
    c = compose(C21)
    c.add_volume("/dev/shm", "/dev/shm", service="gamepad_controller")
    assert "    command: >" in c.text() and c.list_volumes("gamepad_controller")[0].target == "/dev/shm"


# ------------------------------------------------------------------ environment


def test_environment_forms() -> None:
    assert compose(C21).environment()["ROBOT_NAMESPACE"] == "panther"
    mapping = compose((INPUTS / "compose-2.1-block-list-command.yaml").read_text())
    assert mapping.environment() == {"RMW_IMPLEMENTATION": "rmw_cyclonedds_cpp", "ROS_DOMAIN_ID": "7",
                                     "ROBOT_NAMESPACE": "panther"}
    assert compose(C22).environment() == {}
    assert compose(C22).env_files() == ["/home/husarion/config/common/.env"]


def test_set_env_override_vs_shared() -> None:
    c = compose(C21)
    c.set_env("ROBOT_NAMESPACE", "p1")
    assert c.get_env("ROBOT_NAMESPACE") == "p1"
    assert c.get_env("ROBOT_NAMESPACE", "gamepad_controller") == "panther"
    c2 = compose(C21)
    c2.set_env("ROBOT_NAMESPACE", "p1", shared=True)
    assert c2.get_env("ROBOT_NAMESPACE", "gamepad_controller") == "p1"
    assert changed_lines(c2.diff()) == ["-    - ROBOT_NAMESPACE=panther", "+    - ROBOT_NAMESPACE=p1"]
    with pytest.raises(UsageError):
        c2.set_env("BAD-NAME", "1")


def test_unset_env() -> None:
    c = compose((INPUTS / "compose-2.1-block-list-command.yaml").read_text())
    assert c.unset_env("ROS_DOMAIN_ID") is True
    assert "ROS_DOMAIN_ID" not in c.environment()
    assert c.unset_env("ROS_DOMAIN_ID") is False
    c2 = compose(C21)
    assert c2.unset_env("ROBOT_NAMESPACE", shared=True) is True
    assert "ROBOT_NAMESPACE" not in c2.environment("gamepad_controller")


# ------------------------------------------------------------------ services


def test_add_and_remove_service() -> None:
    c = compose(C21)
    gps = {"image": "husarion/nmea-gps:humble-2.0.1-20240617", "container_name": "nmea_gps"}
    assert c.add_service("nmea_gps", gps, merge="common-config") is True
    assert c.service("nmea_gps")["restart"] == "always"
    assert c.add_service("nmea_gps", gps, merge="common-config") is False
    with pytest.raises(UsageError, match="already exists"):
        c.add_service("nmea_gps", {"image": "other"})
    with pytest.raises(UsageError, match="no anchor"):
        c.add_service("x", gps, merge="nope")
    with pytest.raises(UsageError, match="invalid"):
        c.add_service("bad name", gps)
    assert c.remove_service("nmea_gps") is True
    assert c.text() == C21
    assert c.remove_service("nmea_gps") is False


def test_unknown_service() -> None:
    with pytest.raises(ComposeError, match="no service 'nope'"):
        compose(C21).image("nope")


def test_multiline_commands() -> None:
    quoted = ('services:\n  panther_ros:\n    image: husarion/panther:humble-2.1.1-20240828\n'
              '    command: "ros2 launch panther_bringup\n      bringup.launch.py a:=1"\n')
    c = compose(quoted)
    assert c.command().form is CommandForm.STRING
    c.set_arg("a", "2")  # a quoted scalar is rewritten as one line (documented)
    assert c.text().endswith('    command: "ros2 launch panther_bringup bringup.launch.py a:=2"\n')
    plain = ('services:\n  panther_ros:\n    image: husarion/panther:humble-2.1.1-20240828\n'
             '    command: ros2 launch panther_bringup\n      bringup.launch.py a:=1\n')
    c = compose(plain)
    assert c.command().form is CommandForm.BLOCK
    c.set_arg("b", "2")
    assert c.text().endswith("      bringup.launch.py a:=1\n      b:=2\n")
    c.unset_arg("b")
    assert c.text() == plain


# ------------------------------------------------ bash -c "ros2 launch ..." (husarion/panther-docker's gamepad)

PARAMS = "$(ros2 pkg prefix joy2twist)/share/joy2twist/config/joy2twist_panther.yaml"
UPSTREAM_GAMEPAD = (f'bash -c "ros2 launch joy2twist gamepad_controller.launch.py joy2twist_params_file:={PARAMS} '
                    'namespace:=panther"')
"""The gamepad's command of husarion/panther-docker@2.0.4 and @2.1.1:demo/compose.minimal-setup.yaml."""


def test_the_templates_run_the_gamepad_as_upstream_does() -> None:
    for text in (C20, C21):
        c = compose(text)
        assert c.service("gamepad_controller")["command"] == UPSTREAM_GAMEPAD + "\n"
        cmd = c.command("gamepad_controller")
        assert cmd.form is CommandForm.BLOCK and cmd.shell == ("bash", "-c")
        assert cmd.argv[:2] == ("bash", "-c") and cmd.words[:4] == ("ros2", "launch", "joy2twist",
                                                                    "gamepad_controller.launch.py")
        assert cmd.args == {"joy2twist_params_file": PARAMS, "namespace": "panther"}


def test_an_argument_is_edited_inside_the_script_and_restored_byte_for_byte() -> None:
    c = compose(C21)
    assert c.set_arg("joy2twist_params_file", "/config/joy2twist/config/pad.yaml", "gamepad_controller") is True
    assert c.set_arg("use_sim_time", "True", "gamepad_controller") is True
    assert changed_lines(c.diff()) == [
        f"-      {UPSTREAM_GAMEPAD}",
        '+      bash -c "ros2 launch joy2twist gamepad_controller.launch.py joy2twist_params_file:=/config/joy2twist/'
        'config/pad.yaml namespace:=panther use_sim_time:=True"']
    assert c.command("gamepad_controller").args["joy2twist_params_file"] == "/config/joy2twist/config/pad.yaml"
    assert c.unset_arg("use_sim_time", "gamepad_controller") is True
    assert c.set_arg("joy2twist_params_file", PARAMS, "gamepad_controller") is True  # the file's own word again
    assert c.text() == C21
    assert c.set_arg("namespace", "panther", "gamepad_controller") is False


@pytest.mark.parametrize("value", ['/config/a"b.yaml', "$(find joy2twist)/x.yaml", "/config/`id`.yaml",
                                   "/config/a\\b.yaml", "/config/it's.yaml"])
def test_a_value_the_scripts_quotes_cannot_hold_is_refused_and_nothing_changes(value: str) -> None:
    c = compose(C20)
    with pytest.raises(InputError) as exc:
        c.set_arg("joy2twist_params_file", value, "gamepad_controller")
    assert f"joy2twist_params_file: the value {value!r}" in exc.value.message
    assert "double-quoted bash -c script" in exc.value.message and ":42 [command]" in exc.value.message
    assert c.text() == C20 and not c.changed


@pytest.mark.parametrize(("command", "after"), [
    ('command: bash -c "ros2 launch panther_bringup bringup.launch.py wheel_type:=WH01"\n',
     'command: bash -c "ros2 launch panther_bringup bringup.launch.py wheel_type:=WH02 use_ekf:=False"\n'),
    ("command: bash -c 'ros2 launch panther_bringup bringup.launch.py wheel_type:=WH01'\n",
     "command: bash -c 'ros2 launch panther_bringup bringup.launch.py wheel_type:=WH02 use_ekf:=False'\n"),
    ('command: ["bash", "-c", "ros2 launch panther_bringup bringup.launch.py wheel_type:=WH01"]\n',
     'command: ["bash", "-c", "ros2 launch panther_bringup bringup.launch.py wheel_type:=WH02 use_ekf:=False"]\n'),
    ("command:\n      - bash\n      - -c\n      - ros2 launch panther_bringup bringup.launch.py wheel_type:=WH01\n",
     "command:\n      - bash\n      - -c\n      - ros2 launch panther_bringup bringup.launch.py wheel_type:=WH02 "
     "use_ekf:=False\n"),
    ('command: >\n      bash -c "ros2 launch panther_bringup bringup.launch.py\n      wheel_type:=WH01"\n',
     'command: >\n      bash -c "ros2 launch panther_bringup bringup.launch.py\n      wheel_type:=WH02\n'
     '      use_ekf:=False"\n'),
])
def test_every_form_of_a_bash_c_driver_command_is_read_and_edited(command: str, after: str) -> None:
    head = "services:\n  panther_ros:\n    image: husarion/panther:humble-2.1.1-20240828\n    "
    c = compose(head + command)
    assert c.args == {"wheel_type": "WH01"}
    assert c.command().shell == ("bash", "-c")
    assert c.set_arg("wheel_type", "WH02") and c.set_arg("use_ekf", "False")
    assert c.text() == head + after
    assert c.args == {"wheel_type": "WH02", "use_ekf": "False"}
    assert c.unset_arg("use_ekf") and c.set_arg("wheel_type", "WH01")
    assert c.text() == head + command


def test_a_script_of_several_commands_is_refused() -> None:
    # a more indented line keeps its line break in a folded block: the shell runs two commands
    c = compose("services:\n  panther_ros:\n    image: husarion/panther:humble-2.1.1-20240828\n    command: >\n"
                '      bash -c "ros2 launch panther_bringup bringup.launch.py\n        wheel_type:=WH01"\n')
    with pytest.raises(InputError, match=r"compose.yaml:4 \[command\]: the bash -c script holds '\\n'"):
        c.set_arg("wheel_type", "WH02")
