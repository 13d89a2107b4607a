"""`config rollback` on a robot: what a backup's manifest names is checked before anything is
restored or recreated (a manifest changed on the robot is refused, nothing is changed)."""

from __future__ import annotations

import copy
from typing import Any

import pytest

from panther_ops.errors import RemoteStateError
from tests.golden.golden_plans import run_case

COMPOSE = "services:\n  panther_ros:\n    command: ros2 launch panther_bringup bringup.launch.py{}\n"
CASE: dict[str, Any] = {
    "planner": "config.rollback",
    "files": {"/home/husarion/compose.yaml": {"text": COMPOSE.format(" wheel_type:=WH02")}},
    "facts": {
        "history": [{"id": "20261123T101500Z-3c4d", "command": "config set wheel_type WH02",
                     "files": [{"path": "/home/husarion/compose.yaml", "backup": "files/0"}],
                     "recreate": ["panther_ros"], "compose_file": "~/compose.yaml", "status": "applied"}],
        "backup 20261123T101500Z-3c4d/files/0": {"text": COMPOSE.format("")},
    },
    "args": {},
}


def _with(**entry: Any) -> dict[str, Any]:
    case = copy.deepcopy(CASE)
    case["facts"]["history"][0].update(entry)
    return case


def test_a_sound_manifest_is_restored_and_its_service_recreated() -> None:
    plan, _ = run_case(CASE)
    assert [e.path for e in plan.edits] == ["/home/husarion/compose.yaml"]
    assert plan.recreate == ("panther_ros",) and plan.compose_file == "~/compose.yaml"


@pytest.mark.parametrize(("entry", "named"), [
    ({"compose_file": "~/../../etc/compose.yaml"}, "holds '..'"),
    ({"compose_file": "compose.yaml"}, "must be absolute"),
    ({"compose_file": "~/compose.yaml\n; reboot"}, "control character"),
    ({"recreate": ["panther_ros; reboot"]}, "'panther_ros; reboot' is not a compose service name"),
])
def test_a_damaged_manifest_is_refused(entry: dict[str, Any], named: str) -> None:
    with pytest.raises(RemoteStateError) as info:
        run_case(_with(**entry))
    assert "manifest is damaged" in info.value.message and named in info.value.message
