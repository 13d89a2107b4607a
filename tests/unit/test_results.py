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
        "OK": 0, "ERROR": 1, "USAGE": 2, "PARTIAL": 3, "UNREACHABLE": 4, "INTERRUPTED": 130,
    }


def test_json_document() -> None:
    fleet = FleetResult("status", [RobotResult("a", O.OK, "fine"), RobotResult("b", O.UNREACHABLE, "down")])
    doc = fleet.to_json()
    assert doc["schema"] == 1
    assert doc["exit_code"] == 3
    assert doc["summary"]["ok"] == 1 and doc["summary"]["unreachable"] == 1
    assert [r["outcome"] for r in doc["robots"]] == ["ok", "unreachable"]


def test_identical_diffs_are_shown_once_under_their_robots(capsys: pytest.CaptureFixture[str]) -> None:
    from panther_ops.cli.render import print_diffs
    from panther_ops.results import Diff, FleetResult, Outcome, RobotResult

    same = Diff("/home/husarion/compose.yaml", "--- a/x\n+++ b/x\n@@ -1 +1 @@\n-wheel_type:=WH01\n+wheel_type:=WH02\n")
    other = Diff("/home/husarion/compose.yaml", "--- a/x\n+++ b/x\n@@ -1 +1 @@\n-wheel_type:=WH04\n+wheel_type:=WH02\n")
    fleet = FleetResult("t", [RobotResult(n, Outcome.CHANGED, "m", diffs=[d])
                              for n, d in (("r1", same), ("r2", other), ("r3", same))])
    print_diffs(fleet)
    out = capsys.readouterr().out
    assert out.count("+wheel_type:=WH02") == 2
    assert "2 robots (r1, r3): /home/husarion/compose.yaml" in out
    assert "r2: /home/husarion/compose.yaml" in out
    assert out.index("r1, r3") < out.index("r2:")
