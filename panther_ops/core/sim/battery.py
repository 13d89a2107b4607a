"""battery_plugin_config.yaml (simulation only, panther_gazebo): the validator of the file kind.

Keys (manual "Linear Battery Plugin", panther-stack.md 1.6): ``simulate_discharging`` (bool),
``initial_charge_percentage`` (0-100; panther_ros 2.1.1's own file writes a 0-1 fraction,
which is reported), ``charging_time`` (h, > 0), ``power_load`` (W, > 0), ``capacity`` (Ah,
> 0; 2.1.1+).
"""

from __future__ import annotations

import math
from typing import Any

from panther_ops.errors import InputError

KEYS = ("simulate_discharging", "initial_charge_percentage", "charging_time", "power_load", "capacity")


def _number(value: Any, key: str, path: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(f"{key} {value!r}: a number", path=path, key=key)
    return float(value)


def validate_battery(doc: Any, path: str) -> list[str]:
    """Raise InputError for a bad file; returns notes (e.g. the 0-1 legacy form)."""
    if not isinstance(doc, dict):
        raise InputError("expected a mapping of the plugin's keys", path=path)
    notes: list[str] = []
    unknown = sorted(set(doc) - set(KEYS))
    if unknown:
        raise InputError(f"unknown key {unknown[0]!r}", path=path, key=unknown[0], hint="allowed: " + ", ".join(KEYS))
    if "simulate_discharging" in doc and not isinstance(doc["simulate_discharging"], bool):
        raise InputError(f"simulate_discharging {doc['simulate_discharging']!r}: true or false", path=path,
                         key="simulate_discharging")
    if "initial_charge_percentage" in doc:
        v = _number(doc["initial_charge_percentage"], "initial_charge_percentage", path)
        if not 0 <= v <= 100:
            raise InputError(f"initial_charge_percentage {v:g}: 0-100 (percent)", path=path,
                             key="initial_charge_percentage")
        if 0 < v <= 1:
            notes.append(f"initial_charge_percentage {v:g} is the 0-1 form of panther_ros 2.1.1's file "
                         f"({v * 100:g} %); the manual's scale is 0-100")
    for key, unit in (("charging_time", "h"), ("power_load", "W"), ("capacity", "Ah")):
        if key in doc and _number(doc[key], key, path) <= 0:
            raise InputError(f"{key} {doc[key]!r}: a positive number [{unit}]", path=path, key=key)
    if doc.get("simulate_discharging") is False and doc.get("power_load"):
        notes.append("simulate_discharging is false: the plugin uses power_load 0 W (the battery does not drain)")
    return notes
