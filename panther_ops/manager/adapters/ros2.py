"""The ROS 2 adapter: `RobotIO` over rclpy (topics and services of panther-stack.md §1.10-1.12).

Message package, topic and service names follow the robot's stack (`adapters.interfaces`):
``panther_msgs`` on panther_ros 2.0/2.1, ``husarion_ugv_msgs`` on husarion_ugv 2.2.

Thin on purpose: it only turns messages into `RobotMsg` values (``robot_io.BatteryMsg`` beside
rclpy's ``msgs.*``, ``sensor.*``, ``std.*``) and service requests into
asynchronous rclpy calls. rclpy and the message packages are imported when an adapter is
created, never at import time, so the rest of the manager runs without ROS. It cannot be
exercised without a ROS 2 installation and is excluded from the tests.
"""

from __future__ import annotations

import importlib
from collections import deque
from pathlib import Path
from typing import TYPE_CHECKING, Any

from panther_ops.manager import robot_io
from panther_ops.manager.adapters.interfaces import RosInterfaces, detect_interfaces
from panther_ops.manager.robot_io import RobotMsg, ServiceRequest, ServiceResult

if TYPE_CHECKING:
    from panther_ops.manager.config import ManagerConfig
    from panther_ops.manager.runtime import TreeSource

MAX_CALLBACKS_PER_DRAIN = 200


def _module(name: str) -> Any:
    return importlib.import_module(name)


class _RosCall:  # pragma: no cover - needs ROS 2
    """A service request in flight; sent once the server is available."""

    def __init__(self, client: Any, request: Any) -> None:
        self.client = client
        self.request = request
        self.future: Any = None
        self._send()

    def _send(self) -> None:
        if self.future is None and self.client.service_is_ready():
            self.future = self.client.call_async(self.request)

    def done(self) -> bool:
        self._send()
        return bool(self.future is not None and self.future.done())

    def result(self) -> ServiceResult:
        response = self.future.result() if self.future is not None else None
        if response is None:
            return ServiceResult(False, "no response")
        return ServiceResult(bool(response.success), str(getattr(response, "message", "")))

    def cancel(self) -> None:
        if self.future is not None:
            self.future.cancel()


class Ros2RobotIO:  # pragma: no cover - needs ROS 2
    """Subscriptions fill a queue that `drain()` empties; `call()` never waits."""

    def __init__(self, node_name: str = "panther_ops_manager", namespace: str = "",
                 interfaces: RosInterfaces | None = None) -> None:
        rclpy = _module("rclpy")
        qos = _module("rclpy.qos")
        self._rclpy = rclpy
        if not rclpy.ok():
            rclpy.init()
        self.node = rclpy.create_node(node_name, namespace=namespace)
        self.executor = _module("rclpy.executors").SingleThreadedExecutor()
        self.executor.add_node(self.node)
        self.inbox: deque[RobotMsg] = deque()
        self.clients: dict[str, Any] = {}
        names = self.interfaces = interfaces or detect_interfaces()
        latched = qos.QoSProfile(depth=1, durability=qos.DurabilityPolicy.TRANSIENT_LOCAL,
                                 reliability=qos.ReliabilityPolicy.RELIABLE)
        sensor, std, msgs = (_module("sensor_msgs.msg"), _module("std_msgs.msg"),
                             _module(f"{names.msg_package}.msg"))
        self.node.create_subscription(sensor.BatteryState, names.battery, self._battery, 10)
        self.node.create_subscription(std.Bool, names.e_stop, self._e_stop, latched)
        self.node.create_subscription(msgs.IOState, names.io_state, self._io_state, latched)
        self.node.create_subscription(msgs.SystemStatus, names.system_status, self._system, 10)
        driver_cb = self._robot_driver if names.driver_state_type == "RobotDriverState" else self._driver
        self.node.create_subscription(getattr(msgs, names.driver_state_type), names.driver_state, driver_cb, 10)
        if names.joy:  # 2.2's lights manager: drive_state from the dead man button
            self.node.create_subscription(sensor.Joy, names.joy, self._joy, 10)
        for topic in names.string_topics:  # 2.3.2: CheckStringMsg's topics
            self.node.create_subscription(std.String, topic, self._string(topic), 10)

    def _string(self, topic: str) -> Any:
        def callback(msg: Any) -> None:
            self.inbox.append(robot_io.StringMsg(topic, str(msg.data)))

        return callback

    def _joy(self, msg: Any) -> None:
        self.inbox.append(robot_io.JoyMsg(tuple(int(b) for b in msg.buttons)))

    def _battery(self, msg: Any) -> None:
        self.inbox.append(robot_io.BatteryMsg(float(msg.percentage), float(msg.temperature),
                                              int(msg.power_supply_status), int(msg.power_supply_health),
                                              float(msg.voltage)))

    def _e_stop(self, msg: Any) -> None:
        self.inbox.append(robot_io.EStopMsg(bool(msg.data)))

    def _io_state(self, msg: Any) -> None:
        self.inbox.append(robot_io.IOStateMsg(bool(msg.aux_power), bool(msg.fan), bool(msg.power_button),
                                              bool(getattr(msg, "charger_connected", False))))

    def _system(self, msg: Any) -> None:
        self.inbox.append(robot_io.SystemStatusMsg(float(msg.cpu_temp)))

    def _driver(self, msg: Any) -> None:
        self.inbox.append(robot_io.DriverStateMsg(float(msg.front.temperature), float(msg.rear.temperature)))

    def _robot_driver(self, msg: Any) -> None:
        """husarion_ugv 2.2: one entry per motor driver; the first two stand for front and rear."""
        temps = [float(d.state.temperature) for d in msg.driver_states]
        if temps:
            self.inbox.append(robot_io.DriverStateMsg(temps[0], temps[1] if len(temps) > 1 else temps[0]))

    def drain(self) -> list[RobotMsg]:
        for _ in range(MAX_CALLBACKS_PER_DRAIN):
            before = len(self.inbox)
            self.executor.spin_once(timeout_sec=0.0)
            if len(self.inbox) == before:
                break
        messages = list(self.inbox)
        self.inbox.clear()
        return messages

    def _client(self, request: ServiceRequest) -> tuple[Any, Any]:
        std_srvs, panther_srv = _module("std_srvs.srv"), None
        if request.kind == "set_led_animation":
            panther_srv = _module(f"{self.interfaces.msg_package}.srv")
            srv_type: Any = panther_srv.SetLEDAnimation
        elif request.kind == "set_bool":
            srv_type = std_srvs.SetBool
        else:
            srv_type = std_srvs.Trigger
        name = self.interfaces.service(request.service)
        client = self.clients.get(name)
        if client is None:
            client = self.node.create_client(srv_type, name)
            self.clients[name] = client
        return client, srv_type.Request()

    def call(self, request: ServiceRequest) -> _RosCall:
        client, ros_request = self._client(request)
        args = dict(request.args)
        if request.kind == "set_bool":
            ros_request.data = bool(args["data"])
        elif request.kind == "set_led_animation":
            ros_request.animation.id = int(str(args["id"]))
            ros_request.animation.param = str(args["param"])
            ros_request.repeating = bool(args["repeating"])
        return _RosCall(client, ros_request)

    def close(self) -> None:
        self.executor.remove_node(self.node)
        self.node.destroy_node()


def run_on_ros2(config: ManagerConfig, *, trees: TreeSource | None = None, namespace: str = "",
                known_hosts: str | Path | None = None,
                interfaces: RosInterfaces | None = None) -> None:  # pragma: no cover - needs ROS 2
    """Run the manager on a robot: ROS 2 I/O, real shutdown backends, real clock, until DONE."""
    from panther_ops.manager.clock import MonotonicClock
    from panther_ops.manager.runtime import ManagerRuntime
    from panther_ops.manager.shutdown_executor.backends import ShutdownBackends

    io = Ros2RobotIO(namespace=namespace, interfaces=interfaces)
    backends = ShutdownBackends.real(known_hosts)
    runtime = ManagerRuntime(config, io, MonotonicClock(), trees=trees, backends=backends, interfaces=io.interfaces)
    try:
        runtime.run()
    finally:
        runtime.close()
        backends.close()
        io.close()
