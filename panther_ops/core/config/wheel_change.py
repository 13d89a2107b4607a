"""A wheel type change on a robot whose driver reads a custom controller (or wheel) file.

``controller_config_path`` (and ``wheel_config_path``) win over ``wheel_type``: changing only
the wheel type would leave the robot driving the new wheels with the old kinematics (WH02
wheels at WH01's 0.1825 m radius). So a change of ``wheel_type`` migrates the custom
controller file in the same plan and diff: the new type's default controller file, with
each of the user's limits kept where it is within the new type's limits (the others get
the new default, each named in a warning), written to
``~/config/<package>/config/<WHxx>_controller.yaml``, mounted and pointed at. A custom
wheel file cannot be derived from another wheel type: the change is refused with the fix.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from panther_ops.core.config.controller import ControllerConfig
from panther_ops.core.config.files import config_file
from panther_ops.core.config.launch_args import spec
from panther_ops.core.config.robot_config import RobotConfig
from panther_ops.core.fleet.plan import FileEdit
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.kinds import FileKind
from panther_ops.core.kinds.controller_limits import parse_limit_key, validate_limit
from panther_ops.errors import UsageError


@dataclass
class WheelChange:
    """The migrated controller file and the launch argument that points at it."""

    host_path: str
    container_path: str
    controller: ControllerConfig
    edits: list[FileEdit] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    summary: str = ""


def needs_migration(cfg: RobotConfig, new_wheel: str, robot_model: str | None = None) -> bool:
    """The change of wheel type touches a custom controller or wheel file (``robot_model``: the
    robot's, which decides the default wheel type on husarion_ugv)."""
    args = cfg.compose.args
    old = args.get("wheel_type") or spec("wheel_type").default_for(cfg.stack, robot_model)
    changes = new_wheel not in (old, "custom")
    return changes and bool(args.get("controller_config_path") or args.get("wheel_config_path"))


def migrate(reads: Reads, cfg: RobotConfig, new_wheel: str) -> WheelChange | None:
    """Plan the migration for ``wheel_type`` -> ``new_wheel`` (None: nothing to migrate).

    Raises:
        UsageError: a custom wheel file is mounted, or the controller file cannot be read
            as a controller file (the message says how to go on).
    """
    from panther_ops.core.config.robot_model import robot_model_of

    model = robot_model_of(reads, cfg)
    if not needs_migration(cfg, new_wheel, model):
        return None
    args = cfg.compose.args
    old = args.get("wheel_type") or spec("wheel_type").default_for(cfg.stack, model)
    wheel_path = args.get("wheel_config_path")
    if wheel_path:
        raise UsageError(
            f"wheel_config_path:={wheel_path} sets the wheels whatever wheel_type says: wheel_type {new_wheel} "
            f"would not take effect (the robot would keep the {old} wheel file)",
            hint=f"push a {new_wheel} wheel file (panther-ops config push FILE --as wheel), or unset it first: "
            "panther-ops config unset wheel_config_path",
        )
    cpath = args["controller_config_path"]
    host = cfg.host_path_of(cpath)
    before = reads.file(host) if host else None
    if before is None:
        raise UsageError(
            f"controller_config_path:={cpath} is not a file mounted from the robot: it cannot be migrated to "
            f"{new_wheel}",
            hint=f"unset it (panther-ops config unset controller_config_path) or push a {new_wheel} controller "
            "file (panther-ops config push FILE --as controller)",
        )
    assert host is not None
    try:
        current = ControllerConfig.parse(before.decode(errors="replace"), cfg.stack,
                                         old if old != "custom" else "WH01", path=host, force=True)
    except UsageError as exc:
        raise UsageError(f"{host}: the custom controller file cannot be migrated to {new_wheel}: {exc.message}",
                         hint=f"push a {new_wheel} controller file: panther-ops config push FILE --as controller") \
            from None
    cf = config_file(cfg.stack, FileKind.CONTROLLER, wheel_type=new_wheel)
    new = ControllerConfig.default(cfg.stack, new_wheel)
    stock = ControllerConfig.default(cfg.stack, old) if old in ("WH01", "WH02", "WH04") else None
    kept: list[str] = []
    warnings: list[str] = []
    for key, value in current.limits().items():
        if value == new.get(key) or (stock is not None and value == stock.get(key)):
            continue  # the old type's default: the new type's default replaces it
        lk = parse_limit_key(key)
        if lk.axis == "linear.y" and new_wheel != "WH02":
            warnings.append(f"{key}={value}: {new_wheel} wheels have no linear.y; dropped")
            continue
        try:
            validate_limit(cfg.stack, new_wheel, lk, value)
        except UsageError as exc:
            warnings.append(f"{exc.message}: the {new_wheel} default {new.get(key)} is used")
            continue
        new.set(key, value)
        kept.append(f"{key}={value}")
    after = new.text().encode()
    target_before = reads.file(cf.robot_path)
    edits = [] if after == target_before else [FileEdit(cf.robot_path, target_before, after)]
    summary = (f"controller file migrated {old} -> {new_wheel}: {cf.robot_path} (the {new_wheel} default"
               + (f", your limits kept: {', '.join(kept)})" if kept else ")"))
    warnings.insert(0, f"{host} was the {old} controller file; {summary}")
    return WheelChange(cf.robot_path, cf.container_path, new, edits, warnings, summary)


def point_at(cfg: RobotConfig, change: WheelChange) -> dict[str, str]:
    """Mount the migrated file (in memory); the launch argument to set."""
    if cfg.host_path_of(change.container_path) != change.host_path:
        cfg.compose.add_volume(change.host_path, change.container_path, ro=True)
    return {"controller_config_path": change.container_path}
