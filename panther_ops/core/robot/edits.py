"""The edits every feature makes to the robot's configuration: launch arguments in the
driver's command (`edit_args`, through `arg_edits` and the launch arguments' rules), the custom
controller file (`controller_edits`), and the plan that writes compose.yaml with them
(`compose_plan`). Pure: functions of the parsed configuration and of what was read."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from panther_ops.core.fleet.plan import FileEdit, RobotPlan, Verify
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.kinds import FileKind
from panther_ops.core.robot.arg_edits import set_launch_args, unset_launch_arg
from panther_ops.core.robot.controller import ControllerConfig
from panther_ops.core.robot.files import config_file
from panther_ops.core.robot.robot_config import RobotConfig
from panther_ops.errors import UsageError


def value_text(value: Any) -> str:
    if isinstance(value, bool):
        return "True" if value else "False"
    return str(value)


def edit_args(cfg: RobotConfig, sets: Mapping[str, Any], unsets: list[str], force: bool,
              robot_model: str | None = None) -> tuple[list[str], Verify]:
    """Apply argument changes to ``cfg.compose`` (in memory); returns warnings and the check.
    ``robot_model``: the robot's ROBOT_MODEL_NAME (`robot_model.env_robot_model`), where read."""
    from panther_ops.core.robot.stale_mounts import drop_unused_mounts

    warnings: list[str] = []
    contains: list[str] = []
    lacks: list[str] = []
    before = dict(cfg.compose.args)
    for key in unsets:  # first: the sets are checked against the command as it will be
        unset_launch_arg(cfg.compose, key)
        lacks.append(key)
    if sets:
        change = set_launch_args(cfg.compose, {k: value_text(v) for k, v in sets.items()}, force=force,
                                 robot_model=robot_model)
        warnings.extend(change.warnings)
        contains.extend(f"{a.name}:={a.value}" for a in change.args)
    warnings.extend(drop_unused_mounts(cfg, before))  # in the same plan and diff
    cmd = cfg.compose.command()
    lacks = [f"{name}:={cmd.args[name]}" for name in lacks if name in cmd.args]
    return warnings, Verify(cfg.service, tuple(contains), tuple(lacks))


def _imu_warnings(reads: Reads, cfg: RobotConfig, ctrl: ControllerConfig, path: str) -> list[str]:
    """The robot's own controller file, edited in place: what its IMU broadcaster does under the
    driver's namespace (the edit does not change it; a template-made file is the stock one)."""
    from panther_ops.core.kinds.controller_imu import imu_findings
    from panther_ops.core.robot.namespace import driver_namespace

    found = imu_findings(ctrl.doc.to_plain(), cfg.stack, driver_namespace(reads, cfg)[0])
    fix = f"; push a corrected file: panther-ops config push FILE --as controller ({found.hint})" if found.hint else ""
    return [f"{path}: {e} (already so on the robot){fix}" for e in found.errors] + \
        [f"{path}: {w}" for w in found.warnings]


def args_summary(cfg: RobotConfig, old: Mapping[str, str]) -> str:
    new = cfg.compose.args
    parts = [f"{k}: {old[k]} -> {new[k]}" if k in old else f"{k}:={new[k]}" for k in new if old.get(k) != new[k]]
    parts += [f"unset {k}" for k in old if k not in new]
    return "; ".join(parts) or "no change"


def compose_plan(robot: str, cfg: RobotConfig, summary: str, warnings: list[str], verify: list[Verify],
                  noop: str, extra: list[FileEdit] | None = None) -> RobotPlan:
    edits = list(extra or [])
    after = cfg.compose.text().encode()
    if after != cfg.before:
        edits.insert(0, FileEdit(cfg.compose_path, cfg.before, after, cfg.mode))
    warnings = [*warnings, *cfg.compose.notes]
    plan = RobotPlan(robot, summary, edits, (cfg.service,), cfg.compose_path, verify,
                     None if edits else noop, warnings)
    plan.data["stack"] = cfg.stack.label()
    plan.home = cfg.home
    return plan


def controller_edits(reads: Reads, cfg: RobotConfig, limits: Mapping[str, Any],
                     force: bool, migrated: Any = None) -> tuple[list[FileEdit], list[str], Verify, str]:
    """Edit (or create from the wheel type's default) the custom controller file; ``migrated``
    (a `wheel_change.WheelChange` of the same plan) is the file to edit when the wheel type changes."""
    from panther_ops.core.robot.robot_model import wheel_type_of

    args = cfg.compose.args
    wheel = wheel_type_of(reads, cfg)
    if wheel == "custom" and "controller_config_path" not in args:
        raise UsageError("wheel_type custom needs controller_config_path (and wheel_config_path)")
    warnings: list[str] = []
    cf = config_file(cfg.stack, FileKind.CONTROLLER, wheel_type=wheel if wheel != "custom" else "WH01")
    container_path = args.get("controller_config_path")
    host_path = cfg.host_path_of(container_path) if container_path else None
    if container_path and host_path is None:
        raise UsageError(
            f"controller_config_path:={container_path} is not a file mounted from the robot",
            hint="push a controller file first: panther-ops config push FILE --as controller",
        )
    if host_path is None and cfg.reads_from_tree(cf):  # 2.2: the tree's file is the one in use
        host_path, container_path = cf.robot_path, None
    if host_path is None:
        host_path, container_path = cf.robot_path, cf.container_path
    before = reads.file(host_path)
    robot_file = False
    if migrated is not None and migrated.host_path == host_path:
        ctrl = migrated.controller
    elif before is not None:
        ctrl = ControllerConfig.parse(before.decode(), cfg.stack, wheel, path=host_path, force=force)
        robot_file = True
    else:
        ctrl = ControllerConfig.default(cfg.stack, wheel if wheel != "custom" else "WH01")
    changes = []
    for key, value in limits.items():
        change = ctrl.set(key, value, force=force)
        changes.append(change)
        warnings.extend(change.warnings)
    warnings.extend(ctrl.doc.notes)
    if robot_file:
        warnings.extend(_imu_warnings(reads, cfg, ctrl, host_path))
    after = ctrl.text().encode()
    edits = [] if after == before else [FileEdit(host_path, before, after)]
    contains: tuple[str, ...] = ()
    if container_path:
        if not cfg.host_path_of(container_path):
            cfg.compose.add_volume(host_path, container_path, ro=True)
        w, v = edit_args(cfg, {"controller_config_path": container_path}, [], force)
        warnings.extend(w)
        contains = v.cmd_contains
    summary = "; ".join(f"{k} = {v}" for k, v in limits.items()) + f" in {host_path}"
    return edits, warnings, Verify(cfg.service, contains), summary
