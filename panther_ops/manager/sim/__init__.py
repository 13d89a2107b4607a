"""Simulation: a Panther model, scenario files and a runner yielding per-tick snapshots."""

from __future__ import annotations

from panther_ops.manager.sim.model import BatteryPlugin, PantherModel, SimHost
from panther_ops.manager.sim.runner import Simulation, Snapshot, run_simulation
from panther_ops.manager.sim.scenario import Event, Scenario, load_scenario, parse_scenario

__all__ = [
    "BatteryPlugin",
    "Event",
    "PantherModel",
    "Scenario",
    "SimHost",
    "Simulation",
    "Snapshot",
    "load_scenario",
    "parse_scenario",
    "run_simulation",
]
