"""BT.CPP v4 projects: the shipped XML trees decide like the Python trees, scenario by
scenario; loading, building and validating projects."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from py_trees.common import Status

from panther_ops.manager.bt.project import load_bt_project
from panther_ops.manager.bt.validate import validate_bt_project
from panther_ops.manager.clock import ManualClock
from panther_ops.manager.errors import BtProjectError
from panther_ops.manager.findings import Severity
from panther_ops.manager.paths import (
    BEHAVIOR_TREES,
    SCENARIOS,
    default_lights_project,
    default_safety_project,
)
from panther_ops.manager.runtime import TreeSource
from panther_ops.manager.sim.runner import run_simulation
from panther_ops.manager.sim.scenario import load_scenario, parse_scenario
from tests.manager.doubles import FakeRobotIO, make_ctx, tick

XML = TreeSource.projects(str(default_lights_project()), str(default_safety_project()))
EXTRA_SCENARIOS: dict[str, dict[str, Any]] = {
    "overheat-58": {"robot": {"bat_temp": 30}, "events": [{"at": 70, "set": {"bat_temp": 58}}]},
    "overheat-63": {"robot": {"bat_temp": 30}, "events": [{"at": 5, "ramp": {"bat_temp": 63},
                                                           "over": 10}]},
    "overvoltage-charging": {"robot": {"charger": True},
                             "events": [{"at": 10, "set": {"health": "OVERVOLTAGE"}}]},
    "unknown-status": {"events": [{"at": 5, "set": {"status": "UNKNOWN"}},
                                  {"at": 15, "set": {"status": "auto"}}]},
    "critical": {"robot": {"charge": 0.05, "e_stop": True}},
    "driver-hysteresis": {"events": [{"at": 70, "set": {"driver_rear_temp": 47}},
                                     {"at": 140, "set": {"driver_rear_temp": 33}}]},
}


def trace(scenario: Any, trees: TreeSource | None) -> list[tuple[int, tuple[str, ...], str]]:
    """Per tick: the service calls made and the manager mode."""
    return [(s.tick, s.calls, s.mode) for s in run_simulation(scenario, trees=trees)]


@pytest.mark.parametrize("path", sorted(SCENARIOS.glob("*.yaml")), ids=lambda p: p.stem)
def test_shipped_xml_trees_decide_like_the_python_trees(path: Path) -> None:
    scenario = load_scenario(path)
    python, xml = trace(scenario, None), trace(scenario, XML)
    assert python == xml
    assert sum(len(c) for _, c, _ in python) >= 2


@pytest.mark.parametrize("name", sorted(EXTRA_SCENARIOS))
def test_same_decisions_in_fault_scenarios(name: str) -> None:
    scenario = parse_scenario({"duration": 160, **EXTRA_SCENARIOS[name]}, name)
    assert trace(scenario, None) == trace(scenario, XML)


def test_shipped_projects_validate_cleanly() -> None:
    assert validate_bt_project(default_lights_project()) == []
    assert validate_bt_project(default_safety_project()) == []


def test_project_loads_included_files_and_trees_by_id() -> None:
    project = load_bt_project(default_safety_project())
    assert set(project.trees) == {"Safety", "Shutdown"}
    assert [p.name for p in project.files] == ["PantherSafetyBT.btproj", "safety.xml",
                                               "shutdown.xml"]
    assert {"CallSetBoolService", "ShutdownSingleHost", "TickAfterTimeout"} <= set(project.models)
    assert project.models["ShutdownSingleHost"].ports["port"] == "22"


def write(path: Path, body: str) -> Path:
    path.write_text(f'<?xml version="1.0"?>\n<root BTCPP_format="4">\n{body}\n</root>\n')
    return path


@pytest.mark.parametrize(("files", "message"), [
    ({"main.xml": '<include path="missing.xml"/>'}, "does not exist"),
    ({"main.xml": '<include path="a.xml"/>', "a.xml": '<include path="main.xml"/>'}, "include cycle"),
    ({"main.xml": '<BehaviorTree ID="T"><AlwaysSuccess/></BehaviorTree><include path="a.xml"/>',
      "a.xml": '<BehaviorTree ID="T"><AlwaysSuccess/></BehaviorTree>'}, "already defined"),
    ({"main.xml": "<BehaviorTree><AlwaysSuccess/></BehaviorTree>"}, "without an ID"),
])
def test_project_errors(tmp_path: Path, files: dict[str, str], message: str) -> None:
    for name, body in files.items():
        write(tmp_path / name, body)
    with pytest.raises(BtProjectError, match=message):
        load_bt_project(tmp_path / "main.xml")
    (tmp_path / "bad.xml").write_text("<root><oops></root>")
    with pytest.raises(BtProjectError, match="not well-formed"):
        load_bt_project(tmp_path / "bad.xml")


SUBTREES = """
<BehaviorTree ID="Main">
  <Sequence>
    <Script code="counter := 1; label := 'main'"/>
    <SubTree ID="Bump" _autoremap="true"/>
    <SubTree ID="Private" value="{counter}" literal="7"/>
    <Action ID="CallTriggerService" service_name="hardware/e_stop_trigger" _skipIf="counter != 2"/>
  </Sequence>
</BehaviorTree>
<BehaviorTree ID="Bump">
  <Script code="counter += 1"/>
</BehaviorTree>
<BehaviorTree ID="Private">
  <Sequence>
    <Script code="label := 'private'; total := value + literal"/>
    <Script code="@result := total"/>
  </Sequence>
</BehaviorTree>
"""


def test_subtrees_remap_autoremap_keep_private_names_and_reach_the_root(tmp_path: Path,
                                                                      clock: ManualClock) -> None:
    project = load_bt_project(write(tmp_path / "t.xml", SUBTREES))
    io = FakeRobotIO()
    ctx = make_ctx(io, clock)
    root = project.build("Main", ctx)
    assert tick(root) == Status.RUNNING  # the v3-style <Action ID=...> sends its request
    entries = ctx.blackboard.entries()
    assert entries["counter"] == 2 and entries["label"] == "main" and entries["result"] == 9
    private = {k: v for k, v in entries.items() if "/" in k}
    assert sorted(v for k, v in private.items() if k.endswith("/label")) == ["private"]
    assert io.requests == ["hardware/e_stop_trigger()"]


@pytest.mark.parametrize(("body", "message"), [
    ('<BehaviorTree ID="T"><Teleport/></BehaviorTree>', "unknown node <Teleport>"),
    ('<BehaviorTree ID="T"><Inverter><AlwaysSuccess/><AlwaysSuccess/></Inverter></BehaviorTree>',
     "cannot have 2 children"),
    ('<BehaviorTree ID="T"><CallTriggerService service="x"/></BehaviorTree>', "unknown port 'service'"),
    ('<BehaviorTree ID="T"><CallSetBoolService service_name="x" data="maybe"/></BehaviorTree>',
     "expected bool"),
    ('<BehaviorTree ID="T"><AlwaysSuccess _skipIf="a &amp;&amp;"/></BehaviorTree>', "expected more input"),
    ('<BehaviorTree ID="T"><SubTree ID="Nope"/></BehaviorTree>', "no tree 'Nope'"),
])
def test_build_errors_name_the_node(tmp_path: Path, clock: ManualClock, body: str, message: str) -> None:
    project = load_bt_project(write(tmp_path / "t.xml", body))
    with pytest.raises(BtProjectError, match=message) as raised:
        project.build("T", make_ctx(FakeRobotIO(), clock))
    assert "t.xml: T/" in str(raised.value)


def codes(findings: list[Any]) -> list[str]:
    return [f.code for f in findings]


def test_validate_reports_each_problem(tmp_path: Path) -> None:
    write(tmp_path / "lights.xml", """
      <BehaviorTree ID="Lights">
        <Sequence>
          <Teleport/>
          <CallSetLedAnimationService id="{ERROR_ANIM_ID}" service_name="lights/set_animation"
                                      colour="red"/>
          <CallSetLedAnimationService service_name="lights/set_animation" _skipIf="(("/>
          <CallSetLedAnimationService id="2" service_name="s" _skipIf="moon_phase == 3"
                                      _description="x"/>
          <CallSetBoolService service_name="s" data="perhaps"/>
        </Sequence>
      </BehaviorTree>""")
    (tmp_path / "old.xml").write_text('<root BTCPP_format="3"><BehaviorTree ID="Other">'
                                      "<AlwaysSuccess/></BehaviorTree></root>")
    project = write(tmp_path / "P.btproj", '<include path="lights.xml"/><include path="old.xml"/>')
    found = validate_bt_project(project)
    assert sorted(codes(found)) == sorted([
        "bt-node-unknown", "bt-port-unknown", "bt-port-missing", "bt-script-syntax",
        "bt-name-unknown", "bt-attribute-ignored", "bt-port-value", "bt-format"])
    assert len({f.message for f in found}) == len(found)


def test_validate_requires_the_trees_of_a_project(tmp_path: Path) -> None:
    only_safety = write(tmp_path / "s.btproj", f'<include path="{BEHAVIOR_TREES / "safety.xml"}"/>')
    assert codes(validate_bt_project(only_safety)) == ["bt-tree-missing"]
    neither = write(tmp_path / "n.btproj", '<BehaviorTree ID="Main"><AlwaysSuccess/></BehaviorTree>')
    assert codes(validate_bt_project(neither)) == ["bt-tree-missing"]
    assert codes(validate_bt_project(tmp_path / "missing.btproj")) == ["bt-project-unreadable"]


def test_validate_warns_when_a_custom_safety_tree_drops_a_default_behaviour(tmp_path: Path) -> None:
    safety = (BEHAVIOR_TREES / "safety.xml").read_text()
    without_e_stop = safety.replace('service_name="hardware/e_stop_trigger"',
                                    'service_name="hardware/e_stop_reset"')
    (tmp_path / "safety.xml").write_text(without_e_stop)
    (tmp_path / "shutdown.xml").write_text((BEHAVIOR_TREES / "shutdown.xml").read_text()
                                           .replace("ExecuteCommand", "AlwaysSuccess")
                                           .replace(' command="{SHUTDOWN_LOCALHOST_COMMAND}" '
                                                    'timeout="5.0"', ""))
    project = write(tmp_path / "Custom.btproj",
                    '<include path="safety.xml"/><include path="shutdown.xml"/>')
    found = validate_bt_project(project)
    assert [f.severity for f in found] == [Severity.WARNING, Severity.WARNING]
    assert codes(found) == ["bt-safety-dropped", "bt-safety-dropped"]
    assert "trigger the E-stop" in found[0].message
    assert "shut the robot itself down" in found[1].message


UPSTREAM_STYLE = r"""
<BehaviorTree ID="Safety">
  <Sequence>
    <Sequence name="BatteryOverheatSequence"
              _skipIf="battery_health != POWER_SUPPLY_HEALTH_OVERHEAT">
      <Sequence name="FatalBatTempSequence" _skipIf="bat_temp &lt;= FATAL_BAT_TEMP">
        <SignalShutdown message="Fatal battery temperature"/>
      </Sequence>
    </Sequence>
    <TickAfterTimeout timeout="{FAN_TURN_OFF_TIMEOUT}">
      <CallSetBoolService data="false" service_name="hardware/fan_enable"
                          _skipIf="cpu_temp &gt; CPU_FAN_OFF_TEMP \
|| driver_temp &gt; DRIVER_FAN_OFF_TEMP \
|| (!fan_state)"/>
    </TickAfterTimeout>
  </Sequence>
</BehaviorTree>
<BehaviorTree ID="Shutdown">
  <Sequence>
    <ForceSuccess><ShutdownHostsFromFile shutdown_host_file="{SHUTDOWN_HOSTS_FILE}"/></ForceSuccess>
    <ShutdownSingleHost ip="localhost" username="husarion" port="22" command="sudo shutdown now"
                        timeout="5.0" ping_for_success="false"/>
  </Sequence>
</BehaviorTree>
"""


def test_upstream_style_files_load_with_both_port_spellings(tmp_path: Path, clock: ManualClock) -> None:
    """Line continuations, `message`/`shutdown_host_file`, SHUTDOWN_HOSTS_FILE, localhost SSH."""
    path = write(tmp_path / "upstream.xml", UPSTREAM_STYLE)
    findings = validate_bt_project(path)
    assert "bt-port-unknown" not in codes(findings) and "bt-name-unknown" not in codes(findings)
    assert "shut the robot itself down" not in " ".join(f.message for f in findings)
    ctx = make_ctx(FakeRobotIO(), clock, {"battery_health": 2, "POWER_SUPPLY_HEALTH_OVERHEAT": 2,
                                          "bat_temp": 63.0, "FATAL_BAT_TEMP": 62.0,
                                          "FAN_TURN_OFF_TIMEOUT": 60.0, "signal_shutdown": (False, "")})
    tree = load_bt_project(path).build("Safety", ctx)
    tree.setup_with_descendants()
    assert tick(tree) == Status.SUCCESS
    assert ctx.blackboard.get("signal_shutdown") == (True, "Fatal battery temperature")
