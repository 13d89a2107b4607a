"""``config set namespace`` names the places that keep the old one, and changes them in the
same plan with --everywhere (issue 16, finding 9), on the demo fleet."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml

from panther_ops.cli.app import main

Capsys = pytest.CaptureFixture[str]
COMPOSE = "home/husarion/compose.yaml"
ENV_22 = "home/husarion/config/common/.env"


def _files(demo: Path) -> dict[str, str]:
    return {str(p.relative_to(demo)): p.read_text() for p in sorted(demo.rglob("*")) if p.is_file()}


def test_a_new_namespace_warns_of_every_place_that_keeps_the_old_one(demo: Path, capsys: Capsys) -> None:
    before = _files(demo)
    capsys.readouterr()
    assert main(["-i", str(demo), "config", "set", "namespace", "panther2", "--all", "--dry-run"]) == 0
    err = capsys.readouterr().err
    assert ("warning panther-01: service gamepad_controller (namespace:=panther) keeps the old namespace; "
            "add --everywhere") in err
    assert "warning panther-01: ROBOT_NAMESPACE=panther in compose.yaml's environment keeps the old namespace" in err
    assert "warning panther-02: service gamepad_controller (namespace:=panther) keeps the old namespace" in err
    assert "warning panther-03: ROBOT_NAMESPACE=panther in /home/husarion/config/common/.env keeps" in err
    for robot in ("panther-01", "panther-02", "panther-03"):
        assert f"warning {robot}: the WebUI (husarion-webui snap) has its own ros.namespace" in err
        assert "ros.namespace=panther2" in err
    assert _files(demo) == before  # a dry run


def test_everywhere_changes_them_in_the_same_plan(demo: Path, capsys: Capsys) -> None:
    robots = demo / "robots"
    assert main(["-i", str(demo), "config", "set", "namespace", "panther2", "--all", "--everywhere", "--yes"]) == 0
    err = capsys.readouterr().err
    assert "keeps the old namespace" not in err
    for robot in ("panther-01", "panther-02"):
        doc = yaml.safe_load((robots / robot / COMPOSE).read_text())
        services = doc["services"]
        driver = next(s for s in services if s.startswith(("panther_ros", "husarion_ugv")))
        assert "namespace:=panther2" in services[driver]["command"]
        assert "namespace:=panther2" in services["gamepad_controller"]["command"]
        assert "namespace:=panther " not in services["gamepad_controller"]["command"] + " "
    common = yaml.safe_load((robots / "panther-01" / COMPOSE).read_text())["x-common-config"]
    assert "ROBOT_NAMESPACE=panther2" in common["environment"]
    env = (robots / "panther-03" / ENV_22).read_text()
    assert "ROBOT_NAMESPACE=panther2\n" in env and "ROBOT_NAMESPACE=panther\n" not in env
    # a second run has nothing left to do
    capsys.readouterr()
    assert main(["-i", str(demo), "config", "set", "namespace", "panther2", "--all", "--everywhere", "--yes"]) == 0
    assert "4 robots: 4 ok" in capsys.readouterr().err


@pytest.mark.lab
def test_everywhere_recreates_the_gamepad_service_with_the_driver_on_the_lab(lab: Any) -> None:
    """On a 2.1.1 lab robot (real sshd, dockerd, Compose v2): one change, both containers
    recreated, each running with the new namespace."""
    import json

    robot = next(r for r in lab.robots if "2.1.1" in r.image and not r.jump)
    saved = lab.read(robot.name, "/" + COMPOSE)
    try:
        code = main(["-i", str(lab.inventory_path), "config", "set", "namespace", "panther2", "-r", robot.name,
                     "--everywhere", "--yes", "--settle", "1", "--json"])
        assert code == 0
        for container in (robot.driver_container, "gamepad_controller"):
            out = lab.docker(robot.name, "inspect", "-f", "{{json .Config.Cmd}}", container, check=True).stdout
            assert "namespace:=panther2" in " ".join(json.loads(out)), container
            env = lab.docker(robot.name, "inspect", "-f", "{{json .Config.Env}}", container, check=True).stdout
            assert "ROBOT_NAMESPACE=panther2" in json.loads(env), container
    finally:
        lab.write(robot.name, "/" + COMPOSE, saved)
        lab.sh(robot.name, "rm -rf /home/husarion/.panther-ops; true")
        lab.compose(robot.name, "up", "-d", "--force-recreate")
