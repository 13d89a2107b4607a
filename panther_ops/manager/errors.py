"""Errors of the runtime manager.

The manager is deployed alone on robots, so it does not depend on `panther_ops.errors`;
the CLI layer wraps these into its own hierarchy when it calls the manager.
"""

from __future__ import annotations


class ManagerError(Exception):
    """Root of every error the manager raises on purpose."""


class ConfigError(ManagerError):
    """A parameter file is unreadable or holds a value that is not allowed."""


class ScenarioError(ManagerError):
    """A simulation scenario file is unreadable or malformed."""


class BtProjectError(ManagerError):
    """A BehaviorTree project or XML file cannot be loaded or built."""


class ScriptError(ManagerError):
    """A precondition or script expression cannot be parsed or evaluated."""


class ShutdownHostsError(ManagerError):
    """A shutdown hosts file is unreadable or malformed."""


class LightsConfigError(ManagerError):
    """An LED configuration or animation file cannot be used."""
