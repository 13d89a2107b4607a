"""`config push` / `config pull`: the manual's four-step "Modification of configuration
files" procedure as one command, and its inverse.

push: upload the file under ``/home/husarion/config/<package>/...`` (the 2.2 layout, used on
every version), mount it into the driver container and point the launch argument at it
(2.0/2.1); on 2.2, whose ``~/config`` tree is mounted at ``/config`` and read through
``common_dir_path``, overwrite the tree's file (or, where the tree has no such file, set the
argument to it). A BT project brings the XML files its ``.btproj`` includes; a user
animations file brings the images it references.

pull: the file in use: the mounted one, else the 2.2 tree's, else the default inside the
robot's own image, else panther-ops' template for that version.
"""

from __future__ import annotations

import posixpath
import re
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path
from typing import Any

from panther_ops.core.config_files import CONTAINER_CONFIG_DIR, ROBOT_CONFIG_DIR, ConfigKind, config_file
from panther_ops.core.config_plans import compose_plan, edit_args
from panther_ops.core.controller import ControllerConfig
from panther_ops.core.launch_args import spec
from panther_ops.core.pipeline import FileEdit, RobotPlan
from panther_ops.core.robot_config import RobotConfig, read_config
from panther_ops.core.runner import RobotContext
from panther_ops.errors import InputError, UsageError


class PushKind(str, Enum):
    CONTROLLER = "controller"
    WHEEL = "wheel"
    COMPONENTS = "components"
    LED = "led"
    USER_ANIMATIONS = "user-animations"
    BT_LIGHTS = "bt-lights"
    BT_SAFETY = "bt-safety"
    SHUTDOWN_HOSTS = "shutdown-hosts"
    BATTERY = "battery"


_KINDS = {
    PushKind.CONTROLLER: ConfigKind.CONTROLLER,
    PushKind.WHEEL: ConfigKind.WHEEL,
    PushKind.COMPONENTS: ConfigKind.COMPONENTS,
    PushKind.LED: ConfigKind.ANIMATIONS,
    PushKind.USER_ANIMATIONS: ConfigKind.USER_ANIMATIONS,
    PushKind.SHUTDOWN_HOSTS: ConfigKind.SHUTDOWN_HOSTS,
    PushKind.BATTERY: ConfigKind.BATTERY_PLUGIN,
}
_BT_ARGS = {PushKind.BT_LIGHTS: "lights_bt_project_path", PushKind.BT_SAFETY: "safety_bt_project_path"}


@dataclass
class Bundle:
    """The local files of a push: the main file and what it brings along."""

    main: Path
    data: bytes
    extra: dict[str, bytes] = field(default_factory=dict)
    """name (relative to the main file's robot directory) -> content"""


def read_bundle(kind: PushKind, path: Path) -> Bundle:
    """Read and check the local files before any robot is contacted (bad input: exit 2)."""
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror}", path=str(path)) from None
    bundle = Bundle(path, data)
    if kind in _BT_ARGS:
        _bt_bundle(bundle)
        return bundle
    import yaml

    try:
        doc = yaml.safe_load(data)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        raise InputError(f"not valid YAML: {getattr(exc, 'problem', exc)}", path=str(path),
                         line=mark.line + 1 if mark else None) from None
    if not isinstance(doc, dict):
        raise InputError("must be a YAML mapping", path=str(path))
    if kind is PushKind.USER_ANIMATIONS:
        _animation_images(bundle, doc)
    if kind is PushKind.COMPONENTS:  # the one validator of components files (also `sim gps add`)
        from panther_ops.core.sim.components import validate_components

        validate_components(doc, str(path))
    if kind is PushKind.BATTERY:  # the one validator of battery plugin files (also `sim battery check`)
        from panther_ops.core.sim.battery import validate_battery

        validate_battery(doc, str(path))
    return bundle


def _bt_bundle(bundle: Bundle) -> None:
    import xml.etree.ElementTree as ET

    if bundle.main.suffix != ".btproj":
        raise InputError("a BT project is pushed by its .btproj file", path=str(bundle.main))
    try:
        root = ET.fromstring(bundle.data)  # noqa: S314
    except ET.ParseError as exc:
        raise InputError(f"not valid XML: {exc}", path=str(bundle.main)) from None
    for inc in root.iter("include"):
        rel = inc.get("path")
        if not rel:
            continue
        src = (bundle.main.parent / rel).resolve()
        if not src.is_file():
            raise InputError(f"includes {rel}, which does not exist", path=str(bundle.main))
        bundle.extra[rel] = src.read_bytes()


_IMAGE = re.compile(r"^(\s*image:\s*)(['\"]?)([^'\"\n#]+?)\2(\s*(#.*)?)$", re.MULTILINE)


def _animation_images(bundle: Bundle, doc: dict[str, Any]) -> None:
    """Collect local images the animations reference; their paths are rewritten on push."""
    for m in _IMAGE.finditer(bundle.data.decode()):
        ref = m.group(3).strip()
        if ref.startswith("$(find"):
            continue
        src = Path(ref) if ref.startswith("/") else bundle.main.parent / ref
        if src.is_file():
            bundle.extra[f"animations/{src.name}"] = src.read_bytes()
        elif not ref.startswith("/"):
            raise InputError(f"image {ref} not found next to the file", path=str(bundle.main))


def _rewrite_images(text: str, target_dir: str) -> str:
    def sub(m: re.Match[str]) -> str:
        ref = m.group(3).strip()
        if ref.startswith("$(find"):
            return m.group(0)
        return f"{m.group(1)}{m.group(2)}{target_dir}/animations/{posixpath.basename(ref)}{m.group(2)}{m.group(4)}"

    return _IMAGE.sub(sub, text)


def _wheel(cfg: RobotConfig) -> str:
    wheel = cfg.compose.args.get("wheel_type", spec("wheel_type").default_for(cfg.stack))
    return "WH01" if wheel == "custom" else wheel


def _read(ctx: RobotContext, path: str) -> bytes | None:
    try:
        return ctx.transport.read_file(path)
    except FileNotFoundError:
        return None


def plan_push(ctx: RobotContext, kind: PushKind, bundle: Bundle, *, force: bool = False) -> RobotPlan:
    cfg = read_config(ctx)
    warnings: list[str] = []
    if kind in _BT_ARGS:
        pkg = f"{cfg.stack.package_prefix}_manager"
        robot_dir = f"{ROBOT_CONFIG_DIR}/{pkg}/behavior_trees"
        container_dir = f"{CONTAINER_CONFIG_DIR}/{pkg}/behavior_trees"
        arg = _BT_ARGS[kind]
        name = bundle.main.name
        main_data = bundle.data
        extra = bundle.extra
    else:
        cf = config_file(cfg.stack, _KINDS[kind], wheel_type=_wheel(cfg))
        arg = cf.launch_arg or ""
        robot_dir, container_dir = posixpath.dirname(cf.robot_path), posixpath.dirname(cf.container_path)
        name = bundle.main.name
        if cfg.tree_mounted and _read(ctx, cf.robot_path) is not None:
            name = cf.filename  # the tree's own file: read through common_dir_path, no argument needed
            arg = ""
        main_data = bundle.data
        extra = {}
        if kind is PushKind.USER_ANIMATIONS and bundle.extra:
            main_data = _rewrite_images(bundle.data.decode(), posixpath.dirname(container_dir)).encode()
            extra = {f"../{k}": v for k, v in bundle.extra.items()}
        if kind is PushKind.CONTROLLER:
            ctrl = ControllerConfig.parse(bundle.data.decode(), cfg.stack, _wheel(cfg), path=str(bundle.main),
                                          force=force)
            problems = ctrl.check()
            over = [p for p in problems if "exceeds" in p]
            if over and not force:
                raise UsageError(f"{bundle.main}: {over[0]}", hint="lower the value, or --force to push it anyway")
            warnings.extend(problems)
    edits: list[FileEdit] = []
    files = {name: main_data, **extra}
    for rel, content in files.items():
        path = posixpath.normpath(posixpath.join(robot_dir, rel))
        before = _read(ctx, path)
        if before != content:
            edits.append(FileEdit(path, before, content))
    main_container = f"{container_dir}/{name}"
    contains: tuple[str, ...] = ()
    if not cfg.tree_mounted:
        mount_src = robot_dir if (extra or kind in _BT_ARGS) else f"{robot_dir}/{name}"
        mount_dst = container_dir if (extra or kind in _BT_ARGS) else main_container
        if kind is PushKind.USER_ANIMATIONS and extra:
            mount_src, mount_dst = posixpath.dirname(robot_dir), posixpath.dirname(container_dir)
        if cfg.host_path_of(mount_dst) != mount_src:
            cfg.compose.add_volume(mount_src, mount_dst, ro=True)
    if arg:
        w, v = edit_args(cfg, {arg: main_container}, [], force)
        warnings += w
        contains = v.cmd_contains
    from panther_ops.core.pipeline import Verify

    summary = f"{kind.value}: {bundle.main.name} -> {robot_dir}/{name}" + (f" ({arg}:={main_container})" if arg else "")
    plan = compose_plan(ctx, cfg, summary, warnings, [Verify(cfg.service, contains)],
                         f"{robot_dir}/{name} already has this content", extra=edits)
    plan.data["robot_path"] = f"{robot_dir}/{name}"
    return plan


def pull(ctx: RobotContext, kind: PushKind) -> tuple[bytes, str]:
    """The file of ``kind`` in use on the robot, and where it came from."""
    cfg = read_config(ctx)
    if kind in _BT_ARGS:
        arg = _BT_ARGS[kind]
        current = cfg.compose.args.get(arg)
        host = cfg.host_path_of(current) if current else None
        if host and (data := _read(ctx, host)) is not None:
            return data, f"{host} (mounted, {arg})"
        raise UsageError(f"{kind.value}: no custom project mounted on {ctx.robot.name}; the image's default is used",
                         hint="BT projects ship with panther-ops: templates/behavior_trees/")
    cf = config_file(cfg.stack, _KINDS[kind], wheel_type=_wheel(cfg))
    if cf.launch_arg:
        name = spec(cf.launch_arg).name_for(cfg.stack)
        current = cfg.compose.args.get(name)
        if current:
            host = cfg.host_path_of(current)
            if host and (data := _read(ctx, host)) is not None:
                return data, f"{host} (mounted, {name}:={current})"
    if cfg.tree_mounted and (data := _read(ctx, cf.robot_path)) is not None:
        return data, f"{cf.robot_path} (config tree)"
    from_image = _from_image(ctx, cfg, cf.package, cf.filename)
    if from_image is not None:
        return from_image
    return cf.template_text().encode(), f"panther-ops template for {cfg.stack.label()} (not found in the image)"


def _from_image(ctx: RobotContext, cfg: RobotConfig, package: str, filename: str) -> tuple[bytes, str] | None:
    """The default file inside the running driver container (docker SDK on the same connection)."""
    import io
    import tarfile

    client = ctx.transport.docker()
    if client is None:
        return None
    path = f"/ros2_ws/install/{package}/share/{package}/config/{filename}"
    try:
        containers = client.containers.list(filters={"label": f"com.docker.compose.service={cfg.service}"})
        if not containers:
            return None
        stream, _ = containers[0].get_archive(path)
        buf = io.BytesIO(b"".join(stream))
        with tarfile.open(fileobj=buf) as tar:
            member = tar.next()
            fh = tar.extractfile(member) if member else None
            if fh is None:
                return None
            return fh.read(), f"{path} in {containers[0].name} (the image's default)"
    except Exception:  # docker.errors.NotFound and friends: fall back to the template
        return None
