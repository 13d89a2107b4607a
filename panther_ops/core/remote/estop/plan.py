"""`estop reset`'s plan (pure): from the E-stop's state and the velocity publishers as the
driver told them (`calls.py` asks), whether a reset is needed. An E-stop not triggered is left
alone; a triggered one is reset by the driver's service, and the driver alone judges it: the plan
names the publishers, and a refusal comes back with the publishers to stop (`nonzero_hint`).

The manual says "If some messages are being published to /cmd_vel while E-stop is triggered, it is
impossible to reset it"; what every driver checks is the last velocity command (the hardware
interface's wheel commands, the diff drive controller's output), refusing while it is not zero:
* panther_ros 2.0.1-2.1.x: panther_ros@2.1.1:panther_hardware_interfaces/src/panther_system/
  panther_system_e_stop.cpp (2.0.4: src/panther_system_e_stop.cpp) `EStopPTH12X::ResetEStop` /
  `EStopPTH10X::ResetEStop` (`ZeroVelocityCheck` = panther_system.cpp `AreVelocityCommandsNearZero`),
  the class by PANTHER_ROBOT_VERSION (1.2 and up: PTH12X); 2.0.0: panther_system.cpp
  `PantherSystem::ResetEStop` (the PTH10X message);
* husarion_ugv 2.2.x: husarion_ugv_ros@2.2.2:husarion_ugv_hardware_interfaces/src/robot_system/
  system_e_stop.cpp `EStop::ResetEStop` (the PTH12X message);
* husarion_ugv 2.3.2: the same file @2.3.2, behind the twist mux (its subscriber of cmd_vel), which
  forwards the highest-priority input that had a message within its 0.2 s timeout, else zero
  (husarion/husarion_controllers@f4f78b7: twist_mux_controller/src/twist_mux_controller.cpp, the
  mux's merge; 2.3.2 pins the later 2b2b37a in husarion_ugv/hardware_deps.repos; inputs
  manual/cmd_vel 100, autonomous/cmd_vel 10, cmd_vel 1 in husarion_ugv_controller/config/
  WH01_controller.yaml).
Up to 2.2 the diff drive controller drives the wheels from the last cmd_vel message and sends zero
once none came within its ``cmd_vel_timeout`` (0.5 s: panther_ros@2.1.1:panther_controller/config/
WH01_controller.yaml; 0.2 s: husarion_ugv_ros@2.2.2:husarion_ugv_controller/config/WH01_controller.yaml).
A node publishing zero velocity (an idle joy2twist, a stopped planner) therefore never blocks a reset,
and one that stopped publishing blocks it no longer than that timeout."""

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
NONZERO_REFUSALS = ("the last velocity commands are not zero", "last velocity commands are different than zero")
"""In the drivers' refusals of a reset for a non-zero velocity command: `EStopPTH12X::ResetEStop`
(panther_ros 2.0.1-2.1.x), `EStop::ResetEStop` (husarion_ugv 2.2.x, 2.3.x), then `EStopPTH10X::ResetEStop`
(panther_ros 2.0.1-2.1.x on a Panther before 1.2) and 2.0.0's `PantherSystem::ResetEStop`."""
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


def refused_for_velocity(message: str) -> bool:
    """Whether a driver's answer is its refusal of a reset for a non-zero velocity command."""
    return any(text in message for text in NONZERO_REFUSALS)


def nonzero_hint(planned: dict[str, Any]) -> str:
    """What to do when the driver refused a reset for non-zero velocity: the publishers the plan
    saw on the velocity inputs (``planned``: `State.to_json`), else the inputs to look at."""
    mux: dict[str, list[str]] | None = planned.get("twist_mux_publishers")
    ns = str(planned.get("namespace") or "/").rstrip("/")
    inputs = mux if mux is not None else {f"{ns}/{CMD_VEL}": list(planned.get("cmd_vel_publishers") or [])}
    named = [f"{node} on {topic}" for topic, nodes in inputs.items() for node in nodes]
    if named:
        return f"stop {', '.join(named)} or make it send zero velocity, then reset again"
    topics = [f"{ns}/{t}" for t in MUX_INPUTS] if mux is not None else list(inputs)
    return "make every node publishing on " + ", ".join(topics) + " stop or send zero velocity, then reset again"


def plan_reset(robot: str, state: State) -> RobotPlan:
    """`estop reset` on one robot: nothing when the E-stop is not triggered, else a reset, which the
    driver refuses while the last velocity command is not zero (the plan names the publishers)."""
    if state.problems:
        raise RemoteStateError("; ".join(state.problems))
    data: dict[str, Any] = state.to_json()
    if state.triggered is False:
        return RobotPlan(robot, "", noop="E-stop not triggered: nothing to reset"
                         + (f" ({state_text(state)})" if state.velocity_publishers() else ""), data=data)
    seen = state.velocity_publishers()
    where = "its velocity inputs" if state.mux is not None else state.topic(CMD_VEL)
    who = f"publishing: {', '.join(seen)}" if seen else f"nobody publishes on {where}"
    return RobotPlan(robot, "reset the E-stop (triggered; the driver refuses it while the last velocity command "
                     f"is not zero; {who})", data=data, steps=[ResetEstop()])
