"""Issue 24 (manual walk, "Modifying Behavior Trees"): `config pull bt-lights|bt-safety -o
DIR/NAME.btproj` writes the project and every file it includes beside it (BehaviorTree.CPP@4.9.1:
src/xml_parsing.cpp resolves an ``<include path>`` against the including file), from the
same place the project came from: the robot's mounted project, the 2.2 config tree, the image,
or the release's stock templates. So the pulled project, renamed, is valid and goes back with
`config push`. An included file that exists with other content is not replaced without --force.
The demo's panther-01 runs panther_ros 2.1.1 (no image: the stock templates), panther-03
husarion_ugv 2.2.2 with a config tree (the Lights project read from it)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from panther_ops.core.fleet.templates import template_path
from panther_ops.core.robot.bt_pull import pulled_includes
from tests.clirun import run

TREE_BT = "robots/panther-03/home/husarion/config/husarion_ugv_manager/behavior_trees"


def pull(demo: Path, capsys: pytest.CaptureFixture[str], kind: str, robot: str, *out: str) -> tuple[int, dict, str]:  # type: ignore[type-arg]
    code, stdout, err = run(capsys, "-i", str(demo), "config", "pull", kind, "-r", robot, *out, "--json")
    return code, json.loads(stdout) if stdout.strip() else {}, err


@pytest.mark.parametrize(("robot", "lights"), [
    ("panther-01", template_path("config", "panther-2.1", "panther_manager", "behavior_trees", "lights.xml")),
    ("panther-03", None),  # the tree's own lights.xml
])
def test_the_pulled_lights_project_is_valid_and_goes_back(demo: Path, tmp_path: Path, robot: str, lights: Path | None,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "bt"
    out.mkdir()
    code, doc, err = pull(demo, capsys, "bt-lights", robot, "-o", str(out / "MyLightsBT.btproj"))
    assert code == 0, err
    assert sorted(p.name for p in out.iterdir()) == ["MyLightsBT.btproj", "lights.xml"]
    expected = lights if lights is not None else demo / TREE_BT / "lights.xml"
    assert (out / "lights.xml").read_bytes() == expected.read_bytes()
    data = doc["robots"][0]["data"]
    assert data["includes"] == ["lights.xml"]
    assert data["written"] == [str(out / "MyLightsBT.btproj"), str(out / "lights.xml")]
    code, _, err = run(capsys, "bt", "validate", str(out / "MyLightsBT.btproj"))
    assert code == 0, err
    for step in ("--dry-run", "--yes"):
        code, _, err = run(capsys, "-i", str(demo), "config", "push", str(out / "MyLightsBT.btproj"), "--as",
                           "bt-lights", "-r", robot, step)
        assert code == 0, err


def test_the_safety_project_brings_its_trees(demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, doc, err = pull(demo, capsys, "bt-safety", "panther-01", "--dest", str(tmp_path / "d"))
    assert code == 0, err
    where = tmp_path / "d" / "panther-01"
    assert sorted(p.name for p in where.iterdir()) == ["bt-safety.btproj", "safety.xml", "shutdown.xml"]
    assert sorted(doc["robots"][0]["data"]["written"]) == sorted(str(p) for p in where.iterdir())
    code, _, err = run(capsys, "bt", "validate", str(where / "bt-safety.btproj"))
    assert code == 0, err


def test_an_included_file_with_other_content_is_kept_without_force(demo: Path, tmp_path: Path,
                                                                   capsys: pytest.CaptureFixture[str]) -> None:
    mine = b"<root BTCPP_format=\"4\"/>\n"
    (tmp_path / "lights.xml").write_bytes(mine)
    code, _, err = pull(demo, capsys, "bt-lights", "panther-01", "-o", str(tmp_path / "P.btproj"))
    assert code == 2 and "lights.xml" in err and "--force" in err, err
    assert not (tmp_path / "P.btproj").exists() and (tmp_path / "lights.xml").read_bytes() == mine
    code, doc, err = pull(demo, capsys, "bt-lights", "panther-01", "-o", str(tmp_path / "P.btproj"), "--force")
    assert code == 0, err
    assert (tmp_path / "lights.xml").read_bytes() != mine
    code, doc, err = pull(demo, capsys, "bt-lights", "panther-01", "-o", str(tmp_path / "P.btproj"))
    assert code == 0 and doc["robots"][0]["data"]["unchanged"] == [str(tmp_path / "lights.xml")], err


def test_a_mounted_project_comes_back_with_its_includes_at_their_paths(demo: Path, tmp_path: Path,
                                                                      capsys: pytest.CaptureFixture[str]) -> None:
    """A custom project on a 2.1.1 robot whose tree sits in a subdirectory, pulled under another name."""
    mine = tmp_path / "mine"
    (mine / "trees").mkdir(parents=True)
    stock = template_path("config", "panther-2.1", "panther_manager", "behavior_trees", "PantherLightsBT.btproj")
    (mine / "Custom.btproj").write_text(stock.read_text().replace('path="lights.xml"', 'path="trees/lights.xml"'))
    lights = template_path("config", "panther-2.1", "panther_manager", "behavior_trees", "lights.xml").read_text()
    (mine / "trees" / "lights.xml").write_text(lights.replace("<!--", "<!-- custom -->\n<!--", 1))
    code, _, err = run(capsys, "-i", str(demo), "config", "push", str(mine / "Custom.btproj"), "--as", "bt-lights",
                       "-r", "panther-01", "--yes")
    assert code == 0, err
    back = tmp_path / "back"
    back.mkdir()
    code, doc, err = pull(demo, capsys, "bt-lights", "panther-01", "-o", str(back / "Renamed.btproj"))
    assert code == 0, err
    assert "(mounted, lights_bt_project_path)" in doc["robots"][0]["data"]["source"]
    assert (back / "Renamed.btproj").read_bytes() == (mine / "Custom.btproj").read_bytes()
    assert (back / "trees" / "lights.xml").read_bytes() == (mine / "trees" / "lights.xml").read_bytes()
    code, _, err = run(capsys, "bt", "validate", str(back / "Renamed.btproj"))
    assert code == 0, err


def test_stdout_says_the_includes_are_not_written(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = run(capsys, "-i", str(demo), "config", "pull", "bt-lights", "-r", "panther-01")
    assert code == 0 and out.startswith("<?xml"), err
    assert "includes lights.xml: pull with -o" in " ".join(err.split()), err


def test_includes_are_followed_and_confined() -> None:
    files = {"a.xml": b'<root><include path="sub/b.xml"/></root>', "sub/b.xml": b'<root><include path="../c.xml"/>'
             b'<include path="../../out.xml"/></root>', "c.xml": b"<root/>"}
    project = (b'<root><include path="a.xml"/><include path="/etc/passwd"/><include path="gone.xml"/>'
               b'<include ros_pkg="husarion_ugv_manager" path="x.xml"/></root>')
    got = pulled_includes(project, files.get)
    assert got.files == files and got.missing == ["gone.xml"]
    assert got.refused == ["/etc/passwd", "../../out.xml"]
