"""The planner of `panther-ops apply` and `config diff`: the inventory's desired state
(launch arguments, controller, image, GPS, shutdown hosts, the WebUI on the User Computer) converged in one
plan per robot. The WebUI's change is the plan's action after the robot's files (see
`apply.py`).

Pure: a function of compose.yaml as read, the files and facts it asks for (:class:`Reads`;
the WebUI's state is fact ``webui``) and the robot's ``desired:`` block; the reads are
`read.py`'s."""

from __future__ import annotations

from typing import Any

from panther_ops.core.fleet.plan import FileEdit, RobotPlan, Verify
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.remote.webui.plan import WebuiPlan
from panther_ops.core.robot.edits import args_summary, compose_plan, controller_edits, edit_args
from panther_ops.core.robot.robot_config import ComposeRead, RobotConfig, parse_config
from panther_ops.core.robot.robot_model import model_for_wheels


def plan_desired(raw: ComposeRead, reads: Reads, desired: dict[str, Any], *, force: bool = False) -> RobotPlan:
    """Converge the robot to the inventory's ``desired:`` launch_args, controller and image."""
    cfg = parse_config(raw, reads.stack)
    if not desired:
        return compose_plan(reads.robot, cfg, "no change", [], [], "no desired: block for this robot")
    old_args = dict(cfg.compose.args)
    driver_before = cfg.compose.service(cfg.service)
    warnings: list[str] = []
    verify: list[Verify] = []
    edits: list[FileEdit] = []
    parts: list[str] = []
    image = desired.get("image")
    if image and image != cfg.compose.driver_image:
        cfg.compose.set_image(image)
        parts.append(f"image -> {image}")
    _driver_files(reads, cfg, desired, force, (edits, warnings, verify, parts))
    if desired.get("shutdown_hosts") is not None:
        from panther_ops.core.shutdown.plan import desired_hosts

        hosts = desired_hosts(reads, cfg, desired["shutdown_hosts"])
        edits += hosts.edits
        warnings += hosts.warnings
        parts += [hosts.summary] if hosts.summary else []
    recreate: tuple[str, ...] = ()
    driver_files = bool(edits)
    if desired.get("gps") is not None:
        from panther_ops.core.gps.desired import desired_gps

        gps = desired_gps(reads, cfg, desired["gps"])
        edits += gps.extra
        warnings += gps.warnings
        verify += gps.verify
        parts += gps.parts
        recreate = gps.recreate
    arg_summary = args_summary(cfg, old_args)
    if arg_summary != "no change":
        parts.insert(0, arg_summary)
    webui = _plan_webui(reads, cfg, desired.get("webui"), warnings)
    unsupported = sorted(set(desired) - {"image", "launch_args", "controller", "gps", "webui", "shutdown_hosts"})
    if unsupported:
        warnings.append(f"desired {', '.join(unsupported)}: applied by their own commands, not by `apply`")
    plan = compose_plan(reads.robot, cfg, "; ".join(parts) or "no change", warnings, verify,
                        "matches the inventory's desired state", extra=edits)
    if plan.edits and recreate:  # desired.gps: the nmea-gps service alone when the driver is as it was
        driver_same = not driver_files and cfg.compose.service(cfg.service) == driver_before
        plan.recreate = recreate if driver_same else tuple(dict.fromkeys((*plan.recreate, *recreate)))
        if driver_same:
            plan.verify = [v for v in plan.verify if v.service in recreate]
    _add_webui(plan, webui)
    return plan


def _driver_files(reads: Reads, cfg: RobotConfig, desired: dict[str, Any], force: bool,
                  into: tuple[list[FileEdit], list[str], list[Verify], list[str]]) -> None:
    """desired.launch_args and desired.controller (a wheel type change migrates a custom
    controller file), added ``into`` the plan's edits, warnings, checks and summary parts."""
    edits, warnings, verify, parts = into
    migrated = None
    if desired.get("launch_args"):
        largs = dict(desired["launch_args"])
        if "wheel_type" in largs:
            from panther_ops.core.robot.wheel_change import migrate, point_at

            migrated = migrate(reads, cfg, str(largs["wheel_type"]))
            if migrated is not None:
                largs.update(point_at(cfg, migrated))
                warnings += migrated.warnings
                parts.append(migrated.summary)
        w, v = edit_args(cfg, largs, [], force, model_for_wheels(reads, cfg.stack, largs))
        warnings += w
        verify.append(v)
    if desired.get("controller"):
        e, w, v, s = controller_edits(reads, cfg, desired["controller"], force, migrated)
        if migrated is not None:
            migrated.edits = []  # the controller edit below carries the migrated file
        if e:
            edits += e
            parts.append(s)
        warnings += w
        verify.append(v)
    if migrated is not None:
        edits += migrated.edits


def _plan_webui(reads: Reads, cfg: RobotConfig, desired: dict[str, Any] | None,
                warnings: list[str]) -> WebuiPlan | None:
    """desired.webui's plan, with the robot's namespace as this plan leaves the compose file."""
    if not desired:
        return None
    from panther_ops.core.remote.webui.defaults import robot_namespace_of
    from panther_ops.core.remote.webui.plan import plan_desired_webui

    webui = plan_desired_webui(reads, desired, robot_namespace_of(reads, cfg))
    warnings += webui.warnings or []
    return webui


def _add_webui(plan: RobotPlan, webui: WebuiPlan | None) -> None:
    """The WebUI's change as the plan's action, after the files (see the module's text)."""
    if webui is None or not webui.changes:
        if webui is not None and webui.host:
            plan.data["webui"] = webui.to_json()
        return
    from panther_ops.core.remote.webui.plan import ACTION

    plan.data.update(action=ACTION, webui={**webui.to_json(), "wanted": webui.wanted},
                     files_summary=plan.summary if plan.edits else "")
    plan.summary = f"change {plan.summary}; {webui.summary}" if plan.edits else webui.summary
    plan.noop = None
