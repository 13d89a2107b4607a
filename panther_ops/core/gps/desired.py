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

from panther_ops.core.fleet.inventory_desired import DesiredError, gps_block, usage_error
from panther_ops.core.fleet.plan import FileEdit, Verify
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.gps.plan import DEFAULT_IP, DEFAULT_PORT, SERVICE, GpsOptions, enable_change
from panther_ops.core.robot.edits import edit_args
from panther_ops.core.robot.robot_config import RobotConfig


@dataclass
class DesiredGps:
    parts: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    verify: list[Verify] = field(default_factory=list)
    extra: list[FileEdit] = field(default_factory=list)
    recreate: tuple[str, ...] = ()


def desired_gps(reads: Reads, cfg: RobotConfig, value: Any) -> DesiredGps:
    """Edit ``cfg.compose`` toward ``desired.gps``, as the inventory checked it when it loaded
    (`fleet/inventory_desired.gps_block`, called again for a caller that gives a block of its own)."""
    try:
        value = gps_block(value)
    except DesiredError as bad:
        raise usage_error(bad) from None
    enabled = value.get("enabled")
    out = DesiredGps()
    if "router" in value:
        out.warnings.append("desired.gps.router: set by `panther-ops gps router set` (or gps enable --router), "
                            "not by apply")
    if enabled is True:
        before = cfg.compose.text()
        options = GpsOptions(port=value.get("port", DEFAULT_PORT), ip=value.get("ip", DEFAULT_IP),
                             namespace=value.get("namespace"), container=value.get("container", False))
        change = enable_change(reads, cfg, options)
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
