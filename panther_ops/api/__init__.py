"""panther-ops as a Python library, for front ends other than the CLI (the Ansible collection
``panther_ops.fleet``, docs/ansible.md).

One change on one robot, planned and applied exactly as the CLI does it (the same prechecks,
planners and pipeline: core/fleet/changes.py), its result as plain data. Like cli/, this is a
front end above core; unlike cli/ it imports no typer or rich (import-linter holds it).

    from panther_ops.api import robot_from_hostvars, run_module
    inv, robot = robot_from_hostvars("panther-01", {"ansible_host": "10.0.0.7", ...})
    report = run_module("config", {"key": "wheel_type", "value": "WH02"}, inv, robot, check=True)
"""

from __future__ import annotations

from panther_ops.api.hostvars import robot_from_hostvars
from panther_ops.api.modules import MODULES, ArgumentError, check_arguments
from panther_ops.api.run import run_module

__all__ = ["MODULES", "ArgumentError", "check_arguments", "robot_from_hostvars", "run_module"]
