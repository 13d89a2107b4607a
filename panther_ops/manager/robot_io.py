"""The one interface between the manager and a robot: messages in, service calls out.

Two adapters implement it: `adapters.ros2.Ros2RobotIO` (rclpy, on a robot) and
`sim.adapter.SimRobotIO` (a simulated Panther). The trees never see which one runs.
Service calls are asynchronous: a call returns a `ServiceCall` handle at once and the
behaviour polls it on later ticks, so no tick ever waits for a robot.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, Union


@dataclass(frozen=True)
class BatteryMsg:
    """battery/battery_status (sensor_msgs/BatteryState), the fields the manager reads."""

    percentage: float
    """0..1"""
    temperature: float
    """°C"""
    status: int
    health: int
    voltage: float = float("nan")


@dataclass(frozen=True)
class EStopMsg:
    """hardware/e_stop (std_msgs/Bool)."""

    triggered: bool


@dataclass(frozen=True)
class IOStateMsg:
    """hardware/io_state (panther_msgs/IOState), the fields the manager reads."""

    aux_power: bool
    fan: bool
    power_button: bool = False
    charger_connected: bool = False


@dataclass(frozen=True)
class SystemStatusMsg:
    """system_status (panther_msgs/SystemStatus): Built-in Computer CPU temperature."""

    cpu_temp: float


@dataclass(frozen=True)
class DriverStateMsg:
    """hardware/motor_controllers_state: front and rear driver temperatures."""

    front_temp: float
    rear_temp: float


@dataclass(frozen=True)
class JoyMsg:
    """joy (sensor_msgs/Joy), read by husarion_ugv 2.2's lights manager: the buttons."""

    buttons: tuple[int, ...]


@dataclass(frozen=True)
class StringMsg:
    """A std_msgs/String on a topic: husarion_ugv 2.3.2's ``twist_mux_controller/source`` (the twist
    mux's active input: ``manual``, ``autonomous``, ``unknown`` or ``not_published``), read by the
    Lights tree's CheckStringMsg (husarion_ugv_ros@2.3.2:husarion_ugv_manager/src/plugins/condition/
    check_string_msg.cpp)."""

    topic: str
    """relative to the robot's namespace, without a leading '/'"""
    data: str


RobotMsg = Union[BatteryMsg, EStopMsg, IOStateMsg, SystemStatusMsg, DriverStateMsg, JoyMsg, StringMsg]  # noqa: UP007


class TopicLatch:
    """The last StringMsg of each topic (BT.CPP's RosTopicSubNode with ``latchLastMessage``)."""

    def __init__(self) -> None:
        self._last: dict[str, str] = {}

    def put(self, msg: StringMsg) -> None:
        self._last[msg.topic.strip("/")] = msg.data

    def last(self, topic: str) -> str | None:
        """The last data received on ``topic``, None before the first message."""
        return self._last.get(topic.strip("/"))


@dataclass(frozen=True)
class ServiceResult:
    """A service response: std_srvs SetBool/Trigger and SetLEDAnimation all carry these."""

    success: bool
    message: str = ""


class ServiceCall(Protocol):
    """A request in flight."""

    def done(self) -> bool:
        """True once a response (or an error) is available."""
        ...

    def result(self) -> ServiceResult:
        """The response; only valid when `done()`."""
        ...

    def cancel(self) -> None:
        """Forget the request (the behaviour was halted or timed out)."""
        ...


@dataclass
class CompletedCall:
    """A call whose response is already known (simulation, or a refused request)."""

    response: ServiceResult

    def done(self) -> bool:
        return True

    def result(self) -> ServiceResult:
        return self.response

    def cancel(self) -> None:
        return None


@dataclass(frozen=True)
class ServiceRequest:
    """What was asked of a service, for logs and for comparing trees call by call."""

    service: str
    kind: str
    """"set_bool", "trigger" or "set_led_animation"."""
    args: tuple[tuple[str, object], ...] = ()

    def __str__(self) -> str:
        inner = ", ".join(f"{k}={v!r}" for k, v in self.args)
        return f"{self.service}({inner})"


class RobotIO(Protocol):
    """Messages from the robot and service calls to it."""

    def drain(self) -> list[RobotMsg]:
        """Messages received since the last call, oldest first (never blocks)."""
        ...

    def call(self, request: ServiceRequest) -> ServiceCall:
        """Send a service request and return its handle at once (never blocks)."""
        ...


def set_bool(service: str, data: bool) -> ServiceRequest:
    """A std_srvs/SetBool request."""
    return ServiceRequest(service, "set_bool", (("data", bool(data)),))


def trigger(service: str) -> ServiceRequest:
    """A std_srvs/Trigger request."""
    return ServiceRequest(service, "trigger")


def set_led_animation(service: str, anim_id: int, param: str, repeating: bool) -> ServiceRequest:
    """A panther_msgs/SetLEDAnimation request."""
    return ServiceRequest(
        service,
        "set_led_animation",
        (("id", int(anim_id)), ("param", str(param)), ("repeating", bool(repeating))),
    )
