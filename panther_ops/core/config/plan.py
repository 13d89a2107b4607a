"""The planners of `panther-ops config`: launch arguments, controller limits (`config
set/unset`) and `config push` (a checked file, and what it brings along, onto one robot).

Pure functions of what was read (compose.yaml as :class:`ComposeRead`, other files through
:class:`Reads`), the local bundle and what the user asked; each returns a :class:`RobotPlan`
with exact file edits. The reads are `read.py`'s; nothing here touches a robot. The edits
themselves are the robot's configuration model's (`core.robot.edits`, `core.robot.push`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from panther_ops.core.fleet.memo import Memo
from panther_ops.core.fleet.plan import FileEdit, RobotPlan, Verify
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.kinds import FileKind
from panther_ops.core.robot.edits import args_summary, compose_plan, controller_edits, edit_args, value_text
from panther_ops.core.robot.gamepad import driver_target, find_gamepad_service, gamepad_service, service_target
from panther_ops.core.robot.launch_args import spec
from panther_ops.core.robot.namespace_follow import follow_in_compose, follow_in_env_file
from panther_ops.core.robot.push import Bundle, checked_for, push_plan
from panther_ops.core.robot.robot_config import ComposeRead, RobotConfig, parse_config
from panther_ops.core.stack import Family

if TYPE_CHECKING:
    from panther_ops.core.robot.wheel_change import WheelChange


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
    asked = (tuple((k, value_text(v)) for k, v in sets.items()), tuple(unsets))
    if "wheel_type" in sets or "wheel_type" in unsets:
        # the same for every robot with this compose.yaml and these files (the check reads
        # nothing else): planned once, as the edit below
        seen = (raw, reads.stack, tuple(sorted(reads.files.items())), asked)
        model, migrates = _WHEEL.get(seen, lambda: _wheel_outcome(_looked_at(raw, reads.stack), reads, sets))
        if migrates:  # a controller file to carry over: this robot's own plan, on a parse of its own
            cfg = parse_config(raw, reads.stack)
            model, change = _wheel_check(cfg, reads, sets)
            assert change is not None
            return _plan_wheel_change(reads, cfg, change, sets, unsets, force, model)
    key = (raw, reads.stack, *asked, force, everywhere, model)
    out = _ARGS.get(key, lambda: _edit_args_of(raw, reads.stack, sets, unsets, force, everywhere, model))
    edits = [FileEdit(raw.path, raw.before, out.after, raw.mode)] if out.after != raw.before else []
    warnings, summary = list(out.warnings), out.summary
    for path in out.env_files:
        data = reads.file(path)
        if data is None:
            continue
        env = follow_in_env_file(path, data, value_text(sets["namespace"]), everywhere=everywhere)
        warnings += env.warnings
        if env.after is not None and edits:
            edits.append(FileEdit(path, data, env.after))
            summary += "; also " + ", ".join(env.changed)
    plan = RobotPlan(reads.robot, summary, edits, (out.service, *out.also_recreate), raw.path, [out.verify],
                     None if edits else _noop_args(sets, unsets), warnings)
    plan.data["stack"] = out.stack
    plan.home = raw.home
    return plan


_WHEEL: Memo[tuple[str, bool]] = Memo()
_PARSED: Memo[RobotConfig] = Memo()


def _looked_at(raw: ComposeRead, stack_setting: str) -> RobotConfig:
    """compose.yaml parsed once for every robot that has it, only to be looked at (the wheel
    check reads it again after each file it asks for); a plan that edits parses its own."""
    return _PARSED.get((raw, stack_setting), lambda: parse_config(raw, stack_setting))


def _wheel_outcome(cfg: RobotConfig, reads: Reads, sets: Mapping[str, Any]) -> tuple[str, bool]:
    """:func:`_wheel_check`'s model, and whether a controller file migrates (shared)."""
    model, change = _wheel_check(cfg, reads, sets)
    return model, change is not None


def _wheel_check(cfg: RobotConfig, reads: Reads, sets: Mapping[str, Any]) -> tuple[str, WheelChange | None]:
    """What a wheel type change needs to know of the robot: ROBOT_MODEL_NAME's model (WH05
    is the Lynx wheel: the model decides, and the default wheel type), and the migration of
    a controller file to the new type, if one must be carried over (`wheel_change.migrate`,
    which only looks at ``cfg``)."""
    from panther_ops.core.robot.robot_model import env_robot_model, robot_model_of
    from panther_ops.core.robot.wheel_change import migrate

    model = env_robot_model(reads, cfg.stack)
    running = str(sets.get("robot_model") or robot_model_of(reads, cfg))
    new_wheel = str(sets["wheel_type"]) if "wheel_type" in sets else spec("wheel_type").default_for(cfg.stack, running)
    return model, migrate(reads, cfg, new_wheel, running)


def _plan_wheel_change(reads: Reads, cfg: RobotConfig, change: WheelChange, sets: Mapping[str, Any],
                       unsets: list[str], force: bool, model: str | None = None) -> RobotPlan:
    """A wheel type change (set, or unset back to the stack's default) that migrates the custom
    controller file (or the tree's, `wheel_change`) in the same plan."""
    from panther_ops.core.robot.wheel_change import point_at

    old_args = dict(cfg.compose.args)
    warnings, verify = edit_args(cfg, {**sets, **point_at(cfg, change)}, unsets, force, model)
    summary = f"{args_summary(cfg, old_args)}; {change.summary}"
    return compose_plan(reads.robot, cfg, summary, [*change.warnings, *warnings], [verify],
                        _noop_args(sets, unsets), extra=change.edits)


def _edit_args_of(raw: ComposeRead, stack_setting: str, sets: Mapping[str, Any], unsets: list[str],
                  force: bool, everywhere: bool = False, model: str | None = None) -> _ArgsOutcome:
    cfg = parse_config(raw, stack_setting)
    old_args = dict(cfg.compose.args)
    warnings, verify = edit_args(cfg, sets, unsets, force, model)
    summary = args_summary(cfg, old_args)
    also: tuple[str, ...] = ()
    env_files: tuple[str, ...] = ()
    if "namespace" in sets and cfg.compose.args.get("namespace") != old_args.get("namespace"):
        follow = follow_in_compose(cfg.compose, cfg.service, value_text(sets["namespace"]), everywhere=everywhere)
        warnings += follow.warnings
        also = tuple(follow.services)
        env_files = tuple(cfg.compose.env_files(cfg.service))
        if follow.changed:
            summary += "; also " + ", ".join(follow.changed)
    return _ArgsOutcome(cfg.compose.text().encode(), summary, (*warnings, *cfg.compose.notes), verify, cfg.service,
                        cfg.stack.label(), also, env_files)



def _noop_args(sets: Mapping[str, Any], unsets: list[str]) -> str:
    bits = [f"{k} already {value_text(v)}" for k, v in sets.items()] + [f"{k} not set" for k in unsets]
    return ", ".join(bits) or "nothing asked"


def plan_controller(raw: ComposeRead, reads: Reads, limits: Mapping[str, Any], *, force: bool = False) -> RobotPlan:
    """``config set controller.<key> VALUE``: the robot's custom controller file."""
    cfg = parse_config(raw, reads.stack)
    edits, warnings, verify, summary = controller_edits(reads, cfg, limits, force)
    noop = ", ".join(f"controller {k} already {v}" for k, v in limits.items())
    return compose_plan(reads.robot, cfg, summary, warnings, [verify], noop, extra=edits)


def plan_push(raw: ComposeRead, reads: Reads, kind: FileKind, bundle: Bundle, *, force: bool = False) -> RobotPlan:
    """The plan of pushing ``bundle`` as ``kind`` to the robot whose compose.yaml is ``raw``."""
    cfg = parse_config(raw, reads.stack)
    if kind is FileKind.JOY2TWIST:
        warnings = checked_for(reads, cfg, kind, bundle.main, bundle.data, force)
        return plan_joy2twist(reads, cfg, bundle.main.name, bundle.data, warnings)
    return push_plan(reads, cfg, kind, bundle, force=force)


def plan_joy2twist(reads: Reads, cfg: RobotConfig, name: str, data: bytes, warnings: list[str]) -> RobotPlan:
    """The plan of a checked joy2twist file ``name`` with content ``data`` for this robot."""
    edits: list[FileEdit] = []
    service = find_gamepad_service(cfg)
    contains: tuple[str, ...] = ()
    if service is not None:
        path, contains = service_target(cfg, service, name)
    elif cfg.stack.family is Family.HUSARION_UGV:
        service, path = driver_target(reads, cfg, warnings)
    else:
        service = gamepad_service(cfg)  # refused, naming what is there
        path = ""
    before = reads.file(path)
    if before != data:
        edits.append(FileEdit(path, before, data))
    after = cfg.compose.text().encode()
    if after != cfg.before:
        edits.insert(0, FileEdit(cfg.compose_path, cfg.before, after, cfg.mode))
    summary = f"joy2twist: {name} -> {path}" + (f" ({contains[0]} in {service})" if contains else "")
    plan = RobotPlan(reads.robot, summary, edits, (service,), cfg.compose_path, [Verify(service, contains)],
                     None if edits else f"{path} already has this content", [*warnings, *cfg.compose.notes])
    plan.data["stack"] = cfg.stack.label()
    plan.data["robot_path"] = path
    plan.home = cfg.home
    return plan
