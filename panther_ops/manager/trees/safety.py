"""The Safety and Shutdown trees, built in Python (reference for safety.xml / shutdown.xml).

Safety, per the manual's Faults Handle table:

* OVERHEAT: fan on; above CRITICAL_BAT_TEMP (55 °C) also E-stop and AUX off; above
  FATAL_BAT_TEMP (62 °C) signal a shutdown.
* DEAD: signal a shutdown. OVERVOLTAGE: E-stop. GOOD, UNKNOWN, COLD: nothing.
* Fan: on at start (RunOnce); on at once when the CPU or a driver is above its ``fan_on``
  temperature; off when both are at or below ``fan_off`` and the battery does not overheat,
  but only through the FanOffDelay timer (TickAfterTimeout FAN_TURN_OFF_TIMEOUT, 60 s): it
  starts with the tree, so the fan runs about 60 s after start, and every fan-on sets
  ``fan_turned_on``, which the timer consumes to start over, so the fan never turns off
  sooner than 60 s after it was turned on. (The 2.1 tree put fan-on under the same timer,
  which also delayed turning the fan on by up to 60 s after it was turned off.)

Shutdown: every host of the hosts file through the shutdown executor (failures do not stop
the sequence), then the robot itself with SHUTDOWN_LOCALHOST_COMMAND.
"""

from __future__ import annotations

import py_trees

from panther_ops.manager.constants import (
    AUX_POWER_ENABLE_SERVICE,
    E_STOP_TRIGGER_SERVICE,
    FAN_ENABLE_SERVICE,
)
from panther_ops.manager.keys import FAN_TURNED_ON
from panther_ops.manager.nodes.base import NodeContext, PyProgram, Ref
from panther_ops.manager.nodes.controls import Fallback, Sequence
from panther_ops.manager.nodes.decorators import ForceSuccess, Guard, RunOnce, TickAfterTimeout
from panther_ops.manager.nodes.scripting import Script
from panther_ops.manager.nodes.services import CallSetBoolService, CallTriggerService
from panther_ops.manager.nodes.shutdown import (
    ExecuteCommand,
    ShutdownHostsFromFile,
    SignalShutdown,
)
from panther_ops.manager.trees.common import check

LOCAL_SHUTDOWN_TIMEOUT = 5.0
FAN_TURNED_ON_SCRIPT = PyProgram("fan_turned_on = true",
                                 lambda env: env.set(FAN_TURNED_ON, True), writes=[FAN_TURNED_ON])


def _fan(ctx: NodeContext, name: str, on: bool) -> CallSetBoolService:
    return CallSetBoolService(name, ctx, data=on, service_name=FAN_ENABLE_SERVICE)


def _e_stop(ctx: NodeContext) -> py_trees.behaviour.Behaviour:
    return Guard(CallTriggerService("TriggerEStop", ctx, service_name=E_STOP_TRIGGER_SERVICE),
                 ctx, skip_if=check("E-stop already on", "e_stop_state", lambda v: v.e_stop_state))


def _health_is(name: str) -> PyProgram:
    constant = f"POWER_SUPPLY_HEALTH_{name}"
    return check(f"battery health is not {name}", f"battery_health {constant}",
                 lambda v: v.battery_health != getattr(v, constant))


def _overheat(ctx: NodeContext) -> py_trees.behaviour.Behaviour:
    fatal = Guard(SignalShutdown("SignalFatalTemperature", ctx, reason="Fatal battery temperature"),
                  ctx, skip_if=check("not fatal", "bat_temp FATAL_BAT_TEMP",
                                     lambda v: v.bat_temp <= v.FATAL_BAT_TEMP))
    critical = Guard(
        Sequence("CriticalBatTempSequence", [
            _e_stop(ctx),
            Guard(CallSetBoolService("DisableAUX", ctx, data=False,
                                     service_name=AUX_POWER_ENABLE_SERVICE),
                  ctx, skip_if=check("AUX already off", "aux_state", lambda v: not v.aux_state)),
        ]), ctx,
        skip_if=check("not critical", "bat_temp CRITICAL_BAT_TEMP",
                      lambda v: v.bat_temp <= v.CRITICAL_BAT_TEMP))
    high = Guard(
        Sequence("HighBatTempSequence", [
            critical,
            Guard(_fan(ctx, "EnableFan", True), ctx,
                  skip_if=check("fan already on", "fan_state", lambda v: v.fan_state),
                  on_success=FAN_TURNED_ON_SCRIPT),
        ]), ctx,
        skip_if=check("fatal", "bat_temp FATAL_BAT_TEMP", lambda v: v.bat_temp > v.FATAL_BAT_TEMP))
    return Guard(Sequence("BatteryOverheatSequence", [fatal, high]), ctx,
                 skip_if=_health_is("OVERHEAT"))


def _fan_hysteresis(ctx: NodeContext) -> py_trees.behaviour.Behaviour:
    hot = Guard(
        _fan(ctx, "EnableFan", True), ctx,
        skip_if=check("not hot, or fan on",
                      "cpu_temp CPU_FAN_ON_TEMP driver_temp DRIVER_FAN_ON_TEMP fan_state",
                      lambda v: (v.cpu_temp <= v.CPU_FAN_ON_TEMP
                                 and v.driver_temp <= v.DRIVER_FAN_ON_TEMP) or v.fan_state),
        on_success=FAN_TURNED_ON_SCRIPT)
    restart = Guard(
        Script("RestartFanOffDelay", ctx, PyProgram("fan_turned_on = false",
                                                    lambda env: env.set(FAN_TURNED_ON, False),
                                                    writes=[FAN_TURNED_ON])), ctx,
        skip_if=check("fan not turned on since the last check", FAN_TURNED_ON,
                      lambda v: not v.fan_turned_on))
    cool = Guard(
        _fan(ctx, "DisableFan", False), ctx,
        skip_if=check("still warm, battery overheats, or fan off",
                      "cpu_temp CPU_FAN_OFF_TEMP driver_temp DRIVER_FAN_OFF_TEMP battery_health "
                      "POWER_SUPPLY_HEALTH_OVERHEAT fan_state",
                      lambda v: v.cpu_temp > v.CPU_FAN_OFF_TEMP
                      or v.driver_temp > v.DRIVER_FAN_OFF_TEMP
                      or v.battery_health == v.POWER_SUPPLY_HEALTH_OVERHEAT
                      or not v.fan_state))
    off_delay = TickAfterTimeout("FanOffDelay", Fallback("FanOffFallback", [restart, cool]), ctx,
                                 timeout=Ref("FAN_TURN_OFF_TIMEOUT"))
    return Sequence("FanSequence", [hot, off_delay])


def build_safety_tree(ctx: NodeContext) -> py_trees.behaviour.Behaviour:
    """The Safety tree (pure)."""
    dead = Guard(SignalShutdown("SignalBatteryDead", ctx, reason="Battery dead"), ctx,
                 skip_if=_health_is("DEAD"))
    overvoltage = Guard(Sequence("BatteryOvervoltageSequence", [_e_stop(ctx)]), ctx,
                        skip_if=_health_is("OVERVOLTAGE"))
    startup = RunOnce("TurnOnFanAtStartup", _fan(ctx, "EnableFan", True), then_skip=True)
    return Sequence("Safety", [_overheat(ctx), dead, overvoltage, startup, _fan_hysteresis(ctx)])


def build_shutdown_tree(ctx: NodeContext) -> py_trees.behaviour.Behaviour:
    """The Shutdown tree (pure)."""
    hosts = Guard(
        ForceSuccess("IgnoreHostFailures",
                     ShutdownHostsFromFile("ShutdownHosts", ctx,
                                           shutdown_hosts_file=Ref("SHUTDOWN_HOSTS_PATH"))),
        ctx, skip_if=check("no hosts file", "SHUTDOWN_HOSTS_PATH",
                           lambda v: v.SHUTDOWN_HOSTS_PATH == ""))
    robot = ExecuteCommand("ShutdownRobot", ctx, command=Ref("SHUTDOWN_LOCALHOST_COMMAND"),
                           timeout=LOCAL_SHUTDOWN_TIMEOUT)
    return Sequence("Shutdown", [hosts, robot])
