"""panther-ops runtime manager: the Panther manual's Lights, Safety and Shutdown trees.

Python + py_trees, deployable alone on a robot (Python 3.10): it imports nothing from the
CLI or transport layers. The names below are what the CLI calls; they are loaded lazily so
that importing one part (e.g. the shutdown executor) does not pull in the rest.

* Parameters: `load_manager_config`, `config_with_params`, `ManagerConfig`.
* Running: `ManagerRuntime`, `TreeSource`, `MonotonicClock`, `ManualClock`.
* Trees: `build_lights_tree`, `build_safety_tree`, `build_shutdown_tree`,
  `load_bt_project`, `validate_bt_project`.
* Lights: `validate_animations`, `render_preview`, `load_led_config`.
* Simulation: `run_simulation`, `Simulation`, `Snapshot`, `load_scenario`.
* Shutdown: `ShutdownHost`, `load_shutdown_hosts`, `run_all`, `ShutdownExecutor`,
  `ShutdownBackends`.
* Reports: `Finding`, `Severity`.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

_EXPORTS = {
    "ManagerConfig": "config",
    "load_manager_config": "config",
    "config_with_params": "config",
    "ManagerRuntime": "runtime",
    "TreeSource": "runtime",
    "MonotonicClock": "clock",
    "ManualClock": "clock",
    "build_lights_tree": "trees.lights",
    "build_safety_tree": "trees.safety",
    "build_shutdown_tree": "trees.safety",
    "load_bt_project": "bt.project",
    "validate_bt_project": "bt.validate",
    "validate_animations": "lights.validate",
    "render_preview": "lights.preview",
    "load_led_config": "lights.config",
    "run_simulation": "sim.runner",
    "Simulation": "sim.runner",
    "Snapshot": "sim.runner",
    "load_scenario": "sim.scenario",
    "ShutdownHost": "shutdown_executor.hosts",
    "load_shutdown_hosts": "shutdown_executor.hosts",
    "run_all": "shutdown_executor.machine",
    "ShutdownExecutor": "shutdown_executor.machine",
    "ShutdownBackends": "shutdown_executor.backends",
    "Finding": "findings",
    "Severity": "findings",
}

__all__ = [
    "Finding",
    "ManagerConfig",
    "ManagerRuntime",
    "ManualClock",
    "MonotonicClock",
    "Severity",
    "ShutdownBackends",
    "ShutdownExecutor",
    "ShutdownHost",
    "Simulation",
    "Snapshot",
    "TreeSource",
    "build_lights_tree",
    "build_safety_tree",
    "build_shutdown_tree",
    "config_with_params",
    "load_bt_project",
    "load_led_config",
    "load_manager_config",
    "load_scenario",
    "load_shutdown_hosts",
    "render_preview",
    "run_all",
    "run_simulation",
    "validate_animations",
    "validate_bt_project",
]

if TYPE_CHECKING:
    from panther_ops.manager.bt.project import load_bt_project
    from panther_ops.manager.bt.validate import validate_bt_project
    from panther_ops.manager.clock import ManualClock, MonotonicClock
    from panther_ops.manager.config import ManagerConfig, config_with_params, load_manager_config
    from panther_ops.manager.findings import Finding, Severity
    from panther_ops.manager.lights.config import load_led_config
    from panther_ops.manager.lights.preview import render_preview
    from panther_ops.manager.lights.validate import validate_animations
    from panther_ops.manager.runtime import ManagerRuntime, TreeSource
    from panther_ops.manager.shutdown_executor.backends import ShutdownBackends
    from panther_ops.manager.shutdown_executor.hosts import ShutdownHost, load_shutdown_hosts
    from panther_ops.manager.shutdown_executor.machine import ShutdownExecutor, run_all
    from panther_ops.manager.sim.runner import Simulation, Snapshot, run_simulation
    from panther_ops.manager.sim.scenario import load_scenario
    from panther_ops.manager.trees.lights import build_lights_tree
    from panther_ops.manager.trees.safety import build_safety_tree, build_shutdown_tree


def __getattr__(name: str) -> Any:
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'panther_ops.manager' has no attribute '{name}'")
    return getattr(importlib.import_module(f"panther_ops.manager.{module}"), name)
