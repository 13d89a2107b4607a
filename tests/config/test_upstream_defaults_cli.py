"""On the demo fleet: the robot's own defaults go back through `config push`, the 2.2.2 robot's
config tree is the one the image lays out, and `config pull` says where a file comes from
(issue 24, findings 1 and 5)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from panther_ops.cli.app import main

TREE = "robots/panther-03/home/husarion/config"
# husarion_ugv_ros@2.2.2:docker/utils/update_config_directory.sh, for ROBOT_MODEL_NAME=panther: what it copies
# into /config (~/config on the host): the bringup's joy2twist_panther.yaml, husarion_ugv_controller's config/
# directory (WH01, WH02, WH04, WH05 controllers), user_animations.yaml and panther_animations.yaml, the
# localization config/ directory without nmea_navsat.yaml, lights.xml and LightsBT.btproj, shutdown_hosts.yaml,
# components.yaml
UPDATE_CONFIG_DIRECTORY_222 = {
    "husarion_ugv_bringup/config/joy2twist_panther.yaml",
    "husarion_ugv_controller/config/WH01_controller.yaml", "husarion_ugv_controller/config/WH02_controller.yaml",
    "husarion_ugv_controller/config/WH04_controller.yaml", "husarion_ugv_controller/config/WH05_controller.yaml",
    "husarion_ugv_lights/config/user_animations.yaml", "husarion_ugv_lights/config/panther_animations.yaml",
    "husarion_ugv_localization/config/enu_localization.yaml",
    "husarion_ugv_localization/config/enu_localization_with_gps.yaml",
    "husarion_ugv_localization/config/relative_localization.yaml",
    "husarion_ugv_localization/config/relative_localization_with_gps.yaml",
    "husarion_ugv_manager/behavior_trees/lights.xml", "husarion_ugv_manager/behavior_trees/LightsBT.btproj",
    "husarion_ugv_manager/config/shutdown_hosts.yaml", "husarion_ugv_description/config/components.yaml",
}


@pytest.fixture()
def demo(tmp_path: Path) -> Path:
    assert main(["demo", "init", "--dest", str(tmp_path / "demo")]) == 0
    return tmp_path / "demo"


def run(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    capsys.readouterr()
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


def test_the_222_robots_config_tree_is_what_the_image_copies(demo: Path) -> None:
    tree = demo / TREE
    files = {p.relative_to(tree).as_posix() for p in tree.rglob("*") if p.is_file()}
    assert files - {"common/.env"} == UPDATE_CONFIG_DIRECTORY_222


@pytest.mark.parametrize(("kind", "name"), [("led", "panther_animations.yaml"), ("wheel", "WH01.yaml"),
                                            ("user-animations", "user_animations.yaml"),
                                            ("components", "components.yaml")])
def test_the_robots_own_default_goes_back(demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                          kind: str, name: str) -> None:
    pulled = tmp_path / name
    code, _, err = run(capsys, "-i", str(demo), "config", "pull", kind, "-r", "panther-03", "-o", str(pulled))
    assert code == 0, err
    code, _, err = run(capsys, "-i", str(demo), "config", "push", str(pulled), "--as", kind, "-r", "panther-03",
                       "--yes")
    assert code == 0, err


def test_the_robots_own_lights_project_goes_back(demo: Path, tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    """The 2.2.2 Lights project (Parallel, Delay: standard BehaviorTree.CPP v4 nodes) as the tree holds it."""
    project = tmp_path / "proj"
    project.mkdir()
    code, _, err = run(capsys, "-i", str(demo), "config", "pull", "bt-lights", "-r", "panther-03", "-o",
                       str(project / "LightsBT.btproj"))
    assert code == 0, err
    assert (project / "lights.xml").read_bytes() == (demo / TREE / "husarion_ugv_manager/behavior_trees/lights.xml"
                                                     ).read_bytes()  # pulled with the project
    code, _, err = run(capsys, "-i", str(demo), "config", "push", str(project / "LightsBT.btproj"), "--as",
                       "bt-lights", "-r", "panther-03", "--yes")
    assert code == 0, err


def _source(capsys: pytest.CaptureFixture[str], demo: Path, kind: str, robot: str) -> str:
    code, out, err = run(capsys, "-i", str(demo), "config", "pull", kind, "-r", robot, "--json")
    assert code == 0, err
    return str(json.loads(out)["robots"][0]["data"]["source"])


def test_pull_says_where_a_template_comes_from(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # a demo robot has no image: the template stands in, and says which upstream file it is written from
    said = _source(capsys, demo, "led", "panther-01")
    assert "written from panther_ros@2.1.1:panther_lights/config/led_config.yaml" in said
    assert "the image's file is panther_ros@2.1.1:panther_lights/config/led_config.yaml" in said
    said = _source(capsys, demo, "wheel", "panther-03")  # 2.2 keeps the wheel files in the image
    assert "written from husarion_ugv_ros@2.2.2:husarion_ugv_description/config/WH01.yaml" in said
    # panther-ops' own files are not presented as the image's
    said = _source(capsys, demo, "user-animations", "panther-02")
    assert said.startswith("panther-ops' template for panther_ros 2.0.4, not traced to an upstream file")
    said = _source(capsys, demo, "bt-lights", "panther-01")  # the release's stock project (issue 24)
    assert "written from panther_ros@2.1.1:panther_manager/behavior_trees/PantherLightsBT.btproj" in said
    said = _source(capsys, demo, "bt-safety", "panther-02")  # 2.0.4: its own, not 2.1.1's
    assert "written from panther_ros@2.0.4:panther_manager/behavior_trees/PantherSafetyBT.btproj" in said
    assert "(config tree)" in _source(capsys, demo, "bt-lights", "panther-03")
