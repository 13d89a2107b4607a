"""The simulation adapter: `RobotIO` over a `PantherModel`, plus simulated shutdown backends.

Services answer at once (the behaviour still takes one tick to see the answer, as with
ROS). Every call is recorded with its time, so two trees can be compared call by call.
Shutdown requests only mark simulated hosts as going down; nothing real is contacted.
"""

from __future__ import annotations

from dataclasses import dataclass

from panther_ops.manager.clock import Clock
from panther_ops.manager.constants import (
    AUX_POWER_ENABLE_SERVICE,
    E_STOP_TRIGGER_SERVICE,
    FAN_ENABLE_SERVICE,
    SET_ANIMATION_SERVICE,
)
from panther_ops.manager.lights.controller import LightsController
from panther_ops.manager.robot_io import (
    CompletedCall,
    RobotMsg,
    ServiceRequest,
    ServiceResult,
)
from panther_ops.manager.shutdown_executor.backends import (
    CommandOutcome,
    InlineDispatcher,
    ShutdownBackends,
)
from panther_ops.manager.shutdown_executor.hosts import ShutdownHost
from panther_ops.manager.sim.model import PantherModel
from panther_ops.manager.sim.scenario import ScenarioPlayer

E_STOP_RESET_SERVICE = "hardware/e_stop_reset"
_PLAIN_SERVICES = {"hardware/charger_enable", "hardware/digital_power_enable",
                   "hardware/motor_power_enable"}


@dataclass(frozen=True)
class CallRecord:
    """A service call made to the simulated robot."""

    time: float
    request: ServiceRequest
    result: ServiceResult


class SimRobotIO:
    """Messages from the model; service calls applied to it (and to the lights controller)."""

    def __init__(self, model: PantherModel, clock: Clock, lights: LightsController | None = None,
                 player: ScenarioPlayer | None = None) -> None:
        self.model = model
        self.clock = clock
        self.lights = lights
        self.player = player
        self.calls: list[CallRecord] = []
        self.commands: list[str] = []

    def update(self) -> float:
        """Bring the model (scenario, battery, lights) to the clock's time."""
        now = self.clock.now()
        if self.player is not None:
            self.player.apply(self.model, now)
        self.model.advance(now)
        if self.lights is not None and not self.model.powered_off:
            self.lights.advance(now)
        return now

    def drain(self) -> list[RobotMsg]:
        self.update()
        return self.model.messages()

    def call(self, request: ServiceRequest) -> CompletedCall:
        result = self._serve(request)
        self.calls.append(CallRecord(self.clock.now(), request, result))
        return CompletedCall(result)

    def _serve(self, request: ServiceRequest) -> ServiceResult:
        if self.model.powered_off:
            return ServiceResult(False, "robot is powered off")
        args = dict(request.args)
        service = request.service.lstrip("/")
        if service == FAN_ENABLE_SERVICE:
            self.model.fan = bool(args["data"])
        elif service == AUX_POWER_ENABLE_SERVICE:
            self.model.aux = bool(args["data"])
        elif service == E_STOP_TRIGGER_SERVICE:
            self.model.e_stop = True
        elif service == E_STOP_RESET_SERVICE:
            self.model.e_stop = False
        elif service == SET_ANIMATION_SERVICE:
            if self.lights is None:
                return ServiceResult(True, "no lights simulated")
            ok, message = self.lights.set_animation(int(str(args["id"])), str(args["param"]),
                                                    bool(args["repeating"]), self.clock.now())
            return ServiceResult(ok, message)
        elif service not in _PLAIN_SERVICES:
            return ServiceResult(False, f"service '{service}' is not available")
        return ServiceResult(True)


class SimPinger:
    """Ping on the simulated network."""

    def __init__(self, model: PantherModel, clock: Clock) -> None:
        self.model, self.clock = model, clock

    def is_reachable(self, ip: str) -> bool:
        host = self.model.hosts.get(ip)
        return host is not None and host.up(self.clock.now())


class SimRemoteShutdown:
    """A shutdown request to a simulated host: it goes down after its shutdown_delay."""

    def __init__(self, model: PantherModel, clock: Clock) -> None:
        self.model, self.clock = model, clock

    def request(self, host: ShutdownHost) -> CommandOutcome:
        sim = self.model.hosts.get(host.ip)
        now = self.clock.now()
        if sim is None or not sim.up(now):
            return CommandOutcome(False, error="Error connecting to host: Connection refused")
        if sim.down_at is None:
            sim.down_at = now + sim.shutdown_delay
        return CommandOutcome(True, "simulated shutdown")


class SimLocalRunner:
    """The robot's own shutdown command: the simulated robot powers off."""

    def __init__(self, io: SimRobotIO) -> None:
        self.io = io

    def run(self, command: str, timeout: float) -> CommandOutcome:
        self.io.commands.append(command)
        self.io.model.powered_off = True
        return CommandOutcome(True, f"simulated: {command}")


def sim_backends(io: SimRobotIO) -> ShutdownBackends:
    """Shutdown backends that act on the simulated robot and network only."""
    remote = SimRemoteShutdown(io.model, io.clock)
    return ShutdownBackends(SimPinger(io.model, io.clock), remote, remote, SimLocalRunner(io),
                            InlineDispatcher())
