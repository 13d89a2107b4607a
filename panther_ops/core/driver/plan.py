"""The planners of `driver restart|stop|start`, `driver update` and `config restore-defaults`.

Pure functions of compose.yaml as read (:class:`ComposeRead`), the facts they ask for
(:class:`Reads`: whether the robot has a docker engine, whether it holds an image) and what
the user asked; the reads are `read.py`'s, the executors `apply.py`'s.
"""

from __future__ import annotations

import posixpath
import re
from typing import Any

from panther_ops.core.driver.images import TargetImage, parse_target, repo_for
from panther_ops.core.fleet.plan import RobotPlan, Verify
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.robot.arg_edits import migrate_args
from panther_ops.core.robot.compose import ComposeError, ComposeFile
from panther_ops.core.robot.edits import compose_plan
from panther_ops.core.robot.files import CONTAINER_CONFIG_DIR
from panther_ops.core.robot.launch_args import check_args
from panther_ops.core.robot.robot_config import ComposeRead, RobotConfig, parse_config
from panther_ops.core.stack import Family, parse_image
from panther_ops.errors import OpsError, RemoteStateError, UsageError

ENGINE = "engine"
"""Fact: why the robot's docker engine cannot be asked (None: it can)."""
IMAGE = "image"
"""Fact: whether the robot's engine holds an image (None: no engine to ask)."""
_PATH_ARG = re.compile(r"(_config_path|_file|_path)$")


def compose_argv(cfg: RobotConfig) -> list[str] | None:
    try:
        return list(cfg.compose.command().argv)
    except OpsError:
        return None


DEFAULT_SERVICE = {Family.PANTHER_ROS: "panther_ros", Family.HUSARION_UGV: "husarion_ugv_ros"}


def plan_restart(raw: ComposeRead, reads: Reads) -> RobotPlan:
    """`driver restart`: what will be recreated (from compose.yaml only)."""
    cfg = parse_config(raw, reads.stack)
    words = tuple(f"{k}:={v}" for k, v in cfg.compose.args.items()) if compose_argv(cfg) else ()
    plan = RobotPlan(reads.robot, f"recreate {cfg.service} ({cfg.compose.driver_image})", [], (cfg.service,),
                     cfg.compose_path, [Verify(cfg.service, words)])
    plan.data.update(action="recreate", service=cfg.service, image=cfg.compose.driver_image)
    return plan


def plan_run_state(raw: ComposeRead, reads: Reads, action: str) -> RobotPlan:
    """`driver stop` / `driver start` (``action``): the driver's service from compose.yaml.

    Stop is ``docker compose stop`` (the container is kept, so ``start`` brings the same one
    back; ``restart: always`` starts it again when the robot boots, as Husarion's compose
    files ask); start is ``docker compose start`` (no recreate: a change written with
    ``--no-restart`` stays pending until `driver restart`)."""
    cfg = parse_config(raw, reads.stack)
    plan = RobotPlan(reads.robot, f"{action} {cfg.service} ({cfg.compose.driver_image})", [], (), cfg.compose_path,
                     [Verify(cfg.service)] if action == "start" else [])
    plan.data.update(action=action, service=cfg.service, image=cfg.compose.driver_image)
    return plan


def _under(path: str, root: str) -> bool:
    root = root.rstrip("/")
    return path == root or path.startswith(root + "/")


def _check_tree(tree: str, cfg: RobotConfig) -> None:
    """The config tree is replaced wholesale on a failed reset: it must be a directory of its own."""
    tree = posixpath.normpath(tree)
    protected = (cfg.compose_path, posixpath.join(cfg.home, ".panther-ops"), posixpath.join(cfg.home, ".ssh"))
    if not _under(tree, cfg.home) or tree == posixpath.normpath(cfg.home) or any(_under(p, tree) for p in protected):
        raise RemoteStateError(
            f"the config tree mounted at /config is {tree}: not a directory of its own under {cfg.home}; "
            "refusing to reset it", hint="mount ~/config at /config, as husarion_ugv_ros does")


def plan_restore_defaults(raw: ComposeRead, reads: Reads, *, hard: bool = False) -> RobotPlan:
    """`config restore-defaults`: the 2.2 config tree reset, or (2.0/2.1) panther-ops' mounts removed."""
    cfg = parse_config(raw, reads.stack)
    config_dir = posixpath.join(cfg.home, "config")
    if cfg.stack.has_config_tree:
        tree = cfg.host_path_of(CONTAINER_CONFIG_DIR) or config_dir
        _check_tree(tree, cfg)
        image = cfg.compose.driver_image
        warnings: list[str] = []
        if not cfg.tree_mounted:
            warnings.append(f"{tree} is not mounted at /config in compose.yaml: the driver does not read it")
        no_engine = reads.fact(ENGINE)
        if no_engine is not None:
            warnings.append(f"{no_engine}: update_config_directory cannot run here (it would be skipped)")
        mounts = [f"{cfg.resolve(v.source)}:{v.target}:ro" for v in cfg.compose.list_volumes(cfg.service)
                  if v.source and v.target.startswith("/run/husarion/") and v.target.endswith(".env")]
        summary = (f"back up {tree} and run update_config_directory from {image}"
                   + (" after removing everything but common/ (--hard)" if hard else ""))
        plan = RobotPlan(reads.robot, summary, [], (cfg.service,), cfg.compose_path, [Verify(cfg.service)],
                         None, warnings)
        plan.data.update(action="update_config_directory", image=image, config_dir=tree, env_mounts=mounts,
                         hard=hard, stack=cfg.stack.label())
        return plan
    service = cfg.service
    removed = [v for v in cfg.compose.list_volumes(service)
               if v.source and v.source.startswith(("/", "~", ".")) and _under(cfg.resolve(v.source), config_dir)]
    args = cfg.compose.args
    drop = [k for k, v in args.items() if _PATH_ARG.search(k)
            and (_under(v, CONTAINER_CONFIG_DIR) or any(_under(v, vol.target) for vol in removed))]
    warnings = []
    if args.get("wheel_type") == "custom" and {"controller_config_path", "wheel_config_path"} & set(drop):
        drop.append("wheel_type")
        from panther_ops.core.robot.robot_model import default_wheel_type

        warnings.append("wheel_type:=custom needs the controller/wheel files being removed: wheel_type is unset too "
                        f"(the stack's default for this robot, {default_wheel_type(reads, cfg)}, applies; set yours "
                        "with panther-ops config set wheel_type)")
    for v in sorted(removed, key=lambda v: -v.index):
        cfg.compose.remove_volume(v.target, service)
    for k in drop:
        cfg.compose.unset_arg(k, service)
    lacks = tuple(f"{k}:={args[k]}" for k in drop)
    parts = [f"unmount {v.target}" for v in removed] + [f"unset {k}" for k in drop]
    summary = "; ".join(parts) + (f" (files stay in {config_dir})" if removed else "")
    plan = compose_plan(reads.robot, cfg, summary, warnings, [Verify(service, (), lacks)],
                        f"nothing panther-ops added: no mounts from {config_dir}, no arguments into /config")
    plan.data["removed_mounts"] = [v.spec() for v in removed]
    plan.data["unset_args"] = drop
    return plan


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


def plan_update(raw: ComposeRead, reads: Reads, target: TargetImage | None, *, desired_image: Any = None,
                force: bool = False, pull: bool = False) -> RobotPlan:
    """`driver update`: the driver image in compose.yaml (``target`` None: the inventory's desired image)."""
    cfg = parse_config(raw, reads.stack)
    if target is None:
        wanted = desired_image
        if not wanted:
            return compose_plan(reads.robot, cfg, "no change", [], [],
                                "no TAG given and no desired image in the inventory")
        target = parse_target(str(wanted), force=force)
    current = cfg.compose.driver_image
    new_ref = target.ref_for(current)
    warnings = list(target.warnings)
    old_stack = cfg.stack
    new_stack = parse_image(f"{repo_for(target.version)}:{target.tag}")
    if new_ref == current:
        plan = compose_plan(reads.robot, cfg, "no change", warnings, [], f"compose.yaml already has {current}")
        plan.data.update(image_from=current, image_to=new_ref)
        return plan
    running = _image_stack(cfg.compose) or old_stack  # the image, not an inventory pin, tells the files' schema
    if (running.version >= (2, 3, 0)) != (new_stack.version >= (2, 3, 0)):
        cfg.stack = running  # Humble <-> Jazzy: a migration, or its way back (migrate/plan.py)
        return _migration(cfg, reads, new_ref, new_stack, warnings, pull)
    if running.version >= (2, 3, 0) and (running.version >= (2, 3, 2)) != (new_stack.version >= (2, 3, 2)):
        warnings.append(f"{running.version_str} -> {new_stack.version_str}: 2.3.2 brought the twist mux, the IMU "
                        "covariance placeholder and the gamepad file in husarion_ugv_teleop; the files in ~/config are "
                        "not translated between 2.3 releases (check them, or `config restore-defaults` after)")
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
    if reads.stack != "auto":
        warnings.append(f"the inventory pins stack: {reads.stack} for this robot: change it to "
                        f"{new_stack.version_str} (or auto) with the update")
    warnings += _device_notes(cfg.compose.service(service).get("devices") or [], new_stack.version)
    present = reads.fact(IMAGE, new_ref)
    if present is False:
        warnings.append(f"{new_ref} is not on the robot: it needs a pull (internet on the robot); "
                        + ("--pull runs" if not pull else "--pull given: runs") + " docker compose pull first")
    parts = [f"image {current} -> {new_ref}"]
    if renamed_from:
        parts.append(f"service {renamed_from} -> {service}")
    parts += [f"{o} -> {n}" for o, n in migration.renamed.items()] + [f"drop {d}" for d in migration.dropped]
    words = tuple(f"{k}:={v}" for k, v in cfg.compose.args.items())
    plan = compose_plan(reads.robot, cfg, "; ".join(parts), warnings, [Verify(service, words)], "no change")
    plan.data.update(image_from=current, image_to=new_ref, image_local=present, pull=pull,
                     stack_from=old_stack.label(), stack_to=new_stack.label())
    if renamed_from:
        plan.data["service_from"] = renamed_from
    return plan


def _image_stack(compose: ComposeFile) -> Any:
    """The stack compose.yaml's driver image names (None: not a driver image panther-ops reads)."""
    try:
        return compose.stack()
    except OpsError:
        return None


def _migration(cfg: RobotConfig, reads: Reads, new_ref: str, new_stack: Any, warnings: list[str],
               pull: bool) -> RobotPlan:
    from panther_ops.core.driver.migrate.plan import plan_migration, plan_way_back

    old_stack = cfg.stack
    if reads.stack != "auto":
        warnings.append(f"the inventory pins stack: {reads.stack} for this robot: change it to "
                        f"{new_stack.version_str} (or auto) with the update")
    present = reads.fact(IMAGE, new_ref)
    if present is False:
        warnings.append(f"{new_ref} is not on the robot: it needs a pull (internet on the robot); "
                        + ("--pull runs" if not pull else "--pull given: runs") + " docker compose pull first")
    if new_stack.version >= (2, 3, 0):
        plan = plan_migration(cfg, reads, new_ref, new_stack, warnings)
    else:
        plan = plan_way_back(cfg, reads, new_ref, new_stack, warnings)
    plan.data.update(image_from=old_stack.image, image_to=new_ref, image_local=present, pull=pull,
                     stack_from=old_stack.label(), stack_to=new_stack.label())
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
