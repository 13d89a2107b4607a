"""`panther-ops webui` without a lab: the snap's answers parsed, the plan, DDS profiles checked,
bad input refused before any robot is contacted, and the demo fleet's recorded answers."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from panther_ops.cli.app import main
from panther_ops.core.kinds.webui_settings import SettingError, dds_profile
from panther_ops.core.remote.webui.state import parse_state, plan_changes

STATE = """@@list
Name            Version  Rev  Tracking       Publisher  Notes
husarion-webui  1.4.2    42   humble/stable  husarion   -
@@exit 0
@@get
{"ros": {"namespace": "panther", "transport": "udp"}, "webui": {"port": "8081"}}
@@exit 0
@@services
Service                 Startup  Current   Notes
husarion-webui.daemon   disabled inactive  -
@@exit 0
@@profiles
my-fastdds.xml
layout.json
@@exit 0
"""


def test_state_parsed_with_defaults_and_the_plan() -> None:
    st = parse_state(STATE)
    assert (st.installed, st.channel, st.revision, st.running) == (True, "humble/stable", "42", False)
    assert st.profiles == {"my-fastdds"}
    assert st.value("ros.namespace") == "panther" and st.value("webui.layout") == "default"
    assert plan_changes(st, {"ros.namespace": "panther", "webui.port": "8080", "webui.layout": "panther"}) == [
        ("webui.port", "8081", "8080"), ("webui.layout", "default", "panther")]
    assert parse_state(STATE.replace("inactive", "active")).running is True
    assert parse_state('@@list\nerror: snap "husarion-webui" is not installed\n@@exit 1\n').installed is False


def test_dds_profile_checks() -> None:
    assert dds_profile("fast.xml", b"<dds><profiles/></dds>") == ("fast", b"<dds><profiles/></dds>")
    assert dds_profile("cyc.xml", b'<CycloneDDS xmlns="https://cdds.io/config"/>')[0] == "cyc"
    for name, data, why in [("x.xml", b"transport: udp", "well-formed XML"),
                            ("x.xml", b"<html/>", "root element"),
                            ("x.xml", b'<!DOCTYPE d [<!ENTITY a "b">]><dds/>', "without DOCTYPE"),
                            ("../x.xml", b"<dds/>", "file name")]:
        with pytest.raises(SettingError, match=why):
            dds_profile(name, data)


@pytest.fixture
def demo(tmp_path: Path) -> str:
    path = str(tmp_path / "demo")
    assert main(["demo", "init", "--dest", path]) == 0
    return path


@pytest.mark.parametrize("arg", ["ros.namespace=bad ns", "webui.port=70000", "ros.domain-id=300", "nokey"])
def test_bad_values_exit_2_before_any_robot(demo: str, capsys: pytest.CaptureFixture[str], arg: str) -> None:
    capsys.readouterr()
    assert main(["-i", demo, "webui", "set", arg, "--all", "--yes"]) == 2
    err = capsys.readouterr().err
    assert "inventory:" not in err  # refused before the inventory was even loaded: nothing contacted
    assert "nothing was sent" in err or "KEY=VALUE" in err


def test_demo_fleet_webui_status_as_recorded(demo: str, capsys: pytest.CaptureFixture[str]) -> None:
    capsys.readouterr()
    assert main(["-i", demo, "webui", "status", "--all", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    data = {r["robot"]: r["data"] for r in doc["robots"]}
    assert data["panther-01"]["running"] is True and data["panther-01"]["ui_http"] == 200
    assert data["panther-01"]["settings"]["ros.transport"] == "rmw_cyclonedds_cpp"
    assert data["panther-02"] == {"recorded": True, "installed": False}
    assert data["panther-03"]["running"] is False and data["panther-03"]["ui_http"] is None
    assert all(d["recorded"] for d in data.values())
    assert [r["outcome"] for r in doc["robots"]] == ["ok", "skipped", "ok"]


def test_status_has_a_webui_column_from_the_recording(demo: str, capsys: pytest.CaptureFixture[str]) -> None:
    capsys.readouterr()
    assert main(["-i", demo, "status", "--all", "--json"]) == 0
    data = {r["robot"]: r["data"]["webui"] for r in json.loads(capsys.readouterr().out)["robots"]}
    assert data == {"panther-01": {"installed": True, "running": True, "port": "8080"}, "panther-02": None,
                    "panther-03": {"installed": True, "running": False, "port": "8080"}}
    (Path(demo) / "robots/panther-01/var/lib/panther-ops-demo/ros.json").unlink()  # a fleet from before
    assert main(["-i", demo, "status", "-r", "panther-01", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["robots"][0]["data"]["webui"] is None


def test_demo_fleet_changes_are_planned_on_the_recording_and_skipped(demo: str,
                                                                      capsys: pytest.CaptureFixture[str]) -> None:
    """url and set's plan read the recording; a change a demo robot would need is skipped, one it
    does not need is ok, and a robot without a recorded User Computer is skipped."""
    def run(*argv: str) -> tuple[int, dict[str, dict[str, object]]]:
        capsys.readouterr()
        code = main(["-i", demo, "webui", *argv, "--json"])
        return code, {r["robot"]: r for r in json.loads(capsys.readouterr().out)["robots"]}

    code, got = run("url", "-r", "panther-01")
    assert code == 0 and got["panther-01"]["data"] == {
        "lan": "http://10.15.20.3:8080/ui", "husarnet": "http://<husarnet-hostname>:8080/ui", "port": "8080"}
    code, got = run("set", "webui.port=8081", "-r", "panther-01", "--dry-run")
    assert code == 0 and got["panther-01"]["data"]["plan"] == [{"key": "webui.port", "current": "8080", "new": "8081"}]
    code, got = run("set", "webui.port=8081", "-r", "panther-01", "--yes")
    assert code == 0 and got["panther-01"]["outcome"] == "skipped"
    code, got = run("start", "-r", "panther-01", "-r", "panther-03")
    assert code == 0 and got["panther-01"]["message"] == "already running"
    assert got["panther-03"]["outcome"] == "skipped"
    code, got = run("install", "-r", "panther-01")
    assert code == 0 and got["panther-01"]["outcome"] == "ok"
    # a demo robot without a recorded User Computer: skipped with why by every webui command alike
    # (as `apply` skips its WebUI), never a failure in one and ok or skipped in a sibling
    for argv in (["status"], ["get"], ["url"], ["start"], ["stop"], ["install"], ["set", "webui.port=8081", "--yes"],
                 ["set", "webui.port=8081", "--dry-run"]):
        code, got = run(*argv, "-r", "panther-02")
        assert code == 0 and got["panther-02"]["outcome"] == "skipped", argv
        assert got["panther-02"]["message"] == "demo robot: no User Computer recorded (the WebUI runs on one)"


def test_webui_set_says_nothing_to_change_only_when_nothing_failed(demo: str,
                                                                  capsys: pytest.CaptureFixture[str]) -> None:
    capsys.readouterr()
    assert main(["-i", demo, "webui", "set", "webui.port=8080", "-r", "panther-01", "--yes"]) == 0
    assert "nothing to change" in capsys.readouterr().err
    assert main(["-i", demo, "webui", "set", "webui.port=8081", "-r", "panther-02", "--yes"]) == 0
    assert "nothing to change" not in capsys.readouterr().err  # beside a skip (or a failure) it is not said
