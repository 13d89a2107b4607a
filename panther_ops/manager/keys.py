"""Blackboard entry names, in one place (the manual's BehaviorTree section)."""

from __future__ import annotations

# Lights tree
BATTERY_PERCENT = "battery_percent"
BATTERY_PERCENT_ROUND = "battery_percent_round"
BATTERY_STATUS = "battery_status"
BATTERY_HEALTH = "battery_health"
CHARGING_ANIM_PERCENT = "charging_anim_percent"
CURRENT_ANIM_ID = "current_anim_id"
E_STOP_STATE = "e_stop_state"
# husarion_ugv 2.2's Lights tree (lights_manager_node.cpp CreateLightsInitialBlackboard, JoyCB)
CURRENT_BATTERY_ANIM_ID = "current_battery_anim_id"
CURRENT_ERROR_ANIM_ID = "current_error_anim_id"
DRIVE_STATE = "drive_state"

# Safety tree
AUX_STATE = "aux_state"
BAT_TEMP = "bat_temp"
CPU_TEMP = "cpu_temp"
DRIVER_TEMP = "driver_temp"
FAN_STATE = "fan_state"
FAN_TURNED_ON = "fan_turned_on"
"""Set when the tree turns the fan on; the fan-off delay consumes it to start over."""

# Shutdown (written by SignalShutdown, read by the manager loop)
SIGNAL_SHUTDOWN = "signal_shutdown"

LIGHTS_INPUTS = (BATTERY_PERCENT, BATTERY_PERCENT_ROUND, BATTERY_STATUS, BATTERY_HEALTH,
                 E_STOP_STATE)
LIGHTS_STATE = (CHARGING_ANIM_PERCENT, CURRENT_ANIM_ID)
LIGHTS_STATE_22 = (CURRENT_BATTERY_ANIM_ID, CURRENT_ERROR_ANIM_ID, DRIVE_STATE)
"""The entries 2.2's lights manager adds (``drive_state``: written from the ``joy`` topic)."""
SAFETY_INPUTS = (AUX_STATE, BAT_TEMP, BATTERY_STATUS, BATTERY_HEALTH, CPU_TEMP, DRIVER_TEMP,
                 E_STOP_STATE, FAN_STATE)
SAFETY_STATE = (FAN_TURNED_ON, SIGNAL_SHUTDOWN)

LIGHTS_REQUIRED = (E_STOP_STATE, BATTERY_STATUS)
"""Lights is not ticked before these arrived (lights_manager SystemReady)."""
SAFETY_REQUIRED = (E_STOP_STATE, BATTERY_STATUS, AUX_STATE, CPU_TEMP, DRIVER_TEMP)
"""Safety is not ticked before these arrived (safety_manager SystemReady)."""
