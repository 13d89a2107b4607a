"""`sim battery charge start|stop`: the recharge service of Husarion's manual, its name from the
model and namespace, called through a stand-in of Gazebo's CLI (tests/standins/ign)."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from panther_ops.core.sim.plan import plan_charge, recharge_service
from panther_ops.errors import UsageError
from tests.clirun import run

STANDINS = Path(__file__).resolve().parents[1] / "standins"


def test_the_service_names_of_the_manual() -> None:
    # husarion_ugv_ros@2.1.1:panther_gazebo/CONFIGURATION.md and @2.2.2:husarion_ugv_gazebo/CONFIGURATION.md
    assert recharge_service("start") == "/model/panther/battery/battery/recharge/start"
    assert recharge_service("stop", "lynx") == "/model/lynx/battery/battery/recharge/stop"
    # spawned with -name <namespace>; battery_name <namespace>/battery
    assert recharge_service("start", "panther", "robot1") == "/model/robot1/battery/robot1/battery/recharge/start"
    call = plan_charge("start")
    assert call.argv == ("ign", "service", "--service", "/model/panther/battery/battery/recharge/start", "--reqtype",
                         "ignition.msgs.Boolean", "--reptype", "ignition.msgs.Empty", "--req", "", "--timeout", "0")
    assert plan_charge("stop", tool="gz").argv[:2] == ("gz", "service")


@pytest.mark.parametrize(("args", "named"), [
    (("begin",), "'begin'"), (("start", "--robot-model", "rosbot"), "'rosbot'"),
    (("start", "--namespace", "a b"), "' ' is not allowed"), (("start", "--namespace", "1x"), "starts with a digit"),
    (("start", "--tool", "gazebo"), "'gazebo'"),
])
def test_bad_values_exit_2(capsys: pytest.CaptureFixture[str], args: tuple[str, ...], named: str) -> None:
    code, _, err = run(capsys, "sim", "battery", "charge", *args, "--yes")
    assert code == 2 and named in err


def test_unknown_action_is_refused_by_the_planner() -> None:
    with pytest.raises(UsageError):
        recharge_service("pause")


@pytest.fixture
def gazebo(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> tuple[Path, Path]:
    services, calls = tmp_path / "services", tmp_path / "calls"
    services.write_text("/model/panther/battery/battery/recharge/start\n"
                        "/model/panther/battery/battery/recharge/stop\n/gazebo/worlds\n")
    monkeypatch.setenv("PATH", f"{STANDINS}{os.pathsep}{os.environ['PATH']}")
    monkeypatch.setenv("PANTHER_OPS_STANDIN_GZ_SERVICES", str(services))
    monkeypatch.setenv("PANTHER_OPS_STANDIN_GZ_CALLS", str(calls))
    return services, calls


def test_start_and_stop_call_the_service(gazebo: tuple[Path, Path], capsys: pytest.CaptureFixture[str]) -> None:
    _, calls = gazebo
    code, out, _ = run(capsys, "sim", "battery", "charge", "start", "--dry-run")
    assert code == 0 and "would run: ign service --service /model/panther/battery/battery/recharge/start" in out
    assert not calls.exists(), "a dry run calls nothing"
    code, out, _ = run(capsys, "sim", "battery", "charge", "start", "--yes")
    assert code == 0 and "charging start: sent to /model/panther/battery/battery/recharge/start" in out
    code, out, _ = run(capsys, "sim", "battery", "charge", "stop", "--yes", "--json")
    doc = json.loads(out)
    assert code == 0 and doc["outcome"] == "changed" and doc["exit_code"] == 0
    assert calls.read_text().splitlines() == [
        "/model/panther/battery/battery/recharge/start ignition.msgs.Boolean ignition.msgs.Empty ''",
        "/model/panther/battery/battery/recharge/stop ignition.msgs.Boolean ignition.msgs.Empty ''"]


def test_a_service_the_simulation_lacks_is_named(gazebo: tuple[Path, Path],
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    _, calls = gazebo
    code, _, err = run(capsys, "sim", "battery", "charge", "start", "--namespace", "robot1", "--yes")
    assert code == 3
    assert "does not serve /model/robot1/battery/robot1/battery/recharge/start" in err
    assert "it serves /model/panther/battery/battery/recharge/start" in err
    assert not calls.exists()


def test_without_gazebo_the_tool_is_named(capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PATH", "/nonexistent")
    code, _, err = run(capsys, "sim", "battery", "charge", "start", "--yes")
    assert code == 2 and "ign: not found on this machine's PATH" in err
