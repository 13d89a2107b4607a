"""`panther-ops webui` without a lab: the snap's answers parsed, the plan, DDS profiles checked,
bad input refused before any robot is contacted, and the demo fleet's recorded answers."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from panther_ops.cli.app import main
from panther_ops.core.kinds.webui_settings import SettingError, dds_profile
from panther_ops.core.remote.webui.apply import apply_settings
from panther_ops.core.remote.webui.defaults import RobotNamespace
from panther_ops.core.remote.webui.state import parse_state, plan_changes
from panther_ops.transport.base import Command, CommandResult

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
dds-config-my-fastdds.xml
dds-config-udp.xml
foxglove-panther.json
my-old.xml
rmw
@@exit 0
"""


def test_state_parsed_with_defaults_and_the_plan() -> None:
    st = parse_state(STATE)
    assert (st.installed, st.channel, st.revision, st.running) == (True, "humble/stable", "42", False)
    # the configure hook resolves a transport <X> to dds-config-<X>.xml (husarion-snap-common@0.13.0:
    # local-ros/configure_hook_ros.sh); a plain my-old.xml there is no profile of it
    assert st.profiles == {"my-fastdds", "udp"}
    assert st.value("ros.namespace") == "panther" and st.value("webui.layout") == "default"
    assert plan_changes(st, {"ros.namespace": "panther", "webui.port": "8080", "webui.layout": "panther"}) == [
        ("webui.port", "8081", "8080"), ("webui.layout", "default", "panther")]
    assert parse_state(STATE.replace("inactive", "active")).running is True
    assert parse_state('@@list\nerror: snap "husarion-webui" is not installed\n@@exit 1\n').installed is False


FASTDDS = (b'<?xml version="1.0" encoding="UTF-8" ?>\n'
           b'<profiles xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">\n'
           b'  <participant profile_name="lab" is_default_profile="true"><rtps/></participant>\n</profiles>\n')
CYCLONE = (b'<?xml version="1.0" encoding="UTF-8" ?>\n<CycloneDDS xmlns="https://cdds.io/config" '
           b'xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"><Domain id="any"/></CycloneDDS>\n')


def test_dds_profile_checks_are_the_snaps() -> None:
    """husarion-snap-common@0.13.0:local-ros/utils.sh check_xml_profile_type: `yq '. | keys | .[1]'`
    (key 0 the XML declaration) is `profiles` with the Fast DDS xmlns or `CycloneDDS` with cdds.io's."""
    assert dds_profile("fast.xml", FASTDDS) == ("fast", FASTDDS)
    assert dds_profile("cyc.xml", CYCLONE)[0] == "cyc"
    assert dds_profile("dds-config-cyc.xml", CYCLONE)[0] == "cyc"  # a file taken from the snap's directory
    for name, data, why in [("x.xml", b"transport: udp", "well-formed XML"),
                            ("x.xml", b'<?xml version="1.0"?><html/>', "root element <profiles>"),
                            ("x.xml", b'<?xml version="1.0"?><dds><profiles/></dds>', "not <dds>"),
                            ("x.xml", FASTDDS.replace(b"fastRTPS_Profiles", b"other"), "xmlns"),
                            ("x.xml", CYCLONE.split(b"\n", 1)[1], "first line <\\?xml"),
                            ("x.xml", b'<!DOCTYPE d [<!ENTITY a "b">]><dds/>', "without DOCTYPE"),
                            ("udp.xml", FASTDDS, "other than the snap's own transports"),
                            ("rmw_zenoh_cpp.xml", FASTDDS, "other than the snap's own transports"),
                            ("../x.xml", FASTDDS, "file name")]:
        with pytest.raises(SettingError, match=why):
            dds_profile(name, data)


class FakeSession:
    """A User Computer's snap as `apply_settings` sees it: the read, and the sudo commands."""

    def __init__(self, state: str) -> None:
        self.state = state
        self.sudos: list[list[str]] = []
        self.address = type("A", (), {"name": "uc"})()

    def run(self, command: Command, *, timeout: float = 60.0) -> CommandResult:
        return CommandResult("read", 0, self.state, "")

    def sudo(self, command: Command, *, timeout: float = 60.0) -> CommandResult:
        self.sudos.append([str(a) for a in command.argv])
        return CommandResult("sudo", 0, "", "")


def test_dds_file_is_uploaded_where_the_configure_hook_looks_for_it() -> None:
    """`webui set --dds-file lab.xml` selects ros.transport=lab, which the hook resolves to
    <common>/dds-config-lab.xml: the upload goes there, not to <common>/lab.xml."""
    session = FakeSession(STATE)
    apply_settings(session, {"ros.transport": "lab"}, RobotNamespace(None, ""),  # type: ignore[arg-type]
                   ("lab", FASTDDS))
    upload = session.sudos[0]
    assert upload[:2] == ["sh", "-c"] and upload[-1] == "/var/snap/husarion-webui/common/dds-config-lab.xml"
    assert session.sudos[1] == ["snap", "set", "husarion-webui", "ros.transport=lab"]


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
    assert [r["outcome"] for r in doc["robots"]] == ["ok", "skipped", "ok", "ok"]


def test_status_has_a_webui_column_from_the_recording(demo: str, capsys: pytest.CaptureFixture[str]) -> None:
    capsys.readouterr()
    assert main(["-i", demo, "status", "--all", "--json"]) == 0
    data = {r["robot"]: r["data"]["webui"] for r in json.loads(capsys.readouterr().out)["robots"]}
    url = "http://10.15.20.3:8080/ui"  # the recorded User Computer's
    assert data == {"panther-01": {"installed": True, "running": True, "port": "8080", "url": url},
                    "panther-02": None, "panther-03": {"installed": True, "running": False, "port": "8080", "url": url},
                    "panther-04": {"installed": True, "running": False, "port": "8080", "url": url}}
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
