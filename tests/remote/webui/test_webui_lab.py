"""Issue-14 WebUI acceptance on the lab: `webui install|set|get|start|stop|status|url` on User
Computers behind the robots (namespaces with a real sshd and sudo, reached with fabric through
the robot's connection), the lab's `snap` stand-in for husarion-webui (its configuration, the
configure hook's rules as husarion-snap-common@0.13.0 states them, a real HTTP server answering
/ui on webui.port while started)."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml

from tests.clirun import run_cli
from tests.lab import Lab
from tests.lab.computers import ComputerSpec
from tests.labtools import computers_lab, user_computer_inventory

pytestmark = pytest.mark.lab

W1_PASSWORD = "w1-lab-sudo-password"
STATE = "/var/lib/snapd-standin/husarion-webui.json"


@pytest.fixture(scope="module")
def wlab(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[Lab, Path]]:
    with computers_lab(
        ComputerSpec("w1", behind="r01", password=W1_PASSWORD, admin="group", webui=True),  # sudo asks
        ComputerSpec("w2", behind="r02", admin="nopasswd", webui=True),
        images=("2.1.1", "2.3.2"),  # r02: husarion_ugv 2.3.2 (Jazzy), its User Computer's WebUI as on Humble
    ) as lab:
        path = tmp_path_factory.mktemp("webui") / "inventory.yaml"
        yield lab, user_computer_inventory(lab, path, {"r01": "w1", "r02": "w2"})


def cli(capsys: pytest.CaptureFixture[str], inventory: Path, *argv: str) -> tuple[int, dict[str, Any], str]:
    code, doc, _, err = run_cli(capsys, "-i", str(inventory), *argv)
    return code, doc, err


def ui_status(lab: Lab, robot: str, computer: str, port: int) -> str:
    """The HTTP status of http://<computer>:<port>/ui fetched on the robot (000: no answer)."""
    url = f"http://{lab.computer(computer).ip}:{port}/ui"
    return str(lab.exec(robot, ["curl", "-s", "-o", "/dev/null", "-m", "3", "-w", "%{http_code}", url]).stdout)


def snap_state(lab: Lab, computer: str) -> str:
    return str(lab.exec(computer, ["sh", "-c", f"cat {STATE} 2>/dev/null || echo none"]).stdout)


def without_namespace_on_8080(lab: Lab, computer: str) -> None:
    """The computer's snap stand-in without a namespace (as a fresh install leaves it), on its
    default port, restarted (also docs/remote.md's lab, tests/ux/doclab.py)."""
    lab.exec(computer, ["python3", "-c", "import json,sys; p=sys.argv[1]; d=json.load(open(p)); "
                        "d['config'].get('ros', {}).pop('namespace', None); d['config'].setdefault('webui', {})"
                        "['port']='8080'; json.dump(d, open(p, 'w'))", STATE])
    lab.exec(computer, ["sh", "-c", "husarion-webui.stop; husarion-webui.start"])


def test_install_set_start_with_password_sudo_then_idempotent_then_port(
        wlab: tuple[Lab, Path], capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    lab, inv = wlab
    monkeypatch.setenv("PANTHER_OPS_SUDO_PASSWORD", W1_PASSWORD)
    steps = [("webui", "install", "-r", "r01", "--json"),
             ("webui", "set", "ros.namespace=panther", "ros.transport=rmw_cyclonedds_cpp", "webui.layout=panther",
              "-r", "r01", "--yes", "--json"),
             ("webui", "start", "-r", "r01", "--json")]
    for argv in steps:
        code, doc, err = cli(capsys, inv, *argv)
        assert code == 0, err
        assert doc["robots"][0]["outcome"] == "changed", doc
    code, doc, _ = cli(capsys, inv, "webui", "status", "-r", "r01", "--json")
    data = doc["robots"][0]["data"]
    assert data["installed"] and data["channel"] == "humble/stable" and data["running"] is True
    assert data["settings"] == {"ros.namespace": "panther", "ros.transport": "rmw_cyclonedds_cpp",
                                "ros.domain-id": "0", "ros.localhost-only": "", "webui.layout": "panther",
                                "webui.port": "8080"}
    assert data["ui_http"] == 200 and data["url"] == f"http://{lab.computer('w1').ip}:8080/ui"
    assert W1_PASSWORD not in json.dumps(doc)

    before = snap_state(lab, "w1")
    for argv in steps:  # a second run changes nothing
        code, doc, err = cli(capsys, inv, *argv)
        assert code == 0 and doc["robots"][0]["outcome"] == "ok", doc
    assert snap_state(lab, "w1") == before

    code, doc, err = cli(capsys, inv, "webui", "set", "webui.port=8081", "-r", "r01", "--yes", "--json")
    assert code == 0 and doc["robots"][0]["data"]["restarted"] is True, err
    assert ui_status(lab, "r01", "w1", 8081) == "200"
    assert ui_status(lab, "r01", "w1", 8080) == "000"
    code, doc, _ = cli(capsys, inv, "webui", "url", "-r", "r01", "--json")
    assert doc["robots"][0]["data"]["lan"] == f"http://{lab.computer('w1').ip}:8081/ui"

    # `panther-ops status`: the WebUI column (read without sudo), r02's not installed yet or installed
    code, doc, _ = cli(capsys, inv, "status", "-r", "r01", "--json")
    url = f"http://{lab.computer('w1').ip}:8081/ui"
    assert doc["robots"][0]["data"]["webui"] == {"installed": True, "running": True, "port": "8081", "url": url}

    code, doc, _ = cli(capsys, inv, "webui", "stop", "-r", "r01", "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "changed"
    assert ui_status(lab, "r01", "w1", 8081) == "000"
    code, doc, _ = cli(capsys, inv, "status", "-r", "r01", "--json")
    assert doc["robots"][0]["data"]["webui"] == {"installed": True, "running": False, "port": "8081", "url": url}


def test_without_the_password_sudo_fails_with_the_way_out(wlab: tuple[Lab, Path],
                                                         capsys: pytest.CaptureFixture[str],
                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    _lab, inv = wlab
    monkeypatch.delenv("PANTHER_OPS_SUDO_PASSWORD", raising=False)
    code, doc, _ = cli(capsys, inv, "webui", "install", "-r", "r01", "--channel", "humble/edge", "--json")
    assert code == 3
    assert "needs a password" in doc["robots"][0]["message"]
    assert "--ask-sudo-password" in doc["robots"][0]["data"]["hint"]


@pytest.mark.parametrize("arg", ["ros.namespace=bad ns", "webui.port=70000", "ros.domain-id=300",
                                 "ros.transport=no-such-profile", "ros.namespace=panther-01"])
def test_bad_values_exit_2_nothing_sent(wlab: tuple[Lab, Path], capsys: pytest.CaptureFixture[str], arg: str) -> None:
    lab, inv = wlab
    assert cli(capsys, inv, "webui", "install", "-r", "r02")[0] == 0
    before = snap_state(lab, "w2")
    code, _doc, err = cli(capsys, inv, "webui", "set", arg, "-r", "r02", "--yes", "--json")
    assert code == 2, err
    assert "not allowed" in err and "nothing was sent" in err
    assert snap_state(lab, "w2") == before


FASTDDS = ('<?xml version="1.0" encoding="UTF-8" ?>\n'
           '<profiles xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">\n'
           '  <participant profile_name="lab" is_default_profile="true"><rtps/></participant>\n</profiles>\n')


def test_dds_file_not_xml_refused_and_a_good_one_uploaded_and_selected(
        wlab: tuple[Lab, Path], capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    """The configure hook resolves ros.transport=<X> to <common>/dds-config-<X>.xml and detects
    its type (husarion-snap-common@0.13.0): the profile is uploaded there and the snap selects it."""
    lab, inv = wlab
    assert cli(capsys, inv, "webui", "install", "-r", "r02")[0] == 0
    before = snap_state(lab, "w2")
    for text, why in (("transport: udp\n", "well-formed XML"),
                      ('<?xml version="1.0"?>\n<dds><profiles><transport_descriptors/></profiles></dds>\n', "not <dds>")):
        bad = tmp_path / "lab-profile.xml"
        bad.write_text(text)
        code, _, err = cli(capsys, inv, "webui", "set", "--dds-file", str(bad), "-r", "r02", "--yes")
        assert code == 2 and why in err, err
        assert snap_state(lab, "w2") == before
    good = tmp_path / "lab-profile.xml"
    good.write_text(FASTDDS)
    code, doc, err = cli(capsys, inv, "webui", "set", "--dds-file", str(good), "-r", "r02", "--yes", "--json")
    assert code == 0, err
    assert doc["robots"][0]["data"]["settings"]["ros.transport"] == "lab-profile"
    common = "/var/snap/husarion-webui/common"
    assert lab.exec("w2", ["cat", f"{common}/dds-config-lab-profile.xml"]).stdout == good.read_text()
    env = lab.exec("w2", ["cat", f"{common}/ros.env"]).stdout  # what the hook made of it
    assert f"export FASTRTPS_DEFAULT_PROFILES_FILE={common}/dds-config-lab-profile.xml" in env
    assert "export RMW_IMPLEMENTATION=rmw_fastrtps_cpp" in env


def test_install_refused_when_a_clock_is_5_s_off(wlab: tuple[Lab, Path], capsys: pytest.CaptureFixture[str]) -> None:
    lab, inv = wlab
    lab.clock_offset("w2", 5)
    try:
        code, doc, _ = cli(capsys, inv, "webui", "install", "-r", "r02", "--channel", "humble/edge", "--json")
        assert code == 3
        r = doc["robots"][0]
        assert r["outcome"] == "failed" and "refused: clocks differ" in r["message"]
        assert abs(r["data"]["clock_offsets"]["user computer vs robot"] - 5) < 1
        assert "chronyc makestep" in r["data"]["hint"]
        assert json.loads(lab.exec("w2", ["cat", STATE]).stdout)["channel"] != "humble/edge"
    finally:
        lab.clock_offset("w2", 0)


def _inventory_with(inv: Path, tmp_path: Path, **robots: dict[str, Any]) -> Path:
    """A copy of the lab inventory with each robot's entries replaced (None: removed)."""
    doc = yaml.safe_load(inv.read_text())
    for name, entries in robots.items():
        for key, value in entries.items():
            if value is None:
                doc["robots"][name].pop(key, None)
            else:
                doc["robots"][name][key] = value
    path = tmp_path / "inventory.yaml"
    path.write_text(yaml.safe_dump(doc))
    return path


def test_apply_converges_desired_webui_with_the_robots_namespace_then_changes_nothing(
        wlab: tuple[Lab, Path], capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    lab, base = wlab
    assert cli(capsys, base, "webui", "install", "-r", "r02")[0] == 0
    code, doc, err = cli(capsys, base, "webui", "start", "-r", "r02", "--json")
    assert code == 0, err
    without_namespace_on_8080(lab, "w2")
    inv = _inventory_with(base, tmp_path, r02={"desired": {"webui": {"transport": "rmw_cyclonedds_cpp",
                                                                     "port": 8082, "layout": "panther"}}})
    code, doc, err = cli(capsys, inv, "config", "diff", "-r", "r02", "--json")
    assert code == 0, err
    r = doc["robots"][0]
    assert r["outcome"] == "changed" and r["data"]["action"] == "webui"
    plan = {p["key"]: (p["current"], p["new"]) for p in r["data"]["webui"]["plan"]}
    assert plan["ros.namespace"] == ("", "panther") and plan["webui.port"] == ("8080", "8082")
    # r02 runs husarion_ugv 2.3.2: ROBOT_NAMESPACE from the env_file its compose.yaml names, as on 2.2
    assert "ROBOT_NAMESPACE in /home/husarion/config/common/.env" in r["data"]["webui"]["namespace"]
    assert "ros.namespace: (unset) -> panther" in r["message"] and r["message"].endswith("and restart it")

    before = snap_state(lab, "w2")
    code, doc, err = cli(capsys, inv, "apply", "-r", "r02", "--dry-run", "--json")
    assert code == 0 and doc["robots"][0]["message"].startswith("would set WebUI "), err
    assert snap_state(lab, "w2") == before

    code, doc, err = cli(capsys, inv, "apply", "-r", "r02", "--yes", "--json")
    assert code == 0, err
    r = doc["robots"][0]
    assert r["outcome"] == "changed" and r["message"].endswith("; restarted it"), r
    assert r["data"]["webui_after"]["settings"]["ros.namespace"] == "panther"
    assert ui_status(lab, "r02", "w2", 8082) == "200" and ui_status(lab, "r02", "w2", 8080) == "000"

    after = snap_state(lab, "w2")
    for argv in (("apply", "-r", "r02", "--yes", "--json"), ("config", "diff", "-r", "r02", "--json")):
        code, doc, err = cli(capsys, inv, *argv)  # a second run changes nothing
        assert code == 0 and doc["robots"][0]["outcome"] == "ok", doc
        assert doc["robots"][0]["message"] == "matches the inventory's desired state"
    assert snap_state(lab, "w2") == after


def test_apply_skips_desired_webui_without_a_user_computer_in_the_inventory(
        wlab: tuple[Lab, Path], capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    lab, base = wlab
    inv = _inventory_with(base, tmp_path, r01={"user_computer": None, "desired": {"webui": {"port": 8083}}})
    before = snap_state(lab, "w1")
    code, doc, err = cli(capsys, inv, "apply", "-r", "r01", "--yes", "--json")
    assert code == 0, err
    r = doc["robots"][0]
    assert r["outcome"] == "ok" and any("no user_computer: for r01" in w for w in r["warnings"]), r
    assert snap_state(lab, "w1") == before
