"""The inventory's ``desired.gps`` block, converged by `apply` and reported by `config diff`.

``enabled: true`` runs the NMEA driver as `gps enable` would (``port``, ``ip``,
``namespace``, ``container`` as its options); ``enabled: false`` takes ``launch_nmea_gps``
off the driver (an ``nmea-gps`` service is left to `gps disable`, which also removes its
container). ``router`` (the router's forwarding) is set by `gps router set` / `gps enable
--router`, not by `apply`: reported as a warning.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from panther_ops.core.config.planners import edit_args
from panther_ops.core.config.robot_config import RobotConfig
from panther_ops.core.fleet.plan import FileEdit, Verify
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.gps.plan import DEFAULT_IP, DEFAULT_PORT, SERVICE, GpsOptions, enable_change
from panther_ops.errors import UsageError

KEYS = ("enabled", "port", "ip", "namespace", "container", "router")


@dataclass
class DesiredGps:
    parts: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    verify: list[Verify] = field(default_factory=list)
    extra: list[FileEdit] = field(default_factory=list)
    recreate: tuple[str, ...] = ()


def _options(value: dict[str, Any]) -> GpsOptions:
    port = value.get("port", DEFAULT_PORT)
    if isinstance(port, bool) or not isinstance(port, int):
        raise UsageError(f"desired.gps.port {port!r}: a UDP port number (1-65535)")
    for key in ("container",):
        if key in value and not isinstance(value[key], bool):
            raise UsageError(f"desired.gps.{key} {value[key]!r}: true or false")
    ns = value.get("namespace")
    if ns is not None and not isinstance(ns, str):
        raise UsageError(f"desired.gps.namespace {ns!r}: a ROS namespace")
    return GpsOptions(port=port, ip=str(value.get("ip", DEFAULT_IP)), namespace=ns,
                      container=bool(value.get("container", False)))


def desired_gps(reads: Reads, cfg: RobotConfig, value: Any) -> DesiredGps:
    """Edit ``cfg.compose`` toward ``desired.gps``; UsageError for a bad block."""
    if not isinstance(value, dict):
        raise UsageError("desired.gps must be a mapping", hint="keys: " + ", ".join(KEYS))
    unknown = sorted(set(value) - set(KEYS))
    if unknown:
        raise UsageError(f"desired.gps.{unknown[0]}: unknown key", hint="allowed: " + ", ".join(KEYS))
    enabled = value.get("enabled")
    if enabled is not None and not isinstance(enabled, bool):
        raise UsageError(f"desired.gps.enabled {enabled!r}: true or false")
    out = DesiredGps()
    if "router" in value:
        out.warnings.append("desired.gps.router: set by `panther-ops gps router set` (or gps enable --router), "
                            "not by apply")
    if enabled is True:
        before = cfg.compose.text()
        change = enable_change(reads, cfg, _options(value))
        out.warnings += change.warnings
        out.verify += change.verify
        if cfg.compose.text() != before or change.extra:
            if change.data.get("mode") == "service":  # an argument shows in the launch arguments' summary
                out.parts.append(change.summary)
            out.extra += change.extra
            out.recreate = change.recreate
    elif enabled is False:
        if SERVICE in cfg.compose.services():
            out.warnings.append(f"desired.gps.enabled false: the {SERVICE} service stays; "
                                "`panther-ops gps disable` removes it and its container")
        if cfg.stack.version >= (2, 1, 1) and "launch_nmea_gps" in cfg.compose.args:
            _w, check = edit_args(cfg, {}, ["launch_nmea_gps"], False)
            out.verify.append(check)
            out.recreate = (cfg.service,)
    return out
