"""`driver update`: a new driver image in compose.yaml, pulled, recreated, verified, rolled back on failure."""

from __future__ import annotations

import posixpath
import re
from dataclasses import replace
from typing import Any

from panther_ops.core.config.arg_edits import migrate_args
from panther_ops.core.config.arg_rules import check_args
from panther_ops.core.config.compose import ComposeError, ComposeFile
from panther_ops.core.config.plans import compose_plan
from panther_ops.core.config.robot import RobotConfig, read_config
from panther_ops.core.containers.engine import engine
from panther_ops.core.driver.containers import last_line, service_containers
from panther_ops.core.driver.images import TargetImage, parse_target, repo_for
from panther_ops.core.driver.restart import DEFAULT_SERVICE
from panther_ops.core.fleet.pipeline import ApplyOptions, apply_plan, mark_backup, recreate_and_verify, roll_back
from panther_ops.core.fleet.plan import RobotPlan, Verify
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.stack import Family, parse_image
from panther_ops.errors import UsageError
from panther_ops.results import Outcome, RobotResult
from panther_ops.transport.base import Command

_FAMILY_LABEL = {Family.PANTHER_ROS: "panther_ros (2.0-2.1)", Family.HUSARION_UGV: "husarion_ugv_ros (2.2)"}
_BRINGUP = {Family.PANTHER_ROS: "panther_bringup", Family.HUSARION_UGV: "husarion_ugv_bringup"}


def _rename_service(compose: ComposeFile, old: str, new: str) -> ComposeFile:
    """compose.yaml with service key ``old`` renamed ``new`` (only that line changes)."""
    text = compose.text()
    start = compose.doc.info(("services", old)).start
    keys = [m for m in re.finditer(rf"^([ \t]*){re.escape(old)}:(?=[ \t]*(?:#.*)?$)", text, re.M)
            if m.start() < start]
    if not keys:
        raise ComposeError(f"cannot rename service {old}: its key is not written plainly", path=compose.path)
    k = keys[-1]
    renamed = ComposeFile.parse(text[: k.start()] + k[1] + new + ":" + text[k.end():], compose.path)
    if new not in renamed.services() or old in renamed.services() or renamed.service(new) != compose.service(old):
        raise ComposeError(f"cannot rename service {old} to {new} in place", path=compose.path)
    return renamed


def _replace_package(compose: ComposeFile, service: str, old: str, new: str) -> ComposeFile:
    info = compose.doc.info(("services", service, "command"))
    text = compose.text()
    region = re.sub(rf"(?<![\w/-]){re.escape(old)}(?![\w/-])", new, text[info.start:info.end])
    out = ComposeFile.parse(text[: info.start] + region + text[info.end:], compose.path)
    if out.command(service).package != new:
        raise ComposeError(f"cannot change the launch package of {service} to {new}", path=compose.path)
    return out


_FAMILY_NOTES = {
    Family.HUSARION_UGV: (
        "husarion_ugv_ros 2.2 expects Built-in Computer OS 2.x: /run/husarion/robot_config.env, the config tree "
        "~/config mounted at /config with common_dir_path:=/config and env_file ~/config/common/.env, the gamepad "
        "inside the driver (launch_gamepad:=true); none of that is added here (Husarion's path: reinstall the OS)"
    ),
    Family.PANTHER_ROS: (
        "panther_ros 2.0-2.1 expects /run/husarion/panther_config.env and its config inside the image "
        "(no ~/config tree, gamepad as its own gamepad_controller service); none of that is added here"
    ),
}


def _change_family(cfg: RobotConfig, target: Family, warnings: list[str]) -> str | None:
    """Rename the driver service and launch package for the other family; returns the old service name."""
    old_service = cfg.service
    new_service = DEFAULT_SERVICE[target]
    compose = cfg.compose
    renamed_from: str | None = None
    if old_service == DEFAULT_SERVICE[cfg.stack.family] and new_service not in compose.services():
        compose = _rename_service(compose, old_service, new_service)
        renamed_from = old_service
    else:
        new_service = old_service
    if compose.command(new_service).package == _BRINGUP[cfg.stack.family]:
        compose = _replace_package(compose, new_service, _BRINGUP[cfg.stack.family], _BRINGUP[target])
    if compose.service(new_service).get("container_name") == old_service and renamed_from:
        compose.doc.set(("services", new_service, "container_name"), new_service)
    cfg.compose = compose
    warnings.append(_FAMILY_NOTES[target])
    return renamed_from


def plan_update(ctx: RobotContext, target: TargetImage | None, *, force: bool = False, pull: bool = False) -> RobotPlan:
    """`driver update`: the driver image in compose.yaml (``target`` None: the inventory's desired image)."""
    cfg = read_config(ctx)
    if target is None:
        wanted = ctx.robot.desired.get("image")
        if not wanted:
            return compose_plan(ctx, cfg, "no change", [], [], "no TAG given and no desired image in the inventory")
        target = parse_target(str(wanted), force=force)
    current = cfg.compose.driver_image
    new_ref = target.ref_for(current)
    warnings = list(target.warnings)
    old_stack = cfg.stack
    new_stack = parse_image(f"{repo_for(target.version)}:{target.tag}")
    if new_ref == current:
        plan = compose_plan(ctx, cfg, "no change", warnings, [], f"compose.yaml already has {current}")
        plan.data.update(image_from=current, image_to=new_ref)
        return plan
    old_service = cfg.service
    renamed_from: str | None = None
    if new_stack.family is not old_stack.family:
        if not force:
            raise UsageError(
                f"{current} -> {new_ref} moves the robot from {_FAMILY_LABEL[old_stack.family]} to "
                f"{_FAMILY_LABEL[new_stack.family]}: another image repository and service name ({old_service} -> "
                f"{DEFAULT_SERVICE[new_stack.family]}), another config layout and OS; that is a reinstall, "
                "not an update",
                hint="Husarion's path is reinstalling the Built-in Computer's OS image; --force edits compose.yaml "
                     "anyway (image, service name, launch package, launch arguments) and rolls back if the driver "
                     "fails",
            )
        renamed_from = _change_family(cfg, new_stack.family, warnings)
    old_args = dict(cfg.compose.args)
    migration = migrate_args(old_stack, new_stack, old_args)
    service = cfg.service
    for name in migration.dropped:
        cfg.compose.unset_arg(name, service)
        warnings.append(f"launch argument {name}:={old_args[name]} dropped: {new_stack.label()} has no such argument")
    for old, new in migration.renamed.items():
        cfg.compose.unset_arg(old, service)
        cfg.compose.set_arg(new, old_args[old], service)
        warnings.append(f"launch argument {old} renamed {new} for {new_stack.label()}; check the file it points "
                        "to has that version's format")
    cfg.compose.set_image(new_ref, service, force=force)
    volumes = cfg.compose.list_volumes(service)
    before = {(f.rule, f.keys) for f in check_args(old_stack, old_args, volumes=volumes)}
    warnings += [f"after the update: {f.message}" for f in check_args(new_stack, cfg.compose.args, volumes=volumes)
                 if (f.rule, f.keys) not in before]
    if ctx.robot.stack != "auto":
        warnings.append(f"the inventory pins stack: {ctx.robot.stack} for this robot: change it to "
                        f"{new_stack.version_str} (or auto) with the update")
    warnings += _device_notes(cfg.compose.service(service).get("devices") or [], new_stack.version)
    present = _image_present(ctx, new_ref)
    if present is False:
        warnings.append(f"{new_ref} is not on the robot: it needs a pull (internet on the robot); "
                        + ("--pull runs docker compose pull first" if not pull else "pulled before recreating"))
    parts = [f"image {current} -> {new_ref}"]
    if renamed_from:
        parts.append(f"service {renamed_from} -> {service}")
    parts += [f"{o} -> {n}" for o, n in migration.renamed.items()] + [f"drop {d}" for d in migration.dropped]
    words = tuple(f"{k}:={v}" for k, v in cfg.compose.args.items())
    plan = compose_plan(ctx, cfg, "; ".join(parts), warnings, [Verify(service, words)], "no change")
    plan.data.update(image_from=current, image_to=new_ref, image_local=present, pull=pull,
                     stack_from=old_stack.label(), stack_to=new_stack.label())
    if renamed_from:
        plan.data["service_from"] = renamed_from
    return plan


def _device_notes(devices: list[Any], version: tuple[int, int, int]) -> list[str]:
    """The LED SPI devices were renamed at 2.1.0 (spidev0.x -> spiled-channelN, with cgroup rules)."""
    text = " ".join(str(d) for d in devices)
    if version >= (2, 1, 0) and "/dev/spidev0." in text:
        return ["2.1+ drives the LEDs through /dev/spiled-channel1/2 (with device_cgroup_rules), not /dev/spidev0.x: "
                "update the devices of the driver service (see the 2.1 compose file) or the lights will not work"]
    if version < (2, 1, 0) and "/dev/spiled-channel" in text:
        return ["2.0 drives the LEDs through /dev/spidev0.0/0.1, not /dev/spiled-channelN: update the devices of "
                "the driver service (see the 2.0 compose file) or the lights will not work"]
    return []


def _image_present(ctx: RobotContext, ref: str) -> bool | None:
    """Whether the robot's engine has ``ref`` (None: no engine to ask)."""
    client, _why = engine(ctx)
    if client is None:
        return None
    import docker.errors

    try:
        client.images.get(ref)
    except docker.errors.ImageNotFound:
        return False
    except docker.errors.APIError:
        return None
    return True


def apply_update(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions) -> RobotResult:
    """Apply a `driver update` plan: the pipeline, plus pull / orphan removal when the plan needs them."""
    renamed_from = plan.data.get("service_from")
    pull = bool(plan.data.get("pull"))
    if not (renamed_from or pull) or not plan.edits or opts.dry_run or not opts.restart:
        result = apply_plan(ctx, plan, opts)
        if renamed_from and result.outcome is Outcome.CHANGED and not opts.restart and not opts.dry_run:
            result.warnings.append(
                f"the {renamed_from} container keeps running until the driver is recreated: then remove it "
                f"(docker compose up -d --remove-orphans {plan.recreate[0]}) or two drivers hold the hardware")
        return result
    client, _why = engine(ctx)
    if client is None:
        return apply_plan(ctx, plan, opts)
    result = apply_plan(ctx, plan, replace(opts, restart=False))
    if result.outcome is not Outcome.CHANGED:
        return result
    backup_id = str(result.data["backup"])
    result.message = plan.summary
    cdir = posixpath.dirname(plan.compose_file) or "~"
    if pull:
        res = ctx.transport.run(Command.of("docker", "compose", "-f", posixpath.basename(plan.compose_file), "pull",
                                           *plan.recreate, login=True, cwd=cdir), timeout=1800)
        if not res.ok:
            failed = f"docker compose pull failed: {last_line(res.stderr)}"
            return _roll_back_update(ctx, plan, opts, result, failed, backup_id, client, recreated=False)
    if renamed_from:
        for c in service_containers(client, str(renamed_from), cdir):
            c.remove(force=True)
    problem = recreate_and_verify(ctx, plan, opts.settle_s, result)
    if problem is None:
        result.outcome = Outcome.CHANGED
        mark_backup(ctx, backup_id, "applied")
        return result
    return _roll_back_update(ctx, plan, opts, result, problem, backup_id, client, recreated=True)


def _roll_back_update(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions, result: RobotResult, problem: str,
                      backup_id: str, client: Any, *, recreated: bool) -> RobotResult:
    """The pipeline's rollback; when containers were touched the old driver comes back up (a
    renamed service: the new service's containers removed first, the old one recreated)."""
    if not recreated:
        return roll_back(ctx, plan, opts, result, problem, backup_id, recreate=(),
                         note="; the driver was not touched")
    renamed_from = plan.data.get("service_from")
    if not renamed_from:
        return roll_back(ctx, plan, opts, result, problem, backup_id)
    cdir = posixpath.dirname(plan.compose_file) or "~"

    def remove_new_containers() -> None:
        for svc in plan.recreate:
            for c in service_containers(client, svc, cdir):
                c.remove(force=True)

    return roll_back(ctx, plan, opts, result, problem, backup_id, recreate=(str(renamed_from),),
                     before_recreate=remove_new_containers)
