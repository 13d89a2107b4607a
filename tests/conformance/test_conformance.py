"""Conformance with Husarion's releases, offline: the release tables in tests/golden/upstream
(distilled from the upstream repositories by scripts/conformance.py) against the project's
validators, launch-argument catalogue and templates. One test per item; the failures known
today (panther_ops/conformance/known.py, each tied to its finding of issue #24) are
``xfail(strict=True)``, so the fix of one turns its test red until its line is removed.

The tool's parts are tested on small inputs written here (a launch file, a config-tree
script, a git repository made in a temporary directory): no upstream file is copied.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from fnmatch import fnmatchcase
from pathlib import Path

import pytest

from panther_ops.conformance import launch
from panther_ops.conformance.catalogue import catalogue_default, declared
from panther_ops.conformance.checks import Result, check_release, load_tables, untraced_templates
from panther_ops.conformance.digest import compose_leaves, diff, leaves
from panther_ops.conformance.distil import distil, own_compose
from panther_ops.conformance.known import FINDINGS, KNOWN, known
from panther_ops.conformance.preview import checked_stack, kinds_stack, preview_for
from panther_ops.conformance.pyexpr import Unevaluable, evaluate
from panther_ops.conformance.report import render
from panther_ops.conformance.upstream import GitRelease, config_tree
from panther_ops.core.stack import stack_from_version
from panther_ops.errors import OpsError

ROOT = Path(__file__).resolve().parents[2]
TABLES = ROOT / "tests" / "golden" / "upstream"
SUPPORTED = ("2.0.4", "2.1.1", "2.2.0", "2.2.2")
NOT_YET = ("2.3.0", "2.3.1", "2.3.2")
"""husarion_ugv 2.3 (Jazzy, issue #25): supported; its file kinds and config templates are issue #25's to-do."""

_TABLES = load_tables(TABLES)
_RESULTS: list[Result] = [r for t in _TABLES for r in check_release(t)] + untraced_templates(_TABLES)


def _param(result: Result) -> object:
    entry = known(result.id)
    reason = entry and (entry[0] + (f": {entry[1]}" if entry[1] else ""))
    marks = [pytest.mark.xfail(strict=True, reason=reason)] if reason and result.ok is not None else []
    return pytest.param(result, id=result.id, marks=marks)


@pytest.mark.parametrize("result", [_param(r) for r in _RESULTS])
def test_conforms(result: Result) -> None:
    if result.ok is None:
        pytest.skip(f"not checked: {result.summary}")
    assert result.ok, "\n  ".join((f"{result.id}: {result.summary}", *result.details))


def test_every_supported_release_has_its_table() -> None:
    tags = [t["tag"] for t in _TABLES]
    assert [t for t in (*SUPPORTED, *NOT_YET) if t not in tags] == []
    for table in _TABLES:
        assert re.fullmatch(r"[0-9a-f]{40}", table["commit"]), table["tag"]
        assert table["repo"] in ("husarion/panther_ros", "husarion/husarion_ugv_ros")


def test_tables_hold_digests_not_upstream_files() -> None:
    """Every stored value is a type and a 16-hex-digit hash: no upstream value or text is kept."""
    leaf = re.compile(r"^(int|float|bool|str|null|map\{\}|list\[\]|bytes):[0-9a-f]{16}$")
    for table in _TABLES:
        digests = [*table["files"], *([table["compose"]] if table.get("compose") else [])]
        for row in digests:
            bad = [k for k, v in row["leaves"].items() if not leaf.match(v)]
            assert bad == [], (table["tag"], row["path"], bad[:3])
            assert set(row) <= {"path", "sha256", "format", "leaves", "kind", "robot", "verdict", "note", "repo",
                                "commit"}, row["path"]


def test_every_known_failure_is_a_failing_item() -> None:
    """A line of known.py that matches no failing item is stale (or a typo): it would hide nothing."""
    failing = [r.id for r in _RESULTS if r.failed]
    stale = [p for p in KNOWN if not any(fnmatchcase(i, p) for i in failing)]
    assert stale == []
    assert {label for label, _ in KNOWN.values()} <= set(FINDINGS)


def test_no_failure_is_unknown() -> None:
    """Each failing item is listed in known.py with its finding (or is new and listed as such)."""
    assert [r.id for r in _RESULTS if r.failed and known(r.id) is None] == []


def test_jazzy_releases_are_supported_and_reported_with_the_others() -> None:
    """2.3.x is a supported stack (core/stack.py): checked as itself (no ``release`` item, no preview), its
    launch arguments equal to the catalogue and its compose template equal to upstream's; what still fails
    is issue #25's file kinds and config templates, each listed in known.py."""
    for tag in (*SUPPORTED, *NOT_YET):
        assert preview_for(tag) is None and checked_stack(tag).version_str == tag
    assert preview_for("2.4.0") is None  # a line no preview covers stays a plain refusal
    with pytest.raises(OpsError):
        checked_stack("2.4.0")
    for tag in NOT_YET:
        assert kinds_stack(tag).version_str == tag  # the file kinds: the release's own rules
        mine = [r for r in _RESULTS if r.tag == tag]
        assert not [r for r in mine if r.check == "release"]
        assert [r.id for r in mine if r.check == "launch" and not r.ok] == []
        (compose,) = [r for r in mine if r.item.startswith("compose/")]
        assert compose.item == f"compose/husarion-ugv-{tag}.yaml" and compose.ok, compose.summary
        assert all(known(r.id) is not None and known(r.id)[0] == "issue #25" for r in mine if r.failed)
    shutdown = next(r for r in _RESULTS if r.id == "2.3.2:defaults:husarion_ugv_manager/config/shutdown_hosts.yaml")
    assert shutdown.ok is True  # unchanged from 2.2.2, accepted by today's validator
    controllers = [r for r in _RESULTS if r.check == "defaults" and r.tag in NOT_YET and "_controller.yaml" in r.item]
    assert len(controllers) == 12 and all(r.ok for r in controllers)  # the Jazzy limits schema, per release
    (madgwick,) = [r for r in _RESULTS if r.id == "2.3.2:launch:use_madgwick_filter"]
    assert madgwick.ok is True
    (tree,) = [r for r in _RESULTS if r.id == "2.3.2:tree:panther"]  # the demo fleet's 2.3.2 robot
    assert tree.ok is True
    report = render(_TABLES, _RESULTS)
    assert "## Not yet supported" not in report and "| 2.3.2 |" in report


def test_report_is_current() -> None:
    """docs/conformance.md is what the tables and the project give today."""
    expected = render(_TABLES, _RESULTS)
    actual = (ROOT / "docs" / "conformance.md").read_text(encoding="utf-8")
    assert actual == expected, "docs/conformance.md is stale: python scripts/conformance.py --report docs/conformance.md"


# -- the parts of the tool, on inputs written here ---------------------------------------------

LAUNCH = '''
from launch.actions import DeclareLaunchArgument, IncludeLaunchDescription
from launch.substitutions import EnvironmentVariable, LaunchConfiguration, PathJoinSubstitution, PythonExpression
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    common_dir_path = LaunchConfiguration("common_dir_path")
    declare_common = DeclareLaunchArgument("common_dir_path", default_value="")
    pkg_dir = PythonExpression(["'", common_dir_path, "/demo_pkg' if '", common_dir_path, "' else '",
                                FindPackageShare("demo_pkg"), "'"])
    wheel_type = LaunchConfiguration("wheel_type")
    models = {"lynx": "WH05", "panther": "WH01"}
    declare_wheel = DeclareLaunchArgument(
        "wheel_type", default_value=PythonExpression([f"{models}['", LaunchConfiguration("robot_model"), "']"]),
        choices=["WH01", "WH05", "custom"])
    declare_model = DeclareLaunchArgument(
        "robot_model", default_value=EnvironmentVariable("ROBOT_MODEL_NAME", default_value="panther"))
    declare_tree = DeclareLaunchArgument(
        "controller_config_path",
        default_value=PathJoinSubstitution([pkg_dir, "config", PythonExpression(["'", wheel_type, "_c.yaml'"])]))
    declare_image = DeclareLaunchArgument(
        "wheel_config_path", default_value=PathJoinSubstitution([FindPackageShare("demo_pkg"), "config", "w.yaml"]))
    declare_flag = DeclareLaunchArgument("use_sim", default_value="False", choices=["True", "False"])
    forgotten = DeclareLaunchArgument("never_added", default_value="x")
    other = IncludeLaunchDescription(PathJoinSubstitution([FindPackageShare("other_repo"), "launch", "x.launch.py"]))
    return LaunchDescription([declare_common, declare_model, declare_wheel, declare_tree, declare_image,
                              declare_flag, other])
'''


def test_launch_arguments_from_the_ast() -> None:
    trav = launch.traverse("demo_pkg/launch/bringup.launch.py", {"demo_pkg/launch/bringup.launch.py": LAUNCH},
                           {"demo_pkg": "demo_pkg"})
    rows = {r["name"]: r for r in launch.arguments(trav)}
    assert sorted(rows) == ["common_dir_path", "controller_config_path", "robot_model", "use_sim",
                            "wheel_config_path", "wheel_type"]
    assert "never_added" not in rows
    assert any("forgotten" in p and "never added" in p for p in trav.problems)
    assert trav.external == ["other_repo/launch/x.launch.py"]
    tree = rows["controller_config_path"]
    assert tree["source"] == "tree"
    assert tree["default"] == {"image": "$(find demo_pkg)/config/WH01_c.yaml",
                               "tree": "/config/demo_pkg/config/WH01_c.yaml",
                               "variant": "/config/demo_pkg/config/WH02_c.yaml"}
    assert rows["wheel_config_path"]["source"] == "image"
    assert rows["wheel_type"]["default"]["variant"] == "WH05"  # robot_model lynx
    assert rows["wheel_type"]["source"] == "arg:robot_model"
    assert (rows["wheel_type"]["kind"], rows["wheel_type"]["choices"]) == ("choice", ["WH01", "WH05", "custom"])
    assert rows["robot_model"]["source"] == "env:ROBOT_MODEL_NAME"
    assert rows["use_sim"]["kind"] == "bool"


def test_python_expressions_are_evaluated_not_run() -> None:
    assert evaluate("'/config/x' if '/config' else 'y'") == "/config/x"
    assert evaluate("{'lynx': 'WH05', 'panther': 'WH01'}['lynx']") == "WH05"
    assert evaluate("'_with_gps' if True else ''") == "_with_gps"
    for code in ("__import__('os').system('true')", "open('/etc/passwd')", "x", "(lambda: 1)()", "'a'.upper()"):
        with pytest.raises(Unevaluable):
            evaluate(code)


def test_digest_tells_int_from_float_and_names_the_key() -> None:
    fmt, upstream = leaves("c.yaml", b"a:\n  max_velocity: 2.0\n  b: [1, 2]\n")
    _, ours = leaves("c.yaml", b"a:\n  max_velocity: 2\n  b: [1, 2]\n  extra: x\n")
    assert fmt == "yaml"
    assert [d.line() for d in diff(upstream, ours)] == ["a.max_velocity: type (upstream float, ours int)",
                                                       "a.extra: extra (ours str)"]
    assert diff(upstream, leaves("c.yaml", b"a: {max_velocity: 2.0, b: [1, 2]}")[1]) == []
    _, xml = leaves("p.btproj", b"<root><!-- c --><BehaviorTree ID='Lights'/></root>")
    assert list(xml) == ["root[0]/BehaviorTree[0]@ID"]


def test_compose_digest_reads_like_docker_compose() -> None:
    a = b"services:\n  s:\n    volumes: [/a:/a, /b:/b]\n    command: >\n      ros2 launch\n        x y\n"
    b = b"services:\n  s:\n    volumes: [/b:/b, /a:/a]\n    command: ros2 launch x y\n"
    assert diff(compose_leaves(a), compose_leaves(b)) == []


def test_config_tree_from_update_config_directory() -> None:
    script = ("copy_package_file p_ctrl config\ncopy_package_file p_lights config/${ROBOT_MODEL_NAME}_a.yaml\n"
              "copy_package_file p_loc config\nrm /config/p_loc/config/nmea.yaml || true\n")
    paths = ("p_ctrl/config/WH01_c.yaml", "p_lights/config/lynx_a.yaml", "p_lights/config/panther_a.yaml",
             "p_loc/config/ekf.yaml", "p_loc/config/nmea.yaml")
    pkgs = {"p_ctrl": "p_ctrl", "p_lights": "p_lights", "p_loc": "p_loc"}
    assert config_tree(script, paths, pkgs, "panther") == ["p_ctrl/config/WH01_c.yaml",
                                                          "p_lights/config/panther_a.yaml", "p_loc/config/ekf.yaml"]


def test_catalogue_notation() -> None:
    stack = stack_from_version("2.2.2")
    specs = declared(stack)
    image = {"common_dir_path": ""}
    tree = {"common_dir_path": "/config"}
    ctl = specs["controller_config_path"]
    assert catalogue_default(ctl, stack, image) == "$(find husarion_ugv_controller)/config/WH01_controller.yaml"
    assert catalogue_default(ctl, stack, {**tree, "wheel_type": "WH02"}) == \
        "/config/husarion_ugv_controller/config/WH02_controller.yaml"
    loc = specs["localization_config_path"]
    assert catalogue_default(loc, stack, {**tree, "fuse_gps": "True", "localization_mode": "enu"}) == \
        "/config/husarion_ugv_localization/config/enu_localization_with_gps.yaml"


def _git(repo: Path, *args: str) -> None:
    subprocess.run(["git", "-C", str(repo), *args], check=True, capture_output=True,
                   env={**os.environ, "GIT_AUTHOR_NAME": "t", "GIT_AUTHOR_EMAIL": "t@t", "GIT_COMMITTER_NAME": "t",
                        "GIT_COMMITTER_EMAIL": "t@t", "GIT_CONFIG_GLOBAL": os.devnull, "GIT_CONFIG_NOSYSTEM": "1"})


def test_distil_a_release_from_a_git_mirror(tmp_path: Path) -> None:
    """The online path end to end, on a release made here: package.xml, bringup, one wheel file."""
    repo = tmp_path / "husarion+husarion_ugv_ros" / "repo"
    (repo / "husarion_ugv_bringup" / "launch").mkdir(parents=True)
    (repo / "husarion_ugv_bringup" / "package.xml").write_text("<package><name>husarion_ugv_bringup</name></package>")
    (repo / "husarion_ugv_bringup" / "launch" / "bringup.launch.py").write_text(
        "def generate_launch_description():\n"
        "    return LaunchDescription([DeclareLaunchArgument('log_level', default_value='INFO',"
        " choices=['INFO', 'DEBUG'])])\n")
    (repo / "husarion_ugv_description" / "config").mkdir(parents=True)
    (repo / "husarion_ugv_description" / "package.xml").write_text(
        "<package><name>husarion_ugv_description</name></package>")
    (repo / "husarion_ugv_description" / "config" / "WH01.yaml").write_text("wheel_radius: 0.1\n")
    _git(repo, "init", "-q")
    _git(repo, "add", "-A")
    _git(repo, "commit", "-q", "-m", "release")
    _git(repo, "tag", "2.2.2")
    table = distil(GitRelease(repo, "2.2.2"))
    assert table["repo"] == "husarion/husarion_ugv_ros" and len(table["commit"]) == 40
    assert [(a["name"], a["kind"], a["default"]["image"]) for a in table["launch"]["args"]] == \
        [("log_level", "choice", "INFO")]
    (row,) = table["files"]
    assert (row["path"], row["kind"], row["verdict"]["accepted"]) == \
        ("husarion_ugv_description/config/WH01.yaml", "wheel", False)  # no wheel_separation: refused, recorded
    assert "0.1" not in json.dumps(row)


def test_a_release_s_own_compose_file_is_digested(tmp_path: Path) -> None:
    """husarion_ugv_ros 2.2+ holds the robot's compose file itself (docker/demo/compose.hardware.yaml):
    without a --docker-repo that has the tag, scripts/conformance.py digests that one, by the compose
    rules; a release without it (panther_ros) has none."""
    repo = tmp_path / "husarion+husarion_ugv_ros" / "repo"
    (repo / "docker" / "demo").mkdir(parents=True)
    (repo / "docker" / "demo" / "compose.hardware.yaml").write_text(
        "services:\n  husarion_ugv_ros:\n    env_file: [/x/.env]\n    command: >\n      ros2 launch a b.launch.py\n")
    _git(repo, "init", "-q")
    _git(repo, "add", "-A")
    _git(repo, "commit", "-q", "-m", "release")
    _git(repo, "tag", "2.2.2")
    compose = own_compose(GitRelease(repo, "2.2.2"))
    assert compose is not None
    assert (compose["repo"], compose["path"]) == ("husarion/husarion_ugv_ros", "docker/demo/compose.hardware.yaml")
    same = b"services:\n  husarion_ugv_ros:\n    env_file: [/x/.env]\n    command: ros2 launch a  b.launch.py\n"
    assert {k: f"{t}:{h}" for k, (t, h) in compose_leaves(same).items()} == compose["leaves"]
    _git(repo, "rm", "-q", "docker/demo/compose.hardware.yaml")
    _git(repo, "commit", "-q", "-m", "older")
    _git(repo, "tag", "2.1.1")
    assert own_compose(GitRelease(repo, "2.1.1")) is None


def test_the_2_2_compose_template_is_checked_against_husarion_ugv_ros() -> None:
    table = next(t for t in _TABLES if t["tag"] == "2.2.2")
    assert (table["compose"]["repo"], table["compose"]["path"]) == \
        ("husarion/husarion_ugv_ros", "docker/demo/compose.hardware.yaml")
    (result,) = [r for r in _RESULTS if r.id == "2.2.2:templates:compose/husarion-ugv-2.2.2.yaml"]
    assert result.ok is True, result.details


def test_script_help_and_bad_usage() -> None:
    script = [sys.executable, str(ROOT / "scripts" / "conformance.py")]
    done = subprocess.run([*script, "--help"], capture_output=True, text=True, check=False)
    assert done.returncode == 0 and "--repo GIT_DIR" in done.stdout and "--tag TAG" in done.stdout
    done = subprocess.run([*script, "--tag", "2.2.2"], capture_output=True, text=True, check=False)
    assert done.returncode == 2 and "--tag needs --repo" in done.stderr
    done = subprocess.run([*script, "--repo", str(ROOT), "--tag", "9.9.9", "--no-write"], capture_output=True,
                          text=True, check=False)
    assert done.returncode == 2 and "tag 9.9.9 is in none of" in done.stderr
