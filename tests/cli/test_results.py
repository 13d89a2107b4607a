from __future__ import annotations

import pytest

from panther_ops.errors import ExitCode
from panther_ops.results import FleetResult, Outcome, RobotResult, exit_code_for

O = Outcome


@pytest.mark.parametrize(
    ("outcomes", "code"),
    [
        ([], ExitCode.OK),
        ([O.OK, O.CHANGED, O.SKIPPED], ExitCode.OK),
        ([O.OK, O.FAILED], ExitCode.PARTIAL),
        ([O.OK, O.ROLLED_BACK], ExitCode.PARTIAL),
        ([O.OK, O.UNREACHABLE], ExitCode.PARTIAL),
        ([O.UNREACHABLE, O.UNREACHABLE], ExitCode.UNREACHABLE),
        ([O.UNREACHABLE, O.FAILED], ExitCode.PARTIAL),
    ],
)
def test_exit_codes(outcomes: list[Outcome], code: ExitCode) -> None:
    assert exit_code_for(outcomes) is code


def test_exit_code_values_are_documented() -> None:
    assert {c.name: int(c) for c in ExitCode} == {
        "OK": 0, "ERROR": 1, "USAGE": 2, "PARTIAL": 3, "UNREACHABLE": 4, "DECLINED": 5, "DRIFT": 6,
        "INTERRUPTED": 130, "CLOSED_PIPE": 141,
    }


def test_json_document() -> None:
    fleet = FleetResult("status", [RobotResult("a", O.OK, "fine"), RobotResult("b", O.UNREACHABLE, "down")])
    doc = fleet.to_json()
    assert doc["schema"] == 1
    assert doc["exit_code"] == 3
    assert doc["summary"]["ok"] == 1 and doc["summary"]["unreachable"] == 1
    assert [r["outcome"] for r in doc["robots"]] == ["ok", "unreachable"]


def test_several_robots_diffs_are_one_patch_for_the_fleet_tree(capsys: pytest.CaptureFixture[str]) -> None:
    """Each robot's own diff, its paths under a directory named after it (issue 16: the output of
    a fleet is one real patch); a diff the same as an earlier robot's says so in its heading."""
    from panther_ops.cli.render import print_diffs
    from panther_ops.results import Diff, FleetResult, Outcome, RobotResult

    head = "--- a/home/husarion/compose.yaml\n+++ b/home/husarion/compose.yaml\n"
    same = Diff("/home/husarion/compose.yaml", head + "@@ -1 +1 @@\n-wheel_type:=WH01\n+wheel_type:=WH02\n")
    other = Diff("/home/husarion/compose.yaml", head + "@@ -1 +1 @@\n-wheel_type:=WH04\n+wheel_type:=WH02\n")
    fleet = FleetResult("t", [RobotResult(n, Outcome.CHANGED, "m", diffs=[d])
                              for n, d in (("r1", same), ("r2", other), ("r3", same))])
    print_diffs(fleet)
    out = capsys.readouterr().out
    assert out.count("+wheel_type:=WH02") == 3
    for robot in ("r1", "r2", "r3"):
        assert f"--- a/{robot}/home/husarion/compose.yaml\n+++ b/{robot}/home/husarion/compose.yaml\n" in out
    assert "r1: /home/husarion/compose.yaml\n" in out
    assert "r3: /home/husarion/compose.yaml (the same change as r1)\n" in out
    assert out.index("r1:") < out.index("r2:") < out.index("r3:")


def test_one_robots_diff_keeps_the_paths_from_its_root(capsys: pytest.CaptureFixture[str]) -> None:
    from panther_ops.cli.render import print_diffs
    from panther_ops.results import Diff, FleetResult, Outcome, RobotResult

    unified = "--- a/home/husarion/compose.yaml\n+++ b/home/husarion/compose.yaml\n@@ -1 +1 @@\n-a\n+b\n"
    print_diffs(FleetResult("t", [RobotResult("r1", Outcome.CHANGED, "m",
                                              diffs=[Diff("/home/husarion/compose.yaml", unified)])]))
    assert capsys.readouterr().out == "r1: /home/husarion/compose.yaml\n" + unified + "\n"  # a blank line after


def test_under_directory_touches_only_the_file_headers() -> None:
    from panther_ops.core.yaml.diff import under_directory, unified_diff

    diff = unified_diff("-- a/x\n++ b/y\nkeep\n", "keep\n", "/etc/f.yaml")
    moved = under_directory(diff, "r1")
    assert moved.splitlines()[:2] == ["--- a/r1/etc/f.yaml", "+++ b/r1/etc/f.yaml"]
    assert moved.splitlines()[2:] == diff.splitlines()[2:]  # "--- a/x" in the hunk is a removed line
    assert "--- a/x" in moved.splitlines()[3:][0]
