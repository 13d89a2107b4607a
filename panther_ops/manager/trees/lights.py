"""The Lights tree, built in Python (the reference for templates/behavior_trees/lights.xml).

* Charger connected (status CHARGING or FULL): ERROR while the battery overheats or is
  over-voltage; otherwise CHARGING_BATTERY with the rounded percentage (re-sent when it
  changes), and an E_STOP reminder every 20 s while the E-stop is on.
* Discharging (DISCHARGING or NOT_CHARGING): READY or E_STOP (repeating), plus LOW_BATTERY
  every LOW_BATTERY_ANIM_PERIOD while critical <= percent < low, and CRITICAL_BATTERY every
  CRITICAL_BATTERY_ANIM_PERIOD below the critical threshold.
* Unknown status: ERROR.
"""

from __future__ import annotations

from typing import Any

import py_trees

from panther_ops.manager.constants import SET_ANIMATION_SERVICE
from panther_ops.manager.nodes.base import NodeContext, PyProgram, Ref
from panther_ops.manager.nodes.controls import Sequence
from panther_ops.manager.nodes.decorators import Guard, TickAfterTimeout
from panther_ops.manager.nodes.services import CallSetLedAnimationService
from panther_ops.manager.trees.common import assign, check

E_STOP_REMINDER_PERIOD = 20.0


def _anim(ctx: NodeContext, name: str, anim_id: str, *, repeating: bool,
          param: Any = "") -> CallSetLedAnimationService:
    return CallSetLedAnimationService(name, ctx, id=Ref(anim_id), param=param,
                                      repeating=repeating, service_name=SET_ANIMATION_SERVICE)


def _status_not(reason: str, *statuses: str) -> PyProgram:
    """Skip (saying `reason`) while battery_status is none of `statuses` (constants' names)."""
    return check(reason, " ".join(("battery_status", *statuses)),
                 lambda v: v.battery_status not in tuple(getattr(v, s) for s in statuses))


def _charging(ctx: NodeContext) -> py_trees.behaviour.Behaviour:
    fault = "battery_health POWER_SUPPLY_HEALTH_OVERHEAT POWER_SUPPLY_HEALTH_OVERVOLTAGE"
    error = Guard(
        _anim(ctx, "SetErrorAnimation", "ERROR_ANIM_ID", repeating=True), ctx,
        skip_if=check("no fault, or ERROR shown", fault + " current_anim_id ERROR_ANIM_ID",
                      lambda v: v.battery_health not in (v.POWER_SUPPLY_HEALTH_OVERHEAT,
                                                         v.POWER_SUPPLY_HEALTH_OVERVOLTAGE)
                      or v.current_anim_id == v.ERROR_ANIM_ID),
        on_success=assign(current_anim_id="ERROR_ANIM_ID"),
    )
    charging = Guard(
        _anim(ctx, "SetChargingAnimation", "CHARGING_BATTERY_ANIM_ID", repeating=True,
              param=Ref("battery_percent_round")), ctx,
        skip_if=check("charging animation already shows this percentage",
                      "battery_percent_round charging_anim_percent current_anim_id "
                      "CHARGING_BATTERY_ANIM_ID",
                      lambda v: v.battery_percent_round == v.charging_anim_percent
                      and v.current_anim_id == v.CHARGING_BATTERY_ANIM_ID),
        on_success=assign(charging_anim_percent="battery_percent_round",
                          current_anim_id="CHARGING_BATTERY_ANIM_ID"),
    )
    e_stop_reminder = Guard(
        TickAfterTimeout("EStopReminder",
                         _anim(ctx, "SetEStopAnimation", "E_STOP_ANIM_ID", repeating=False),
                         ctx, timeout=E_STOP_REMINDER_PERIOD), ctx,
        skip_if=check("E-stop off", "e_stop_state", lambda v: not v.e_stop_state),
    )
    display = Guard(
        Sequence("DisplayChargingAnimationSequence", [charging, e_stop_reminder]), ctx,
        skip_if=check("battery fault", fault,
                      lambda v: v.battery_health in (v.POWER_SUPPLY_HEALTH_OVERHEAT,
                                                     v.POWER_SUPPLY_HEALTH_OVERVOLTAGE)),
    )
    return Guard(
        Sequence("ChargingSequence", [error, display]), ctx,
        skip_if=_status_not("charger not connected",
                            "POWER_SUPPLY_STATUS_CHARGING", "POWER_SUPPLY_STATUS_FULL"),
    )


def _discharging(ctx: NodeContext) -> py_trees.behaviour.Behaviour:
    ready = Guard(
        _anim(ctx, "SetReadyAnimation", "READY_ANIM_ID", repeating=True), ctx,
        skip_if=check("E-stop on, or READY shown", "e_stop_state current_anim_id READY_ANIM_ID",
                      lambda v: v.e_stop_state or v.current_anim_id == v.READY_ANIM_ID),
        on_success=assign(current_anim_id="READY_ANIM_ID"),
    )
    e_stop = Guard(
        _anim(ctx, "SetEStopAnimation", "E_STOP_ANIM_ID", repeating=True), ctx,
        skip_if=check("E-stop off, or E_STOP shown", "e_stop_state current_anim_id E_STOP_ANIM_ID",
                      lambda v: not v.e_stop_state or v.current_anim_id == v.E_STOP_ANIM_ID),
        on_success=assign(current_anim_id="E_STOP_ANIM_ID"),
    )
    low = Guard(
        TickAfterTimeout("LowBatteryPeriod",
                         _anim(ctx, "SetLowBatteryAnimation", "LOW_BATTERY_ANIM_ID",
                               repeating=False),
                         ctx, timeout=Ref("LOW_BATTERY_ANIM_PERIOD")), ctx,
        skip_if=check("battery not low",
                      "battery_percent CRITICAL_BATTERY_THRESHOLD_PERCENT "
                      "LOW_BATTERY_THRESHOLD_PERCENT",
                      lambda v: v.battery_percent < v.CRITICAL_BATTERY_THRESHOLD_PERCENT
                      or v.battery_percent >= v.LOW_BATTERY_THRESHOLD_PERCENT),
    )
    critical = Guard(
        TickAfterTimeout("CriticalBatteryPeriod",
                         _anim(ctx, "SetCriticalBatteryAnimation", "CRITICAL_BATTERY_ANIM_ID",
                               repeating=False),
                         ctx, timeout=Ref("CRITICAL_BATTERY_ANIM_PERIOD")), ctx,
        skip_if=check("battery not critical", "battery_percent CRITICAL_BATTERY_THRESHOLD_PERCENT",
                      lambda v: v.battery_percent >= v.CRITICAL_BATTERY_THRESHOLD_PERCENT),
    )
    return Guard(
        Sequence("DischargingSequence",
                 [ready, e_stop, Sequence("BatteryAnimationSequence", [low, critical])]), ctx,
        skip_if=_status_not("not discharging",
                            "POWER_SUPPLY_STATUS_DISCHARGING", "POWER_SUPPLY_STATUS_NOT_CHARGING"),
    )


def build_lights_tree(ctx: NodeContext) -> py_trees.behaviour.Behaviour:
    """The Lights tree (pure: builds behaviours, touches no robot)."""
    unknown = Guard(
        _anim(ctx, "SetErrorAnimation", "ERROR_ANIM_ID", repeating=True), ctx,
        skip_if=check("status known, or ERROR shown",
                      "battery_status POWER_SUPPLY_STATUS_UNKNOWN current_anim_id ERROR_ANIM_ID",
                      lambda v: v.battery_status != v.POWER_SUPPLY_STATUS_UNKNOWN
                      or v.current_anim_id == v.ERROR_ANIM_ID),
        on_success=assign(current_anim_id="ERROR_ANIM_ID"),
    )
    return Sequence("Lights", [_charging(ctx), _discharging(ctx), unknown])
