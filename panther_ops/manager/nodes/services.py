"""Service-calling actions: CallSetBoolService, CallTriggerService, CallSetLedAnimationService.

Like BT.CPP's RosServiceNode: the first tick sends the request and returns RUNNING; later
ticks poll the response. SUCCESS when the service answers ``success: true``, FAILURE when it
answers false or does not answer within the context's service timeout.
"""

from __future__ import annotations

from typing import ClassVar

from py_trees.common import Status

from panther_ops.manager.errors import ScriptError
from panther_ops.manager.nodes.base import PortedLeaf, PortSpec
from panther_ops.manager.robot_io import (
    ServiceCall,
    ServiceRequest,
    set_bool,
    set_led_animation,
    trigger,
)


class ServiceAction(PortedLeaf):
    """Send one request per run and wait for its response without blocking a tick."""

    def initialise(self) -> None:
        self.call: ServiceCall | None = None
        self.request: ServiceRequest | None = None
        self.sent_at = 0.0

    def build_request(self) -> ServiceRequest:
        raise NotImplementedError

    def update(self) -> Status:
        if self.call is None:
            try:
                self.request = self.build_request()
            except ScriptError as exc:
                self.feedback_message = f"bad port value: {exc}"
                return Status.FAILURE
            self.call = self.ctx.io.call(self.request)
            self.sent_at = self.ctx.clock.now()
            self.feedback_message = f"sent {self.request}"
            return Status.RUNNING
        if self.call.done():
            result = self.call.result()
            self.call = None
            self.feedback_message = (f"{self.request}: "
                                     f"{'ok' if result.success else 'refused'} {result.message}")
            return Status.SUCCESS if result.success else Status.FAILURE
        if self.ctx.clock.now() - self.sent_at > self.ctx.service_timeout:
            self.call.cancel()
            self.call = None
            self.feedback_message = f"{self.request}: no response in {self.ctx.service_timeout} s"
            return Status.FAILURE
        return Status.RUNNING

    def terminate(self, new_status: Status) -> None:
        call = getattr(self, "call", None)
        if new_status == Status.INVALID and call is not None:
            call.cancel()
            self.call = None


class CallSetBoolService(ServiceAction):
    """Call a std_srvs/SetBool service (ports: data, service_name)."""

    PORTS: ClassVar[dict[str, PortSpec]] = {
        "data": PortSpec("bool", description="service data - true or false value"),
        "service_name": PortSpec("str", description="ROS service name"),
    }

    def build_request(self) -> ServiceRequest:
        return set_bool(self.port("service_name"), self.port("data"))


class CallTriggerService(ServiceAction):
    """Call a std_srvs/Trigger service (port: service_name)."""

    PORTS: ClassVar[dict[str, PortSpec]] = {"service_name": PortSpec("str", description="ROS service name")}

    def build_request(self) -> ServiceRequest:
        return trigger(self.port("service_name"))


class CallSetLedAnimationService(ServiceAction):
    """Call panther_msgs/SetLEDAnimation (ports: id, param, repeating, service_name)."""

    PORTS: ClassVar[dict[str, PortSpec]] = {
        "id": PortSpec("int", description="animation ID"),
        "param": PortSpec("str", "", "optional parameter passed to animation"),
        "repeating": PortSpec("bool", False, "indicates if the animation should repeat"),
        "service_name": PortSpec("str", description="ROS service name"),
    }

    def build_request(self) -> ServiceRequest:
        anim_id = self.port("id")
        if anim_id < 0:
            raise ScriptError(f"animation id must be unsigned, got {anim_id}")
        return set_led_animation(self.port("service_name"), anim_id, self.port("param"),
                                 self.port("repeating"))
