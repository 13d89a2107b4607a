"""`estop reset`'s plan (pure): from the E-stop's state and the publishers of cmd_vel as the
driver told them (`calls.py` asks), whether a reset is needed and possible. A node publishing on
cmd_vel refuses the reset, naming the node (the manual: no reset while messages arrive); an
E-stop not triggered is left alone. The reset itself is `apply.py`'s executor."""

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

    def topic(self, name: str) -> str:
        return f"{self.namespace.rstrip('/')}/{name}"

    def to_json(self) -> dict[str, Any]:
        return {"namespace": self.namespace, "e_stop": self.triggered, "cmd_vel_publishers": self.publishers}


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
    return state


def answer_tail(text: str) -> str:
    lines = [ln for ln in text.strip().splitlines() if ln.strip() and "waiting for service" not in ln]
    return f": {lines[-1][-200:]}" if lines else ""


def state_text(state: State) -> str:
    what = {True: "E-stop triggered", False: "E-stop released", None: "E-stop state unknown"}[state.triggered]
    if state.publishers:
        what += f"; publishing on {state.topic(CMD_VEL)}: {', '.join(state.publishers)}"
    return what


def plan_reset(robot: str, state: State) -> RobotPlan:
    """`estop reset` on one robot: a reset when the E-stop is triggered and nobody publishes on
    cmd_vel; nothing when it is not triggered; refused (RemoteStateError) otherwise."""
    if state.problems:
        raise RemoteStateError("; ".join(state.problems))
    data: dict[str, Any] = state.to_json()
    if state.triggered is False:
        return RobotPlan(robot, "", noop="E-stop not triggered: nothing to reset"
                         + (f" ({state_text(state)})" if state.publishers else ""), data=data)
    if state.publishers:
        raise RemoteStateError(f"refused: {', '.join(state.publishers)} publishes on {state.topic(CMD_VEL)} "
                               "(no reset while messages arrive)",
                               hint=f"stop {state.publishers[0]}, then reset again")
    return RobotPlan(robot, f"reset the E-stop (triggered; nobody publishes on {state.topic(CMD_VEL)})", data=data,
                     steps=[ResetEstop()])
