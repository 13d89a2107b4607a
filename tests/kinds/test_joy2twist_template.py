"""panther-ops' template of the gamepad's parameters in the husarion/joy2twist image of panther_ros
2.0-2.1 (`config pull joy2twist` hands it out when the container cannot be read; issue 24, finding 9)
equals its source, husarion/joy2twist@2f8ad45:joy2twist/config/joy2twist_panther.yaml, key for key and
value for value (int vs float counts), and the lab's stand-in of the image holds the same values.
The comparison with the repository itself runs where a local mirror of husarion/joy2twist is."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path
from typing import Any

import pytest
import yaml

from panther_ops.core.kinds import FileKind, check_file

REPO = Path(__file__).resolve().parents[2]
TEMPLATE = REPO / "templates/joy2twist/joy2twist_panther.yaml"
LAB = REPO / "tests/lab/data/joy2twist_panther.yaml"
MIRROR = Path(os.environ.get("PANTHER_OPS_JOY2TWIST_MIRROR", "/work/.mirror/husarion+joy2twist/repo"))
COMMIT = "2f8ad45"


def typed(value: Any) -> Any:
    """The values with their YAML types (2 and 2.0 differ for ROS)."""
    if isinstance(value, dict):
        return {k: typed(v) for k, v in value.items()}
    if isinstance(value, list):
        return [typed(v) for v in value]
    return (type(value).__name__, value)


def test_the_template_names_its_source_and_is_accepted() -> None:
    text = TEMPLATE.read_text()
    assert f"Source: husarion/joy2twist@{COMMIT}:joy2twist/config/joy2twist_panther.yaml" in text
    check_file(FileKind.JOY2TWIST, str(TEMPLATE), text.encode())


def test_the_lab_image_holds_the_templates_values() -> None:
    assert typed(yaml.safe_load(LAB.read_text())) == typed(yaml.safe_load(TEMPLATE.read_text()))


def _show(rev_path: str) -> str:
    return subprocess.run(["git", "-C", str(MIRROR), "show", rev_path], capture_output=True, text=True,
                          check=True).stdout


@pytest.mark.skipif(not MIRROR.is_dir(), reason="no local mirror of husarion/joy2twist")
def test_the_template_equals_husarion_joy2twist_and_the_image_layout_is_its_dockerfiles() -> None:
    upstream = _show(f"{COMMIT}:joy2twist/config/joy2twist_panther.yaml")
    assert typed(yaml.safe_load(upstream)) == typed(yaml.safe_load(TEMPLATE.read_text()))
    dockerfile = _show(f"{COMMIT}:Dockerfile")
    assert "WORKDIR /ros2_ws" in dockerfile and "COPY ./joy2twist ./src/joy2twist" in dockerfile
    assert "colcon build --symlink-install" in dockerfile  # install/joy2twist/share/... link to src/
    assert "COPY --from=pkg-builder /ros2_ws /ros2_ws" in dockerfile
    cmake = _show(f"{COMMIT}:joy2twist/CMakeLists.txt")
    assert "config" in cmake.split("install(DIRECTORY", 1)[1].split(")", 1)[0]
