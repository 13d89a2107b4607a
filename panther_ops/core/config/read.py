"""Readers for `panther-ops config set/unset/get` and `config push`: read what the planners
(`plan.py`, pure) need over the robot's one connection, then plan."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from panther_ops.core.config import plan as planners
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.reading import read_and_plan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.kinds import FileKind
from panther_ops.core.robot.controller import ControllerConfig
from panther_ops.core.robot.files import config_file
from panther_ops.core.robot.launch_args import spec, unavailable_text
from panther_ops.core.robot.push import Bundle
from panther_ops.core.robot.read import read_compose, read_config


def read_and_plan_args(ctx: RobotContext, sets: Mapping[str, Any], unsets: list[str], *, force: bool = False,
              everywhere: bool = False) -> RobotPlan:
    """``config set/unset``: read compose.yaml (kept for the write) and what the plan needs; plan."""
    raw = read_compose(ctx)
    return read_and_plan(ctx, lambda reads: planners.plan_args(raw, reads, sets, unsets, force=force,
                                                               everywhere=everywhere))


def read_and_plan_controller(ctx: RobotContext, limits: Mapping[str, Any], *, force: bool = False) -> RobotPlan:
    """``config set controller.<key> VALUE``: read compose.yaml and the controller file; plan."""
    raw = read_compose(ctx)
    return read_and_plan(ctx, lambda reads: planners.plan_controller(raw, reads, limits, force=force))


def read_and_plan_push(ctx: RobotContext, kind: FileKind, bundle: Bundle, *, force: bool = False) -> RobotPlan:
    """``config push`` (and ``lights deploy``): read compose.yaml and the files the push would
    replace; plan."""
    raw = read_compose(ctx)
    return read_and_plan(ctx, lambda reads: planners.plan_push(raw, reads, kind, bundle, force=force))


def read_arg(ctx: RobotContext, key: str) -> dict[str, Any]:
    """``config get KEY``: the value in the command, or the stack's default; a launch argument the
    robot's release does not declare (and its command does not set) has no value there:
    ``value`` None and ``unavailable`` saying which releases have it."""
    from panther_ops.core.robot.robot_model import robot_model_of, wheel_type_of

    cfg = read_config(ctx)
    args = cfg.compose.args
    if key.startswith("controller."):
        wheel = read_and_plan(ctx, lambda reads: wheel_type_of(reads, cfg))
        cf = config_file(cfg.stack, FileKind.CONTROLLER, wheel_type=wheel if wheel != "custom" else "WH01")
        cpath = args.get("controller_config_path")
        host = cfg.host_path_of(cpath) if cpath else (cf.robot_path if cfg.reads_from_tree(cf) else None)
        text = None
        if host:
            try:
                text = ctx.transport.read_file(host).decode()
            except FileNotFoundError:
                text = None
        ctrl = (ControllerConfig.parse(text, cfg.stack, wheel, path=host or "") if text
                else ControllerConfig.default(cfg.stack, wheel if wheel != "custom" else "WH01"))
        return {"key": key, "value": ctrl.get(key),
                "source": host or "default for " + wheel, "stack": cfg.stack.label()}
    s = spec(key)
    name = s.name_for(cfg.stack)
    for n in (name, *s.all_names()):
        if n in args:
            return {"key": key, "name": n, "value": args[n], "source": "compose.yaml", "stack": cfg.stack.label()}
    if not s.available(cfg.stack):
        return {"key": key, "name": name, "value": None, "source": None, "stack": cfg.stack.label(),
                "unavailable": unavailable_text(s, cfg.stack)}
    if key == "namespace":  # the launch files' default: ROBOT_NAMESPACE of the compose environment or env_file
        from panther_ops.core.robot.namespace import driver_namespace

        value, source = read_and_plan(ctx, lambda reads: driver_namespace(reads, cfg))
        if source != "default":
            return {"key": key, "name": name, "value": value, "source": source, "stack": cfg.stack.label()}
    if s.model_dependent(cfg.stack):  # wheel_type: WH05 on a Lynx
        model = read_and_plan(ctx, lambda reads: robot_model_of(reads, cfg))
        return {"key": key, "name": name, "value": s.default_for(cfg.stack, model),
                "source": f"default for a {model}", "stack": cfg.stack.label()}
    return {"key": key, "name": name, "value": s.default_for(cfg.stack), "source": "default",
            "stack": cfg.stack.label()}
