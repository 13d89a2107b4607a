"""Issue 24 (manual walk, "Changing Wheel Type" on husarion_ugv 2.2): with a config tree
(``common_dir_path``) the 2.2 driver reads ``<common_dir_path>/husarion_ugv_controller/config/
<wheel_type>_controller.yaml`` (husarion_ugv_ros@2.2.2:husarion_ugv_controller/launch/
controller.launch.py), and `config set controller.<key>` edits the tree's file of the current
wheel type. A change of ``wheel_type`` then makes the driver read the new type's tree file:
the user's limits (those that differ from the release's stock file) are carried into it in the
same plan and diff, within the new type's limits, each other one named in a warning, as a
custom controller file is migrated on 2.0/2.1 (`core.robot.wheel_change`). The demo's
panther-03 runs husarion_ugv 2.2.2 with a tree."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

from tests.clirun import run

ROBOT = "robots/panther-03"
TREE_CONTROLLER = f"{ROBOT}/home/husarion/config/husarion_ugv_controller/config"
CONTAINER = "/config/husarion_ugv_controller/config"


def cli(demo: Path, capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, dict, str]:  # type: ignore[type-arg]
    code, out, err = run(capsys, "-i", str(demo), *argv, "-r", "panther-03", "--json")
    return code, json.loads(out) if out.strip() else {}, err


def drive(demo: Path, wheel: str) -> dict:  # type: ignore[type-arg]
    doc = yaml.safe_load((demo / TREE_CONTROLLER / f"{wheel}_controller.yaml").read_text())
    return dict(doc["/**"]["drive_controller"]["ros__parameters"])


def test_a_limit_of_your_own_is_carried_to_the_new_wheel_types_tree_file(
        demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, _, err = cli(demo, capsys, "config", "set", "controller.linear.x.max_velocity", "0.8", "--yes")
    assert code == 0, err
    stock_wh02 = (demo / TREE_CONTROLLER / "WH02_controller.yaml").read_text()
    code, doc, err = cli(demo, capsys, "config", "set", "wheel_type", "WH02", "--dry-run")
    assert code == 0, err
    robot = doc["robots"][0]
    assert (demo / TREE_CONTROLLER / "WH02_controller.yaml").read_text() == stock_wh02  # dry run: nothing written
    diffs = {d["path"].rsplit("/", 1)[1]: d["unified"] for d in robot["diffs"]}
    assert set(diffs) == {"compose.yaml", "WH02_controller.yaml"}, diffs
    assert "+          max_velocity: 0.8 # m/s" in diffs["WH02_controller.yaml"], diffs
    assert any("linear.x.max_velocity=0.8" in w for w in robot["warnings"]), robot["warnings"]
    code, doc, err = cli(demo, capsys, "config", "set", "wheel_type", "WH02", "--yes")
    assert code == 0 and doc["robots"][0]["outcome"] == "changed", err
    wh02 = drive(demo, "WH02")
    assert wh02["linear"]["x"]["max_velocity"] == 0.8
    assert wh02["angular"]["z"]["max_velocity"] == 2.2 and "wheel_separation_x" in wh02  # else WH02's own
    compose = (demo / ROBOT / "home/husarion/compose.yaml").read_text()
    assert "controller_config_path" not in compose  # the tree's file is the one read: no argument
    code, doc, err = cli(demo, capsys, "config", "get", "controller.linear.x.max_velocity")
    assert code == 0 and doc["robots"][0]["data"]["value"] == 0.8, err


def test_a_limit_above_the_new_types_limit_is_not_carried_and_is_named(
        demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """1.8 m/s is within WH01's 2.0 but above WH02's 1.1: WH02's own value stays, with a warning."""
    for key, value in (("linear.x.max_velocity", "1.8"), ("angular.z.max_velocity", "1.5")):
        code, _, err = cli(demo, capsys, "config", "set", f"controller.{key}", value, "--yes")
        assert code == 0, err
    code, doc, err = cli(demo, capsys, "config", "set", "wheel_type", "WH02", "--yes")
    assert code == 0, err
    warnings = doc["robots"][0]["warnings"]
    assert any("linear.x.max_velocity" in w and "1.1" in w for w in warnings), warnings
    wh02 = drive(demo, "WH02")
    assert wh02["linear"]["x"]["max_velocity"] == 1.1 and wh02["angular"]["z"]["max_velocity"] == 1.5


def test_the_stock_tree_file_changes_only_the_wheel_type(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    stock_wh02 = (demo / TREE_CONTROLLER / "WH02_controller.yaml").read_bytes()
    code, doc, err = cli(demo, capsys, "config", "set", "wheel_type", "WH02", "--yes")
    assert code == 0, err
    assert (demo / TREE_CONTROLLER / "WH02_controller.yaml").read_bytes() == stock_wh02
    assert not any("limits" in w for w in doc["robots"][0]["warnings"]), doc


def test_a_robot_without_a_tree_does_not_parse_the_stock_controller_file(
        demo: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    """panther-01 (2.1.1) reads no tree: the stock file the tree's limits are compared with is
    not parsed (~10 ms of CPU per robot, a third of what `config set wheel_type` on 30 lab
    robots had grown by: docs/performance.md, "Issue #28: main before and after")."""
    from panther_ops.core.robot.controller import ControllerConfig

    def parsed(*args: object, **kwargs: object) -> ControllerConfig:
        raise AssertionError("the stock controller file was parsed for a robot without a tree")

    monkeypatch.setattr(ControllerConfig, "default", classmethod(parsed))
    code, out, err = run(capsys, "-i", str(demo), "config", "set", "wheel_type", "WH02", "-r", "panther-01",
                         "--dry-run", "--json")
    assert code == 0, err
    robot = json.loads(out)["robots"][0]
    assert [d["path"].rsplit("/", 1)[1] for d in robot["diffs"]] == ["compose.yaml"], robot


def test_the_wheel_check_parses_compose_yaml_once_for_the_robots_that_share_it(
        demo: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The wheel type check (does a controller file move to the new type?) looks at compose.yaml
    after each file it asks for; robots with the same compose.yaml and files share one parse
    and one answer, as the edit itself is shared (was: a parse per robot and per read, about
    two thirds of the planning CPU of `config set wheel_type` on 30 lab robots)."""
    import uuid

    from panther_ops.core.config import plan as planners
    from panther_ops.core.fleet.reads import NotRead, Reads
    from panther_ops.core.robot.robot_config import ComposeRead, parse_config

    calls: list[bytes] = []

    def counted(raw: ComposeRead, stack: str) -> object:
        calls.append(raw.before)
        return parse_config(raw, stack)

    monkeypatch.setattr(planners, "parse_config", counted)
    home = demo / ROBOT / "home" / "husarion"
    before = (home / "compose.yaml").read_bytes() + f"# {uuid.uuid4()}\n".encode()  # no earlier test's plan
    raw = ComposeRead("/home/husarion", "/home/husarion/compose.yaml", before)
    plans = []
    for i in range(5):
        reads = Reads(f"r{i}")
        while True:  # what fleet.reading does: read what the planner asks for, plan again
            try:
                plans.append(planners.plan_args(raw, reads, {"wheel_type": "WH02"}, []))
                break
            except NotRead as need:
                path = need.need.key
                p = demo / ROBOT / path.lstrip("/")
                reads.files[path] = p.read_bytes() if p.is_file() else None
    assert len({p.edits[0].after for p in plans}) == 1 and all(p.summary == plans[0].summary for p in plans)
    assert len(calls) == 2, "one parse to look at, one for the shared edit"
