"""The planners of `panther-ops config`: launch arguments, controller limits (`config
set/unset`) and `config push` (a checked file, and what it brings along, onto one robot).

Pure functions of what was read (compose.yaml as :class:`ComposeRead`, other files through
:class:`Reads`), the local bundle and what the user asked; each returns a :class:`RobotPlan`
with exact file edits. The reads are `read.py`'s; nothing here touches a robot.
"""

from __future__ import annotations

import posixpath
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from panther_ops.core.config.arg_edits import set_launch_args, unset_launch_arg
from panther_ops.core.config.controller import ControllerConfig
from panther_ops.core.config.files import CONTAINER_CONFIG_DIR, ROBOT_CONFIG_DIR, ConfigFile, config_file
from panther_ops.core.config.launch_args import spec
from panther_ops.core.config.namespace_follow import follow_in_compose, follow_in_env_file
from panther_ops.core.config.robot_config import ComposeRead, RobotConfig, parse_config
from panther_ops.core.fleet.memo import Memo
from panther_ops.core.fleet.plan import FileEdit, RobotPlan, Verify
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.kinds import FileKind, Target, check_file
from panther_ops.errors import InputError, UsageError

if TYPE_CHECKING:
    from panther_ops.core.config.wheel_change import WheelChange


def _value_text(value: Any) -> str:
    if isinstance(value, bool):
        return "True" if value else "False"
    return str(value)


def edit_args(cfg: RobotConfig, sets: Mapping[str, Any], unsets: list[str], force: bool,
              robot_model: str | None = None) -> tuple[list[str], Verify]:
    """Apply argument changes to ``cfg.compose`` (in memory); returns warnings and the check.
    ``robot_model``: the robot's ROBOT_MODEL_NAME (`robot_model.env_robot_model`), where read."""
    from panther_ops.core.config.stale_mounts import drop_unused_mounts

    warnings: list[str] = []
    contains: list[str] = []
    lacks: list[str] = []
    before = dict(cfg.compose.args)
    for key in unsets:  # first: the sets are checked against the command as it will be
        unset_launch_arg(cfg.compose, key)
        lacks.append(key)
    if sets:
        change = set_launch_args(cfg.compose, {k: _value_text(v) for k, v in sets.items()}, force=force,
                                 robot_model=robot_model)
        warnings.extend(change.warnings)
        contains.extend(f"{a.name}:={a.value}" for a in change.args)
    warnings.extend(drop_unused_mounts(cfg, before))  # in the same plan and diff
    cmd = cfg.compose.command()
    lacks = [f"{name}:={cmd.args[name]}" for name in lacks if name in cmd.args]
    return warnings, Verify(cfg.service, tuple(contains), tuple(lacks))


@dataclass(frozen=True)
class _ArgsOutcome:
    """What a launch-argument change does to one compose.yaml (the same for every robot with it)."""

    after: bytes
    summary: str
    warnings: tuple[str, ...]
    verify: Verify
    service: str
    stack: str
    also_recreate: tuple[str, ...] = ()
    """Other services changed with the driver (``config set namespace --everywhere``)."""
    env_files: tuple[str, ...] = ()
    """The driver's env files, when the namespace changes (they may carry ROBOT_NAMESPACE)."""


_ARGS: Memo[_ArgsOutcome] = Memo()


def plan_args(raw: ComposeRead, reads: Reads, sets: Mapping[str, Any], unsets: list[str], *, force: bool = False,
              everywhere: bool = False) -> RobotPlan:
    """``config set/unset``: launch arguments in the driver's command.

    Planned once per distinct compose.yaml (and stack setting) of the fleet; the robots
    that share one get the same edit. A new ``namespace`` warns of the places that keep
    the old one (``everywhere``: changes them in the same plan, see namespace_follow).
    """
    model = None
    if "wheel_type" in sets or "wheel_type" in unsets:
        from panther_ops.core.config.robot_model import env_robot_model, robot_model_of
        from panther_ops.core.config.wheel_change import migrate

        cfg = parse_config(raw, reads.stack)
        model = env_robot_model(reads, cfg.stack)  # WH05 is the Lynx wheel: the model decides
        running = str(sets.get("robot_model") or robot_model_of(reads, cfg))  # and the default wheel type
        new_wheel = (str(sets["wheel_type"]) if "wheel_type" in sets
                     else spec("wheel_type").default_for(cfg.stack, running))
        change = migrate(reads, cfg, new_wheel, running)
        if change is not None:
            return _plan_wheel_change(reads, cfg, change, sets, unsets, force, model)
    key = (raw, reads.stack, tuple((k, _value_text(v)) for k, v in sets.items()), tuple(unsets), force,
           everywhere, model)
    out = _ARGS.get(key, lambda: _edit_args_of(raw, reads.stack, sets, unsets, force, everywhere, model))
    edits = [FileEdit(raw.path, raw.before, out.after, raw.mode)] if out.after != raw.before else []
    warnings, summary = list(out.warnings), out.summary
    for path in out.env_files:
        data = reads.file(path)
        if data is None:
            continue
        env = follow_in_env_file(path, data, _value_text(sets["namespace"]), everywhere=everywhere)
        warnings += env.warnings
        if env.after is not None and edits:
            edits.append(FileEdit(path, data, env.after))
            summary += "; also " + ", ".join(env.changed)
    plan = RobotPlan(reads.robot, summary, edits, (out.service, *out.also_recreate), raw.path, [out.verify],
                     None if edits else _noop_args(sets, unsets), warnings)
    plan.data["stack"] = out.stack
    plan.home = raw.home
    return plan


def _plan_wheel_change(reads: Reads, cfg: RobotConfig, change: WheelChange, sets: Mapping[str, Any],
                       unsets: list[str], force: bool, model: str | None = None) -> RobotPlan:
    """A wheel type change (set, or unset back to the stack's default) that migrates the custom
    controller file (or the tree's, `wheel_change`) in the same plan."""
    from panther_ops.core.config.wheel_change import point_at

    old_args = dict(cfg.compose.args)
    warnings, verify = edit_args(cfg, {**sets, **point_at(cfg, change)}, unsets, force, model)
    summary = f"{_args_summary(cfg, old_args)}; {change.summary}"
    return compose_plan(reads.robot, cfg, summary, [*change.warnings, *warnings], [verify],
                        _noop_args(sets, unsets), extra=change.edits)


def _edit_args_of(raw: ComposeRead, stack_setting: str, sets: Mapping[str, Any], unsets: list[str],
                  force: bool, everywhere: bool = False, model: str | None = None) -> _ArgsOutcome:
    cfg = parse_config(raw, stack_setting)
    old_args = dict(cfg.compose.args)
    warnings, verify = edit_args(cfg, sets, unsets, force, model)
    summary = _args_summary(cfg, old_args)
    also: tuple[str, ...] = ()
    env_files: tuple[str, ...] = ()
    if "namespace" in sets and cfg.compose.args.get("namespace") != old_args.get("namespace"):
        follow = follow_in_compose(cfg.compose, cfg.service, _value_text(sets["namespace"]), everywhere=everywhere)
        warnings += follow.warnings
        also = tuple(follow.services)
        env_files = tuple(cfg.compose.env_files(cfg.service))
        if follow.changed:
            summary += "; also " + ", ".join(follow.changed)
    return _ArgsOutcome(cfg.compose.text().encode(), summary, (*warnings, *cfg.compose.notes), verify, cfg.service,
                        cfg.stack.label(), also, env_files)


def _imu_warnings(reads: Reads, cfg: RobotConfig, ctrl: ControllerConfig, path: str) -> list[str]:
    """The robot's own controller file, edited in place: what its IMU broadcaster does under the
    driver's namespace (the edit does not change it; a template-made file is the stock one)."""
    from panther_ops.core.config.namespace import driver_namespace
    from panther_ops.core.kinds.controller_imu import imu_findings

    found = imu_findings(ctrl.doc.to_plain(), cfg.stack, driver_namespace(reads, cfg)[0])
    fix = f"; push a corrected file: panther-ops config push FILE --as controller ({found.hint})" if found.hint else ""
    return [f"{path}: {e} (already so on the robot){fix}" for e in found.errors] + \
        [f"{path}: {w}" for w in found.warnings]


def _args_summary(cfg: RobotConfig, old: Mapping[str, str]) -> str:
    new = cfg.compose.args
    parts = [f"{k}: {old[k]} -> {new[k]}" if k in old else f"{k}:={new[k]}" for k in new if old.get(k) != new[k]]
    parts += [f"unset {k}" for k in old if k not in new]
    return "; ".join(parts) or "no change"


def _noop_args(sets: Mapping[str, Any], unsets: list[str]) -> str:
    bits = [f"{k} already {_value_text(v)}" for k, v in sets.items()] + [f"{k} not set" for k in unsets]
    return ", ".join(bits) or "nothing asked"


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


def plan_controller(raw: ComposeRead, reads: Reads, limits: Mapping[str, Any], *, force: bool = False) -> RobotPlan:
    """``config set controller.<key> VALUE``: the robot's custom controller file."""
    cfg = parse_config(raw, reads.stack)
    edits, warnings, verify, summary = controller_edits(reads, cfg, limits, force)
    noop = ", ".join(f"controller {k} already {v}" for k, v in limits.items())
    return compose_plan(reads.robot, cfg, summary, warnings, [verify], noop, extra=edits)


def controller_edits(reads: Reads, cfg: RobotConfig, limits: Mapping[str, Any],
                     force: bool, migrated: Any = None) -> tuple[list[FileEdit], list[str], Verify, str]:
    """Edit (or create from the wheel type's default) the custom controller file; ``migrated``
    (a `wheel_change.WheelChange` of the same plan) is the file to edit when the wheel type changes."""
    from panther_ops.core.config.robot_model import wheel_type_of

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


BT_ARGS = {FileKind.BT_LIGHTS: "lights_bt_project_path", FileKind.BT_SAFETY: "safety_bt_project_path"}


@dataclass
class Bundle:
    """The local files of a push: the main file and what it brings along."""

    main: Path
    data: bytes
    extra: dict[str, bytes] = field(default_factory=dict)
    """name (relative to the main file's robot directory) -> content"""



_IMAGE = re.compile(r"^(\s*image:\s*)(['\"]?)([^'\"\n#]+?)\2(\s*(#.*)?)$", re.MULTILINE)


def _rewrite_images(text: str, target_dir: str) -> str:
    def sub(m: re.Match[str]) -> str:
        ref = m.group(3).strip()
        if ref.startswith("$(find"):
            return m.group(0)
        return f"{m.group(1)}{m.group(2)}{target_dir}/animations/{posixpath.basename(ref)}{m.group(2)}{m.group(4)}"

    return _IMAGE.sub(sub, text)


def robot_wheel(reads: Reads, cfg: RobotConfig) -> str:
    """The robot's ``wheel_type`` (``custom`` included; its model's default when the command
    sets none: WH05 on a Lynx)."""
    from panther_ops.core.config.robot_model import wheel_type_of

    return wheel_type_of(reads, cfg)


def wheel_of(reads: Reads, cfg: RobotConfig) -> str:
    """The wheel type whose stock files name the robot's (``WH01``'s for custom wheels)."""
    wheel = robot_wheel(reads, cfg)
    return "WH01" if wheel == "custom" else wheel


def robot_file(reads: Reads, cfg: RobotConfig, kind: FileKind) -> ConfigFile:
    """The configuration file of ``kind`` (not a BT project, not joy2twist) on this robot: of its
    stack, wheel type and model (a Lynx has its own animations)."""
    from panther_ops.core.config.robot_model import robot_model_of

    return config_file(cfg.stack, kind, wheel_type=wheel_of(reads, cfg), robot_model=robot_model_of(reads, cfg))


def _stock_named(kind: FileKind, data: bytes, reads: Reads, cfg: RobotConfig) -> bool:
    """The file may take the name of the robot wheel type's stock file (``WH01_controller.yaml``
    in the 2.2 tree): it describes those wheels, or states no kinematics. A custom wheel's file
    (the manual's procedure) or another stock wheel's keeps its own name, pointed at by its
    launch argument (what ``wheel_type:=custom`` needs)."""
    if kind not in (FileKind.CONTROLLER, FileKind.WHEEL):
        return True
    from panther_ops.core.kinds.stock_wheels import limits_wheel, wheels_in

    wheel = wheel_of(reads, cfg)
    return limits_wheel(wheels_in(kind is FileKind.CONTROLLER, data, cfg.stack), wheel) == wheel


_CHECKED: Memo[list[str]] = Memo()


@dataclass
class Pushed:
    """What a push does to a robot: its files, and (in ``cfg``) the mount and the argument."""

    edits: list[FileEdit]
    warnings: list[str]
    verify: Verify
    summary: str
    robot_path: str


def plan_push(raw: ComposeRead, reads: Reads, kind: FileKind, bundle: Bundle, *, force: bool = False) -> RobotPlan:
    """The plan of pushing ``bundle`` as ``kind`` to the robot whose compose.yaml is ``raw``."""
    cfg = parse_config(raw, reads.stack)
    if kind is FileKind.JOY2TWIST:
        from panther_ops.core.config.gamepad import plan_joy2twist

        warnings = _checked(reads, cfg, kind, bundle.main, bundle.data, force)
        return plan_joy2twist(reads, cfg, bundle.main.name, bundle.data, warnings)
    pushed = push_onto(reads, cfg, kind, bundle, force=force)
    plan = compose_plan(reads.robot, cfg, pushed.summary, pushed.warnings, [pushed.verify],
                        f"{pushed.robot_path} already has this content", extra=pushed.edits)
    plan.data["robot_path"] = pushed.robot_path
    return plan


def _checked(reads: Reads, cfg: RobotConfig, kind: FileKind, main: Path, data: bytes, force: bool) -> list[str]:
    """The file (``data``, as it will be written) through its kind's one validator, for this
    robot's stack, wheel and namespace (once each)."""
    namespace = None
    if kind is FileKind.CONTROLLER:  # its IMU broadcaster must read the IMU under the driver's namespace
        from panther_ops.core.config.namespace import driver_namespace

        namespace = driver_namespace(reads, cfg)[0]
    target = Target(cfg.stack, robot_wheel(reads, cfg), namespace)
    return list(_CHECKED.get((kind, str(main), data, target, force),
                             lambda: check_file(kind, str(main), data, local=main, target=target, force=force)))


def push_onto(reads: Reads, cfg: RobotConfig, kind: FileKind, bundle: Bundle, *, force: bool = False) -> Pushed:
    """Push ``bundle`` as ``kind`` (not joy2twist) onto the robot ``cfg`` describes: the files
    to write, checked by their kind's validator; the mount and the launch argument are made in
    ``cfg`` (the caller's plan writes compose.yaml)."""
    main_data, translated = bundle.data, list[str]()
    if kind in (FileKind.USER_ANIMATIONS, FileKind.LED):  # animation types of this stack, then its check
        from panther_ops.core.config.animation_types import for_stack

        text, translated = for_stack(bundle.data.decode(), cfg.stack)
        main_data = text.encode()
    warnings = _checked(reads, cfg, kind, bundle.main, main_data, force)
    warnings += [f"{bundle.main.name}: {t} for {cfg.stack.label()}" for t in translated]
    forced = [w for w in warnings if w.endswith("(forced)")]
    if kind in BT_ARGS:
        pkg = f"{cfg.stack.package_prefix}_manager"
        robot_dir = f"{ROBOT_CONFIG_DIR}/{pkg}/behavior_trees"
        container_dir = f"{CONTAINER_CONFIG_DIR}/{pkg}/behavior_trees"
        arg = BT_ARGS[kind]
        name = bundle.main.name
        main_data = bundle.data
        extra = bundle.extra
    else:
        cf = robot_file(reads, cfg, kind)
        if cf.launch_arg is None:  # written, it would change nothing (husarion_ugv 2.2's simulated battery)
            raise UsageError(f"--as {kind.value}: {cf.filename} is not the driver's on {cfg.stack.label()}: {cf.note}",
                             hint="pass the file to the simulation's launch command instead")
        arg = cf.launch_arg
        robot_dir, container_dir = posixpath.dirname(cf.robot_path), posixpath.dirname(cf.container_path)
        name = bundle.main.name
        in_tree = cfg.reads_from_tree(cf) and reads.file(cf.robot_path) is not None
        if in_tree and _stock_named(kind, main_data, reads, cfg):
            name = cf.filename  # the tree's own file: read through common_dir_path, no argument needed
            arg = ""
        extra = {}
        if kind is FileKind.USER_ANIMATIONS and bundle.extra:
            main_data = _rewrite_images(main_data.decode(), posixpath.dirname(container_dir)).encode()
            extra = {f"../{k}": v for k, v in bundle.extra.items()}
    edits: list[FileEdit] = []
    files = {name: main_data, **extra}
    inside = posixpath.dirname(robot_dir) if kind is FileKind.USER_ANIMATIONS else robot_dir
    for rel, content in files.items():
        path = posixpath.normpath(posixpath.join(robot_dir, rel))
        if not path.startswith(inside + "/"):
            raise InputError(f"{rel} would be written to {path}, outside {inside}", path=str(bundle.main),
                             hint="the files a push brings stay in the robot's config directory")
        before = reads.file(path)
        if before != content:
            edits.append(FileEdit(path, before, content))
    main_container = f"{container_dir}/{name}"
    contains: tuple[str, ...] = ()
    if not cfg.tree_mounted:
        mount_src = robot_dir if (extra or kind in BT_ARGS) else f"{robot_dir}/{name}"
        mount_dst = container_dir if (extra or kind in BT_ARGS) else main_container
        if kind is FileKind.USER_ANIMATIONS and extra:
            mount_src, mount_dst = posixpath.dirname(robot_dir), posixpath.dirname(container_dir)
        if cfg.host_path_of(mount_dst) != mount_src:
            cfg.compose.add_volume(mount_src, mount_dst, ro=True)
    if arg:
        arg = spec(arg).name_for(cfg.stack)  # the name this stack declares (2.2: animations_config_path)
        w, v = edit_args(cfg, {arg: main_container}, [], force)
        warnings += w
        contains = v.cmd_contains
    summary = f"{kind.value}: {bundle.main.name} -> {robot_dir}/{name}" + (f" ({arg}:={main_container})" if arg else "")
    if forced:
        summary += " [--force: " + "; ".join(forced) + "]"
    return Pushed(edits, warnings, Verify(cfg.service, contains), summary, f"{robot_dir}/{name}")

