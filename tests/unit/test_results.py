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
