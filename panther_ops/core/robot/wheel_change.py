"""A wheel type change on a robot whose driver reads a custom controller (or wheel) file.

``controller_config_path`` (and ``wheel_config_path``) win over ``wheel_type``: changing only
the wheel type would leave the robot driving the new wheels with the old kinematics (WH02
wheels at WH01's 0.1825 m radius). So a change of ``wheel_type`` migrates the custom
controller file in the same plan and diff: the new type's default controller file, with
each of the user's limits kept where it is within the new type's limits (the others get
the new default, each named in a warning), written to
``~/config/<package>/config/<WHxx>_controller.yaml``, mounted and pointed at. A custom
wheel file cannot be derived from another wheel type: the change is refused with the fix.

On husarion_ugv 2.2 with a config tree (``common_dir_path``) the driver reads the wheel type's
controller file from the tree, and ``config set controller.<key>`` edits the tree's file of the
current type. The new type reads its own tree file, so the user's limits would silently be
lost: where the old type's tree file differs from the release's stock file in its limits, the
change carries them into the new type's tree file the same way (that file as it is, or the
stock one where the tree lacks it; no launch argument to point at).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from panther_ops.core.fleet.plan import FileEdit
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.kinds import FileKind
from panther_ops.core.kinds.controller_limits import parse_limit_key, same_limit, same_limits, validate_limit
from panther_ops.core.robot.controller import ControllerConfig
from panther_ops.core.robot.files import config_file
from panther_ops.core.robot.launch_args import spec
from panther_ops.core.robot.robot_config import RobotConfig
from panther_ops.errors import UsageError


@dataclass
class WheelChange:
    """The migrated controller file and the launch argument that points at it."""

    host_path: str
    container_path: str | None
    """where the driver finds the file (None: the tree's file, read with no argument)"""
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


def migrate(reads: Reads, cfg: RobotConfig, new_wheel: str, robot_model: str | None = None) -> WheelChange | None:
    """Plan the migration for ``wheel_type`` -> ``new_wheel`` (None: nothing to migrate);
    ``robot_model``: the robot's model where the caller knows it (else read).

    Raises:
        UsageError: a custom wheel file is mounted, or the controller file cannot be read
            as a controller file (the message says how to go on).
    """
    from panther_ops.core.robot.robot_model import robot_model_of

    model = robot_model or robot_model_of(reads, cfg)
    if not needs_migration(cfg, new_wheel, model):
        return _migrate_tree(reads, cfg, new_wheel, model)
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
    stock = ControllerConfig.default(cfg.stack, old) if old in ("WH01", "WH02", "WH04") else None
    new, kept, warnings = _carry_limits(cfg, current, stock, ControllerConfig.default(cfg.stack, new_wheel), new_wheel)
    after = new.text().encode()
    target_before = reads.file(cf.robot_path)
    edits = [] if after == target_before else [FileEdit(cf.robot_path, target_before, after)]
    summary = (f"controller file migrated {old} -> {new_wheel}: {cf.robot_path} (the {new_wheel} default"
               + (f", your limits kept: {', '.join(kept)})" if kept else ")"))
    warnings.insert(0, f"{host} was the {old} controller file; {summary}")
    return WheelChange(cf.robot_path, cf.container_path, new, edits, warnings, summary)


def _carry_limits(cfg: RobotConfig, current: ControllerConfig, stock: ControllerConfig | None,
                  new: ControllerConfig, new_wheel: str) -> tuple[ControllerConfig, list[str], list[str]]:
    """Set into ``new`` each limit of ``current`` that is not the old type's stock value (nor
    already ``new``'s) and is within ``new_wheel``'s limits; the kept ones and a warning for
    each of the others."""
    kept: list[str] = []
    warnings: list[str] = []
    for key, value in current.limits().items():
        if same_limit(value, new.get(key)) or (stock is not None and same_limit(value, stock.get(key))):
            continue  # the old type's default: the new type's value replaces it
        lk = parse_limit_key(key)
        if lk.axis == "linear.y" and new_wheel != "WH02":
            warnings.append(f"{key}={value}: {new_wheel} wheels have no linear.y; dropped")
            continue
        try:
            validate_limit(cfg.stack, new_wheel, lk, value)
        except UsageError as exc:
            warnings.append(f"{exc.message}: the {new_wheel} value {new.get(key)} is used")
            continue
        new.set(key, value)
        kept.append(f"{key}={value}")
    return new, kept, warnings


def _migrate_tree(reads: Reads, cfg: RobotConfig, new_wheel: str, model: str | None) -> WheelChange | None:
    """husarion_ugv 2.2 reading the controller file from the config tree: the user's limits in
    the old type's tree file (those that differ from the release's stock file) carried into the
    new type's tree file. None: the tree is not read, or holds the stock limits."""
    args = cfg.compose.args
    old = args.get("wheel_type") or spec("wheel_type").default_for(cfg.stack, model)
    if new_wheel in (old, "custom") or old == "custom" or args.get("wheel_config_path"):
        return None
    try:
        old_cf = config_file(cfg.stack, FileKind.CONTROLLER, wheel_type=old)
        new_cf = config_file(cfg.stack, FileKind.CONTROLLER, wheel_type=new_wheel)
    except UsageError:
        return None  # no stock file of that type on this release
    if not (cfg.reads_from_tree(old_cf) and cfg.reads_from_tree(new_cf)):
        return None
    before = reads.file(old_cf.robot_path)
    if before is None:
        return None
    try:  # parsed only for a robot that reads the tree: ~10 ms of CPU each (docs/performance.md)
        stock = ControllerConfig.default(cfg.stack, old)
    except UsageError:
        return None  # no stock file of that type on this release
    try:
        current = ControllerConfig.parse(before.decode(errors="replace"), cfg.stack, old, path=old_cf.robot_path,
                                         force=True)
    except UsageError as exc:
        raise UsageError(f"{old_cf.robot_path}: your {old} limits cannot be carried to {new_wheel}: {exc.message}",
                         hint=f"correct the file, or push a {new_wheel} controller file: panther-ops config push "
                         "FILE --as controller") from None
    if same_limits(current.limits(), stock.limits()):
        return None  # the stock limits: the new type's file is used as it is
    target_before = reads.file(new_cf.robot_path)
    try:
        base = (ControllerConfig.parse(target_before.decode(errors="replace"), cfg.stack, new_wheel,
                                       path=new_cf.robot_path, force=True)
                if target_before is not None else ControllerConfig.default(cfg.stack, new_wheel))
    except UsageError as exc:
        raise UsageError(f"{new_cf.robot_path}: your {old} limits cannot be carried into it: {exc.message}",
                         hint=f"push a {new_wheel} controller file: panther-ops config push FILE --as controller") \
            from None
    new, kept, warnings = _carry_limits(cfg, current, stock, base, new_wheel)
    after = new.text().encode()
    edits = [] if after == target_before else [FileEdit(new_cf.robot_path, target_before, after)]
    summary = (f"your {old} limits carried to {new_cf.robot_path}: " + ", ".join(kept) if kept
               else f"none of your {old} limits carried to {new_cf.robot_path}")
    warnings.insert(0, f"{old_cf.robot_path} holds {old} limits of your own (not the {cfg.stack.label()} stock "
                    f"values); with wheel_type {new_wheel} the driver reads the tree's {new_cf.filename}: "
                    + (f"carried: {', '.join(kept)}" if kept else "none carried"))
    return WheelChange(new_cf.robot_path, None, new, edits, warnings, summary)


def point_at(cfg: RobotConfig, change: WheelChange) -> dict[str, str]:
    """Mount the migrated file (in memory); the launch argument to set (none for the tree's file)."""
    if change.container_path is None:
        return {}
    if cfg.host_path_of(change.container_path) != change.host_path:
        cfg.compose.add_volume(change.host_path, change.container_path, ro=True)
    return {"controller_config_path": change.container_path}
