"""`estop reset`'s plan (pure): from the E-stop's state and the publishers of cmd_vel as the
driver told them (`calls.py` asks), whether a reset is needed and possible. A node publishing on
cmd_vel refuses the reset, naming the node (the manual: no reset while messages arrive); an
E-stop not triggered is left alone. The reset itself is `apply.py`'s executor.

husarion_ugv 2.3.2 (its twist mux subscribes cmd_vel): the driver refuses a reset while the last
velocity commands are not zero (husarion_ugv_ros@2.3.2:husarion_ugv_hardware_interfaces/src/
robot_system/system_e_stop.cpp `EStop::ResetEStop`, `ZeroVelocityCheck` =
ugv_system.cpp `AreVelocityCommandsNearZero`), and the mux forwards the highest-priority input that
had a message within its 0.2 s timeout, else zero (husarion/husarion_controllers:
twist_mux_controller/src/twist_mux_controller.cpp; inputs manual/cmd_vel 100, autonomous/cmd_vel
10, cmd_vel 1 in husarion_ugv_controller/config/WH01_controller.yaml). A publisher of zero
velocity (joy2twist on manual/cmd_vel: bringup always runs it on 2.3.2) does not block it, so
the plan does not refuse on publishers there: it names them, the driver judges, and its refusal
comes back with the publishers to stop (`nonzero_hint`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from panther_ops.core.fleet.plan import RobotPlan, Step
from panther_ops.core.remote.estop import answers
from panther_ops.errors import RemoteStateError

E_STOP_TOPIC = "hardware/e_stop"
TRIGGER_SERVICE = "hardware/e_stop_trigger"
RESET_SERVICE = "hardware/e_stop_reset"
CMD_VEL = "cmd_vel"
MUX_INPUTS = ("manual/cmd_vel", "autonomous/cmd_vel", CMD_VEL)
"""The twist mux's velocity inputs on husarion_ugv 2.3.2, highest priority first (100, 10, 1)."""
NONZERO_REFUSAL = "the last velocity commands are not zero"
"""In the 2.3.2 driver's refusal of a reset (system_e_stop.cpp, `EStop::ResetEStop`)."""
ROS_TIMEOUT_S = 10
"""Longest wait of one ROS 2 command on the robot (discovery included)."""


@dataclass(frozen=True)
class ResetEstop(Step):
    """The driver's ``hardware/e_stop_reset`` service called, then the E-stop read back."""


@dataclass
class State:
    """What the driver said about its E-stop and cmd_vel."""

    namespace: str
    triggered: bool | None
    publishers: list[str] | None
    problems: list[str] = field(default_factory=list)
    mux: dict[str, list[str]] | None = None
    """2.3.2: the publishers of each twist mux input (MUX_INPUTS), None without the mux."""

    def topic(self, name: str) -> str:
        return f"{self.namespace.rstrip('/')}/{name}"

    def velocity_publishers(self) -> list[str]:
        """``node on <topic>`` for each publisher the driver's velocity comes from."""
        inputs = self.mux if self.mux is not None else {CMD_VEL: self.publishers or []}
        return [f"{node} on {self.topic(t)}" for t, nodes in inputs.items() for node in nodes]

    def to_json(self) -> dict[str, Any]:
        data: dict[str, Any] = {"namespace": self.namespace, "e_stop": self.triggered,
                                "cmd_vel_publishers": self.publishers}
        if self.mux is not None:
            data["twist_mux_publishers"] = {self.topic(t): nodes for t, nodes in self.mux.items()}
        return data


def state_of(got: answers.Answers) -> State:
    state = State(got.namespace, None, None)
    status, pubs = got.get("status"), got.get("publishers")
    if status is not None:
        state.triggered = answers.e_stop_state(status.text)
        if state.triggered is None:
            state.problems.append(f"no message on {state.topic(E_STOP_TOPIC)} within {ROS_TIMEOUT_S} s"
                                  + answer_tail(status.text))
    if pubs is not None:
        state.publishers = answers.publishers(pubs.text)
        if state.publishers is None:
            state.problems.append(f"no answer about {state.topic(CMD_VEL)}" + answer_tail(pubs.text))
        elif answers.muxed(pubs.text):
            state.mux = {}
            for topic in MUX_INPUTS:
                section = pubs if topic == CMD_VEL else got.get("publishers_" + topic.split("/")[0])
                nodes = answers.publishers(section.text) if section is not None else None
                if nodes is None:
                    state.problems.append(f"no answer about {state.topic(topic)}"
                                          + answer_tail(section.text if section is not None else ""))
                state.mux[topic] = nodes or []
    return state


def answer_tail(text: str) -> str:
    lines = [ln for ln in text.strip().splitlines() if ln.strip() and "waiting for service" not in ln]
    return f": {lines[-1][-200:]}" if lines else ""


def state_text(state: State) -> str:
    what = {True: "E-stop triggered", False: "E-stop released", None: "E-stop state unknown"}[state.triggered]
    if state.mux is not None:
        seen = state.velocity_publishers()
        what += f"; publishing: {', '.join(seen)}" if seen else ""
    elif state.publishers:
        what += f"; publishing on {state.topic(CMD_VEL)}: {', '.join(state.publishers)}"
    return what


def nonzero_hint(planned: dict[str, Any]) -> str:
    """What to do when the 2.3.2 driver refused a reset for non-zero velocity: the publishers the
    plan saw on the mux inputs (``planned``: `State.to_json`), else the inputs to look at."""
    inputs: dict[str, list[str]] = planned.get("twist_mux_publishers") or {}
    named = [f"{node} on {topic}" for topic, nodes in inputs.items() for node in nodes]
    if named:
        return f"stop {', '.join(named)} or make it send zero velocity, then reset again"
    return ("make every node publishing on " + ", ".join(MUX_INPUTS)
            + " stop or send zero velocity, then reset again")


def plan_reset(robot: str, state: State) -> RobotPlan:
    """`estop reset` on one robot: a reset when the E-stop is triggered and nobody publishes on
    cmd_vel; nothing when it is not triggered; refused (RemoteStateError) otherwise."""
    if state.problems:
        raise RemoteStateError("; ".join(state.problems))
    data: dict[str, Any] = state.to_json()
    if state.triggered is False:
        return RobotPlan(robot, "", noop="E-stop not triggered: nothing to reset"
                         + (f" ({state_text(state)})" if state.publishers else ""), data=data)
    if state.mux is not None:
        seen = state.velocity_publishers()
        return RobotPlan(robot, "reset the E-stop (triggered; the driver refuses it while the last velocity command "
                         "is not zero" + (f"; publishing: {', '.join(seen)})" if seen else
                                          "; nobody publishes on its velocity inputs)"), data=data,
                         steps=[ResetEstop()])
    if state.publishers:
        raise RemoteStateError(f"refused: {', '.join(state.publishers)} publishes on {state.topic(CMD_VEL)} "
                               "(no reset while messages arrive)",
                               hint=f"stop {state.publishers[0]}, then reset again")
    return RobotPlan(robot, f"reset the E-stop (triggered; nobody publishes on {state.topic(CMD_VEL)})", data=data,
                     steps=[ResetEstop()])
