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
from pathlib import Path

from panther_ops.core.config.files import CONTAINER_CONFIG_DIR, ROBOT_CONFIG_DIR, ConfigKind, config_file
from panther_ops.core.config.launch_args import spec
from panther_ops.core.config.plans import compose_plan, edit_args
from panther_ops.core.config.robot import RobotConfig, read_config
from panther_ops.core.fleet.memo import Memo
from panther_ops.core.fleet.plan import FileEdit, RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.kinds import PUSHABLE, FileKind, Target, check_file
from panther_ops.errors import InputError, UsageError

_KINDS = {
    FileKind.CONTROLLER: ConfigKind.CONTROLLER,
    FileKind.WHEEL: ConfigKind.WHEEL,
    FileKind.COMPONENTS: ConfigKind.COMPONENTS,
    FileKind.LED: ConfigKind.ANIMATIONS,
    FileKind.USER_ANIMATIONS: ConfigKind.USER_ANIMATIONS,
    FileKind.SHUTDOWN_HOSTS: ConfigKind.SHUTDOWN_HOSTS,
    FileKind.BATTERY: ConfigKind.BATTERY_PLUGIN,
}
_BT_ARGS = {FileKind.BT_LIGHTS: "lights_bt_project_path", FileKind.BT_SAFETY: "safety_bt_project_path"}
_BT_TEMPLATES = {FileKind.BT_LIGHTS: "PantherLightsBT.btproj", FileKind.BT_SAFETY: "PantherSafetyBT.btproj"}


@dataclass
class Bundle:
    """The local files of a push: the main file and what it brings along."""

    main: Path
    data: bytes
    extra: dict[str, bytes] = field(default_factory=dict)
    """name (relative to the main file's robot directory) -> content"""


_NAME = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.+-]*$")


def push_kind(text: str, option: str = "--as") -> FileKind:
    """The file kind a push or pull names (exit 2 naming what is allowed)."""
    try:
        kind = FileKind(text)
    except ValueError:
        kind = None
    if kind not in PUSHABLE:
        raise UsageError(f"{option} {text!r} is not a config kind",
                         hint="allowed: " + ", ".join(k.value for k in PUSHABLE))
    return kind


def read_bundle(kind: FileKind, path: Path, *, force: bool = False) -> Bundle:
    """Read and check the local files before any robot is contacted (bad input: exit 2).

    The content goes through the kind's one validator (`core.filekinds`) with what needs no
    robot; `plan_push` checks it again against each robot's stack and wheel type.
    """
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror}", path=str(path)) from None
    if not _NAME.match(path.name):
        raise InputError(f"the file name {path.name!r} becomes a path in the driver's command: use letters, "
                         "digits and _ . + - only", path=str(path))
    bundle = Bundle(path, data)
    if kind in _BT_ARGS:
        if path.suffix != ".btproj":
            raise InputError("a BT project is pushed by its .btproj file", path=str(path))
        from panther_ops.core.kinds.bt import project_files

        check_file(kind, str(path), data, local=path, force=force)
        bundle.extra = {rel: src.read_bytes() for rel, src in project_files(path).items()}
        return bundle
    check_file(kind, str(path), data, local=path, force=force)
    if kind is FileKind.USER_ANIMATIONS:
        _animation_images(bundle)
    return bundle


_IMAGE_MAGIC = (b"\x89PNG\r\n\x1a\n", b"\xff\xd8\xff", b"GIF87a", b"GIF89a")
_IMAGE = re.compile(r"^(\s*image:\s*)(['\"]?)([^'\"\n#]+?)\2(\s*(#.*)?)$", re.MULTILINE)


def _animation_images(bundle: Bundle) -> None:
    """Collect local images the animations reference; their paths are rewritten on push."""
    for m in _IMAGE.finditer(bundle.data.decode()):
        ref = m.group(3).strip()
        if ref.startswith("$(find"):
            continue
        src = Path(ref) if ref.startswith("/") else bundle.main.parent / ref
        if src.is_file():
            data = src.read_bytes()
            if not data.startswith(_IMAGE_MAGIC):  # only images travel to the robot, whatever the path names
                raise InputError(f"image {ref} is not a PNG, JPEG or GIF file: not pushed", path=str(bundle.main))
            name = f"animations/{src.name}"
            if bundle.extra.get(name, data) != data:
                raise InputError(f"two different images are named {src.name}: they would land on the same robot "
                                 "path", path=str(bundle.main))
            bundle.extra[name] = data
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


_CHECKED: Memo[list[str]] = Memo()


def plan_push(ctx: RobotContext, kind: FileKind, bundle: Bundle, *, force: bool = False) -> RobotPlan:
    cfg = read_config(ctx)
    target = Target(cfg.stack, _wheel(cfg))
    warnings = list(_CHECKED.get((kind, str(bundle.main), bundle.data, target, force),  # once per stack and wheel
                                 lambda: check_file(kind, str(bundle.main), bundle.data,
                                                    local=bundle.main, target=target, force=force)))
    if kind is FileKind.JOY2TWIST:
        from panther_ops.core.config.gamepad import plan_joy2twist

        return plan_joy2twist(ctx, cfg, bundle.main.name, bundle.data, warnings)
    forced = [w for w in warnings if w.endswith("(forced)")]
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
        if kind in (FileKind.USER_ANIMATIONS, FileKind.LED):  # animation types of this stack
            from panther_ops.core.config.animation_types import for_stack

            text, translated = for_stack(main_data.decode(), cfg.stack)
            main_data = text.encode()
            warnings += [f"{bundle.main.name}: {t} for {cfg.stack.label()}" for t in translated]
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
        before = _read(ctx, path)
        if before != content:
            edits.append(FileEdit(path, before, content))
    main_container = f"{container_dir}/{name}"
    contains: tuple[str, ...] = ()
    if not cfg.tree_mounted:
        mount_src = robot_dir if (extra or kind in _BT_ARGS) else f"{robot_dir}/{name}"
        mount_dst = container_dir if (extra or kind in _BT_ARGS) else main_container
        if kind is FileKind.USER_ANIMATIONS and extra:
            mount_src, mount_dst = posixpath.dirname(robot_dir), posixpath.dirname(container_dir)
        if cfg.host_path_of(mount_dst) != mount_src:
            cfg.compose.add_volume(mount_src, mount_dst, ro=True)
    if arg:
        w, v = edit_args(cfg, {arg: main_container}, [], force)
        warnings += w
        contains = v.cmd_contains
    from panther_ops.core.fleet.plan import Verify

    summary = f"{kind.value}: {bundle.main.name} -> {robot_dir}/{name}" + (f" ({arg}:={main_container})" if arg else "")
    if forced:
        summary += " [--force: " + "; ".join(forced) + "]"
    plan = compose_plan(ctx, cfg, summary, warnings, [Verify(cfg.service, contains)],
                         f"{robot_dir}/{name} already has this content", extra=edits)
    plan.data["robot_path"] = f"{robot_dir}/{name}"
    return plan


def pull(ctx: RobotContext, kind: FileKind) -> tuple[bytes, str]:
    """The file of ``kind`` in use on the robot, and where it came from."""
    cfg = read_config(ctx)
    if kind is FileKind.JOY2TWIST:
        from panther_ops.core.config.gamepad import pull_joy2twist

        return pull_joy2twist(ctx, cfg)
    if kind in _BT_ARGS:
        arg = _BT_ARGS[kind]
        current = cfg.compose.args.get(arg)
        host = cfg.host_path_of(current) if current else None
        if host and (data := _read(ctx, host)) is not None:
            return data, f"{host} (mounted, {arg})"
        from panther_ops.core.fleet.templates import template_file

        project = template_file("behavior_trees", _BT_TEMPLATES[kind])
        return project.read_bytes(), (f"panther-ops' template {_BT_TEMPLATES[kind]} (templates/behavior_trees/): "
                                      f"no custom project is mounted, the robot runs its image's default")
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
    why = ("a demo robot has no image" if ctx.robot.transport == "local"
           else "the driver container could not be read")
    return cf.template_text().encode(), (f"panther-ops' template for {cfg.stack.label()}: the robot uses its "
                                         f"image's default, which this template reproduces ({why})")


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
