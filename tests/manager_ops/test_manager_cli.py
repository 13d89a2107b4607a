from __future__ import annotations

import json
from pathlib import Path

import pytest
from PIL import Image

from panther_ops.cli.app import main
from panther_ops.core.fleet.templates import template_path
from panther_ops.core.manager_ops.lights import service_call_argv


def test_bt_validate_shipped_projects(capsys: pytest.CaptureFixture[str]) -> None:
    for name in ("PantherLightsBT.btproj", "PantherSafetyBT.btproj"):
        assert main(["bt", "validate", str(template_path("behavior_trees", name)), "--json"]) == 0
        doc = json.loads(capsys.readouterr().out)
        assert doc["valid"] is True


def test_bt_validate_refuses_a_broken_tree(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.xml"
    bad.write_text('<root BTCPP_format="4"><BehaviorTree ID="Lights"><NoSuchNode/></BehaviorTree></root>')
    assert main(["bt", "validate", str(bad), "--json"]) == 2
    doc = json.loads(capsys.readouterr().out)
    assert doc["valid"] is False and any("NoSuchNode" in f["message"] for f in doc["findings"])


def test_lights_validate_and_preview(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    img = tmp_path / "strip.png"
    Image.new("L", (46, 2), 255).save(img)
    anim = tmp_path / "anims.yaml"
    anim.write_text(
        "user_animations:\n"
        "  - id: 21\n    name: WHITE\n    priority: 2\n    animations:\n"
        f"      - type: panther_lights::ImageAnimation\n        segments: all\n        animation:\n"
        f"          image: {img}\n          duration: 0.2\n          repeat: 1\n          color: 0x00FF00\n"
    )
    assert main(["lights", "validate", str(anim)]) == 0
    out = tmp_path / "a.gif"
    assert main(["lights", "preview", str(anim), "--id", "21", "--out", str(out)]) == 0
    assert "10 frames" in capsys.readouterr().out
    with Image.open(out) as gif:
        assert gif.n_frames == 10
    anim.write_text(anim.read_text().replace("id: 21", "id: 3"))
    assert main(["lights", "validate", str(anim)]) == 2


def test_manager_run_sim_json(capsys: pytest.CaptureFixture[str]) -> None:
    scen = template_path("manager", "scenarios", "battery_overheat.yaml")
    assert main(["manager", "run", "--sim", "--scenario", str(scen), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)  # one document: the snapshot of every tick
    lines = doc["snapshots"]
    calls = [c for s in lines for c in s["calls"]]
    assert any("e_stop_trigger" in c for c in calls)
    assert any(s["e_stop"] for s in lines)


def test_manager_run_needs_sim(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["manager", "run"]) == 2
    assert "--sim" in capsys.readouterr().err


def test_set_animation_argv_is_the_manuals_call() -> None:
    from panther_ops.manager.adapters.interfaces import interfaces_for

    argv = service_call_argv(interfaces_for((2, 1, 1)), "panther", 0, "", True)
    assert argv == ["ros2", "service", "call", "/panther/lights/set_animation", "panther_msgs/srv/SetLEDAnimation",
                    '{animation: {id: 0, param: ""}, repeating: true}']
    ugv = service_call_argv(interfaces_for((2, 2, 2)), "", 9, "0.5", False)
    assert ugv[3:5] == ["/lights/set_animation", "husarion_ugv_msgs/srv/SetLEDAnimation"]
    assert service_call_argv(interfaces_for((2, 0, 4)), "/panther/", 1, "", False)[3:5] == [
        "/panther/lights/controller/set/animation", "panther_msgs/srv/SetLEDAnimation"]


class _Driver:
    """The driver container as `lights test` runs the call there: (exit, output) of exec_run."""

    def __init__(self, code: int, output: str) -> None:
        self.code, self.output, self.argv = code, output, None

    def exec_run(self, argv: list[str], demux: bool = False) -> tuple[int, bytes]:
        self.argv = argv
        return self.code, self.output.encode()


def test_lights_test_is_bounded_and_judges_the_controllers_answer() -> None:
    """`ros2 service call` waits for ever for a service nobody serves (another release's name:
    2.0's lights/controller/set/animation vs 2.1+'s lights/set_animation); the controller answers
    success=False for an animation it lacks (husarion_ugv_ros@2.0.4 controller_node.cpp)."""
    from panther_ops.core.manager_ops.lights import CALL_TIMEOUT_S, call_in
    from panther_ops.manager.adapters.interfaces import interfaces_for

    argv = service_call_argv(interfaces_for((2, 0, 4)), "panther", 21, "", True)
    req = "requester: making request: panther_msgs.srv.SetLEDAnimation_Request(...)\n\nresponse:\n"
    ok = _Driver(0, req + "panther_msgs.srv.SetLEDAnimation_Response(success=True, message='')\n")
    res = call_in("r1", ok, argv, 21, "panther_ros 2.0")
    assert res.outcome.value == "changed" and ok.argv == ["/ros_entrypoint.sh", "timeout", str(CALL_TIMEOUT_S), *argv]
    refused = _Driver(0, req + "panther_msgs.srv.SetLEDAnimation_Response(success=False, "
                               "message='No animation with ID: 21')\n")
    res = call_in("r1", refused, argv, 21, "panther_ros 2.0")
    assert res.outcome.value == "failed" and "refused animation 21: No animation with ID: 21" in res.message
    for code in (124, 0):  # timed out; or a CLI that gave up waiting without an answer
        res = call_in("r1", _Driver(code, "waiting for service to become available...\n"), argv, 21, "panther_ros 2.0")
        assert res.outcome.value == "failed" and "no answer from /panther/lights/controller/set/animation" in res.message
