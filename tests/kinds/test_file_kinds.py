"""Issue 11: one validator per file kind, used by every path that writes the kind.

`config push` of a bad file says what the kind's dedicated validator says (`bt validate`,
`lights validate`, `shutdown hosts validate`, the controller limits of `config set`); a wheel
type change migrates a custom controller file (demo fleet: the local transport).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

from tests.badinput.test_file_kinds import LIGHTS_PROJ, UNKNOWN_NODE, WH01, _anim
from tests.clirun import run

CTRL_DIR = "robots/panther-01/home/husarion/config/panther_controller/config"


def flat(text: str) -> str:
    return re.sub(r"\s+", " ", text)


def error_lines(text: str) -> list[str]:
    """The `error ...` lines a findings report prints (one per finding; wrapped lines joined)."""
    return [flat(m).strip() for m in re.findall(r"^error (.*?)(?=^\S|\Z)", text, re.M | re.S)]


def finding_lines(text: str) -> list[str]:
    """`<message> (<code>)` of each error finding `lights validate` / `bt validate` print."""
    return [flat(m) for m in re.findall(r"^error (.*?\((?:anim|bt|segment)[a-z-]*\))", flat_lines(text), re.M)]


def flat_lines(text: str) -> str:
    """Lines the terminal width wrapped joined back (a report line starts with its severity)."""
    joined: list[str] = []
    for line in text.splitlines():
        if joined and not re.match(r"^(error|warning) ", line):
            joined[-1] += " " + line.strip()
        else:
            joined.append(line)
    return "\n".join(re.sub(r"\s+", " ", line) for line in joined)


def test_push_says_what_lights_validate_says(demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "anims.yaml"
    bad.write_bytes(_anim(id=5, priority=1, segments="roof"))
    code, out, err = run(capsys, "lights", "validate", str(bad))
    dedicated = finding_lines(out + err)
    assert code == 2 and len(dedicated) == 4
    code, _, err = run(capsys, "-i", str(demo), "config", "push", str(bad), "--as", "user-animations",
                       "-r", "panther-01", "--yes")
    assert code == 2
    for line in dedicated:
        assert f"error {line}" in flat(err) or line in flat(err), line


def test_push_says_what_bt_validate_says(demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "p").mkdir()
    proj = tmp_path / "p" / "My.btproj"
    proj.write_text(LIGHTS_PROJ.replace("{inc}", "lights.xml"))
    (tmp_path / "p" / "lights.xml").write_text(UNKNOWN_NODE)
    code, out, err = run(capsys, "bt", "validate", str(proj))
    dedicated = finding_lines(out + err)
    assert code == 2 and dedicated
    code, _, err = run(capsys, "-i", str(demo), "config", "push", str(proj), "--as", "bt-lights", "-r",
                       "panther-01", "--yes")
    assert code == 2
    for line in dedicated:
        assert line in flat(err), line


def test_push_says_what_shutdown_hosts_validate_says(demo: Path, tmp_path: Path,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "hosts.yaml"
    bad.write_text('hosts:\n  - ip: "10.15.20.5; touch x"\n    username: husarion\n    port: 70000\n')
    code, out, err = run(capsys, "shutdown", "hosts", "validate", str(bad), "--stack", "2.1.1")
    dedicated = [flat(line.split(": ", 1)[1]) for line in error_lines(out + err)]
    assert code == 2 and len(dedicated) == 2
    code, _, err = run(capsys, "-i", str(demo), "config", "push", str(bad), "--as", "shutdown-hosts", "-r",
                       "panther-01", "--yes")
    assert code == 2
    for line in dedicated:
        assert line in flat(err), line


@pytest.mark.parametrize(("key", "value", "old", "new"), [
    ("controller.linear.x.max_velocity", "fast", "max_velocity: 2.0", "max_velocity: fast"),
    ("controller.linear.x.max_velocity", "3.0", "max_velocity: 2.0", "max_velocity: 3.0"),
    ("controller.linear.x.has_velocity_limits", "maybe", "has_velocity_limits: true", "has_velocity_limits: maybe"),
])
def test_push_says_what_config_set_says(demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                        key: str, value: str, old: str, new: str) -> None:
    code, _, err = run(capsys, "-i", str(demo), "config", "set", key, value, "-r", "panther-01", "--yes")
    assert code == 2
    dedicated = flat(err.split("error ", 1)[1].split("hint:")[0]).strip()
    bad = tmp_path / "ctrl.yaml"
    bad.write_text(WH01.replace(old, new, 1))
    code, _, err = run(capsys, "-i", str(demo), "config", "push", str(bad), "--as", "controller", "-r",
                       "panther-01", "--yes")
    assert code == 2
    assert dedicated in flat(err)


def test_force_above_the_limit_warns_and_is_in_the_history(demo: Path, tmp_path: Path,
                                                           capsys: pytest.CaptureFixture[str]) -> None:
    fast = tmp_path / "fast.yaml"
    fast.write_text(WH01.replace("max_velocity: 2.0", "max_velocity: 3.0", 1))
    code, _, err = run(capsys, "-i", str(demo), "config", "push", str(fast), "--as", "controller", "-r",
                       "panther-01", "--yes", "--force")
    assert code == 0, err
    assert "exceeds the WH01 limit of 2.0 m/s (forced)" in err
    code, out, _ = run(capsys, "-i", str(demo), "config", "history", "-r", "panther-01", "--json")
    assert code == 0
    entry = __import__("json").loads(out)["robots"][0]["data"]["history"][-1]
    assert "--force" in entry["command"] and "exceeds the WH01 limit" in entry["summary"]


def test_no_force_for_a_type_error(demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "ctrl.yaml"
    bad.write_text(WH01.replace("max_velocity: 2.0", "max_velocity: fast", 1))
    code, _, err = run(capsys, "-i", str(demo), "config", "push", str(bad), "--as", "controller", "-r",
                       "panther-01", "--yes", "--force")
    assert code == 2 and "is not a number" in err


def test_wheel_type_change_migrates_the_custom_controller(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Finding 7: the WH01 controller file stayed mounted after wheel_type WH02."""
    assert run(capsys, "-i", str(demo), "config", "set", "controller.linear.x.max_velocity", "0.8", "-r",
               "panther-01", "--yes")[0] == 0
    code, _, err = run(capsys, "-i", str(demo), "config", "set", "wheel_type", "WH02", "-r", "panther-01", "--yes")
    assert code == 0, err
    compose = (demo / "robots/panther-01/home/husarion/compose.yaml").read_text()
    assert "controller_config_path:=/config/panther_controller/config/WH02_controller.yaml" in compose
    assert "wheel_type:=WH02" in compose
    doc = yaml.safe_load((demo / CTRL_DIR / "WH02_controller.yaml").read_text())
    params = doc["/**"]["drive_controller"]["ros__parameters"]
    assert params["wheel_radius"] == 0.1016
    assert params["linear"]["x"]["max_velocity"] == 0.8 and params["angular"]["z"]["max_velocity"] == 2.2


def test_apply_migrates_too(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert run(capsys, "-i", str(demo), "config", "set", "controller.angular.z.max_velocity", "3.0", "-r",
               "panther-02", "--yes")[0] == 0
    code, _, err = run(capsys, "-i", str(demo), "apply", "-r", "panther-02", "--yes")  # warehouse: WH02
    assert code == 0, err
    assert "controller.angular.z.max_velocity=3.0 rad/s exceeds the WH02 limit of 2.2 rad/s" in flat(err)
    compose = (demo / "robots/panther-02/home/husarion/compose.yaml").read_text()
    assert "controller_config_path:=/config/panther_controller/config/WH02_controller.yaml" in compose
    text = (demo / "robots/panther-02/home/husarion/config/panther_controller/config/WH02_controller.yaml").read_text()
    assert "wheel_radius: 0.1016" in text


def test_a_custom_wheel_file_refuses_the_change_with_the_fix(demo: Path, tmp_path: Path,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    wheel = tmp_path / "my_wheel.yaml"
    wheel.write_text("wheel_radius: 0.2\nwheel_width: 0.14\nwheel_separation: 0.7\nmass: 3.0\n"  # every key 2.1.1's
                     "inertia: {ixx: 0.02, iyy: 0.03, izz: 0.02}\ninertia_y_offset: 0.0\n"  # URDF reads
                     "mesh_package: panther_description\nfolder_path: meshes/WH01\nmecanum: false\n")
    assert run(capsys, "-i", str(demo), "config", "push", str(wheel), "--as", "wheel", "-r", "panther-01",
               "--yes")[0] == 0
    before = (demo / "robots/panther-01/home/husarion/compose.yaml").read_bytes()
    code, _, err = run(capsys, "-i", str(demo), "config", "set", "wheel_type", "WH02", "-r", "panther-01", "--yes")
    assert code == 2
    assert "wheel_config_path:=/config/panther_description/config/my_wheel.yaml" in err
    assert "config unset wheel_config_path" in err
    assert (demo / "robots/panther-01/home/husarion/compose.yaml").read_bytes() == before


def test_the_manuals_animations_example_is_pushed(demo: Path, tmp_path: Path,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    """Finding 12 through `lights deploy`: accepted, the robot's images reported as unchecked."""
    from tests.manager.test_manager_animations import MANUAL_EXAMPLE

    path = tmp_path / "my_awesome_user_animations.yaml"
    path.write_text(MANUAL_EXAMPLE)
    code, _, err = run(capsys, "-i", str(demo), "lights", "deploy", str(path), "-r", "panther-01", "--dry-run")
    assert code == 0, err
    assert "not checked" in err and "/animations/custom_image.png" in err


def test_registry_has_one_validator_per_kind() -> None:
    from panther_ops.core.kinds import CHECKED, PUSHABLE, FileKind, FileKindError, check_file
    from panther_ops.errors import UsageError

    for kind in CHECKED:
        with pytest.raises(FileKindError):
            check_file(kind, "x", b"\xff\xfe")
    for kind in set(FileKind) - set(CHECKED):  # known (templates), never written: no validator, not pushable
        assert kind not in PUSHABLE
        with pytest.raises(UsageError, match=f"does not write {kind.value} files"):
            check_file(kind, "x", b"a: 1\n")


def test_compose_kind() -> None:
    from panther_ops.core.kinds import FileKind, FileKindError, check_file

    assert check_file(FileKind.COMPOSE, "c.yaml", b"services:\n  a:\n    image: x\n") == []
    with pytest.raises(FileKindError, match="services must be a mapping"):
        check_file(FileKind.COMPOSE, "c.yaml", b"version: 3\n")


def test_a_valid_bt_project_is_pushed_with_its_includes(demo: Path, tmp_path: Path,
                                                       capsys: pytest.CaptureFixture[str]) -> None:
    import shutil

    from tests.badinput.test_file_kinds import TEMPLATES

    proj = tmp_path / "proj"
    proj.mkdir()
    for name in ("PantherLightsBT.btproj", "lights.xml"):
        shutil.copy(TEMPLATES / "behavior_trees" / name, proj / name)
    code, _, err = run(capsys, "-i", str(demo), "config", "push", str(proj / "PantherLightsBT.btproj"), "--as",
                       "bt-lights", "-r", "panther-01", "--yes")
    assert code == 0, err
    robot = demo / "robots/panther-01/home/husarion/config/panther_manager/behavior_trees"
    assert (robot / "lights.xml").read_bytes() == (proj / "lights.xml").read_bytes()
    assert (robot / "PantherLightsBT.btproj").is_file()


def test_user_animations_bring_their_images(demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from PIL import Image

    image = tmp_path / "mine.png"
    Image.new("RGB", (46, 10), (255, 0, 0)).save(image)
    anims = tmp_path / "anims.yaml"
    anims.write_bytes(_anim(image=str(image)))
    code, _, err = run(capsys, "-i", str(demo), "config", "push", str(anims), "--as", "user-animations", "-r",
                       "panther-01", "--yes")
    assert code == 0, err
    pushed = demo / "robots/panther-01/home/husarion/config/panther_lights/animations/mine.png"
    assert pushed.read_bytes() == image.read_bytes()


def test_config_set_force_is_in_the_history(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    import json

    code, _, err = run(capsys, "-i", str(demo), "config", "set", "controller.linear.x.max_velocity", "3.0", "-r",
                       "panther-01", "--yes", "--force")
    assert code == 0, err
    assert "exceeds the WH01 limit of 2.0 m/s (forced)" in err
    code, out, _ = run(capsys, "-i", str(demo), "config", "history", "-r", "panther-01", "--json")
    entry = json.loads(out)["robots"][0]["data"]["history"][-1]
    assert entry["command"] == "config set controller.linear.x.max_velocity 3.0 --force"


def test_unsetting_the_wheel_type_migrates_back(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert run(capsys, "-i", str(demo), "config", "set", "wheel_type", "WH02", "-r", "panther-01", "--yes")[0] == 0
    assert run(capsys, "-i", str(demo), "config", "set", "controller.linear.x.max_velocity", "0.5", "-r",
               "panther-01", "--yes")[0] == 0
    code, _, err = run(capsys, "-i", str(demo), "config", "unset", "wheel_type", "-r", "panther-01", "--yes")
    assert code == 0, err
    compose = (demo / "robots/panther-01/home/husarion/compose.yaml").read_text()
    assert "controller_config_path:=/config/panther_controller/config/WH01_controller.yaml" in compose
    assert "wheel_type:=" not in compose
    doc = yaml.safe_load((demo / CTRL_DIR / "WH01_controller.yaml").read_text())
    params = doc["/**"]["drive_controller"]["ros__parameters"]
    assert params["wheel_radius"] == 0.1825 and "y" not in params["linear"]
    assert params["linear"]["x"]["max_velocity"] == 0.5
