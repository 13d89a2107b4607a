"""The file of a kind in use on a robot (`config pull`, and the file `shutdown hosts` and
`apply` start from). Its inverse, `config push` (`push.py`), is the manual's four-step
"Modification of configuration files" procedure as one command.

push: upload the file under ``/home/husarion/config/<package>/...`` (the 2.2 layout, used on
every version), mount it into the driver container and point the launch argument at it
(2.0/2.1); on 2.2, whose ``~/config`` tree is mounted at ``/config`` and read through
``common_dir_path``, overwrite the tree's file where the stack reads that file from the tree
(`ArgSpec.tree_since`: not the wheel file, nor 2.2.0's animations, which come from the image),
else set the argument to the pushed file. A BT project brings the XML files its ``.btproj`` includes; a user
animations file brings the images it references.

pull: the file in use: the mounted one, else the 2.2 tree's (where the stack reads it from the
tree), else the default inside the robot's own image, else panther-ops' template for that
version, said as such: the upstream file the template is written from (its ``Source:``), or
that it is panther-ops' own.
"""

from __future__ import annotations

import posixpath
from collections.abc import Callable
from typing import TYPE_CHECKING

from panther_ops.core.fleet.reading import read_and_plan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.services import running_containers
from panther_ops.core.kinds import FileKind
from panther_ops.core.robot.files import (
    ROBOT_CONFIG_DIR,
    ConfigFile,
    config_file,
    family_dirs,
    stock_bt_project,
    template_source,
)
from panther_ops.core.robot.gamepad import InImage
from panther_ops.core.robot.launch_args import spec
from panther_ops.core.robot.push import BT_ARGS, robot_file
from panther_ops.core.robot.read import read_config
from panther_ops.core.robot.robot_config import RobotConfig
from panther_ops.core.stack import Family, Stack
from panther_ops.errors import UsageError

if TYPE_CHECKING:
    from panther_ops.core.robot.bt_pull import Includes

def _read(ctx: RobotContext, path: str) -> bytes | None:
    try:
        return ctx.transport.read_file(path)
    except FileNotFoundError:
        return None


def _upstream(stack: Stack, package: str, rel: str) -> str:
    repo = "husarion_ugv_ros" if stack.family is Family.HUSARION_UGV else "panther_ros"
    return f"{repo}@{stack.version_str}:{package}/{rel}"


def _template_note(stack: Stack, text: str, why: str, upstream: str) -> str:
    """Where a template pulled in place of the robot's file comes from, said plainly."""
    source = template_source(text)
    traced = f"written from {source}" if source else "not traced to an upstream file"
    return (f"panther-ops' template for {stack.label()}, {traced}: the image's file is {upstream}, which could "
            f"not be read ({why})")


Reader = Callable[[str], bytes | None]
"""A file of a pulled BT project by its name relative to the project's directory (None: not there)."""


def _bt_pull(ctx: RobotContext, cfg: RobotConfig, kind: FileKind) -> tuple[bytes, str, Reader]:
    """The BT project in use, where it came from, and how to read the files it includes from
    that same place (`bt_pull`)."""
    arg = BT_ARGS[kind]
    current = cfg.compose.args.get(arg)
    host = cfg.host_path_of(current) if current else None
    if current and host and (data := _read(ctx, host)) is not None:
        inside = posixpath.dirname(current)  # an include resolves in the container, beside the project

        def mounted(rel: str) -> bytes | None:
            path = posixpath.join(inside, rel)
            where = cfg.host_path_of(path)
            if where is not None:
                return _read(ctx, where)
            got = _container_read(ctx, cfg, cfg.service, path)
            return got[0] if got else None

        return data, f"{host} (mounted, {arg})", mounted
    package, name = stock_bt_project(cfg.stack, "Lights" if kind is FileKind.BT_LIGHTS else "Safety")
    if kind is FileKind.BT_LIGHTS and cfg.tree_mounted:  # 2.2 reads the Lights project from common_dir_path
        tree_dir = f"{ROBOT_CONFIG_DIR}/{package}/behavior_trees"
        if (in_tree := _read(ctx, f"{tree_dir}/{name}")) is not None:
            return in_tree, f"{tree_dir}/{name} (config tree)", lambda rel: _read(ctx, posixpath.join(tree_dir, rel))
    from_image = _from_image(ctx, cfg, package, name, "behavior_trees")
    if from_image is not None:

        def in_image(rel: str) -> bytes | None:
            got = _from_image(ctx, cfg, package, rel, "behavior_trees")
            return got[0] if got else None

        return *from_image, in_image
    upstream = _upstream(cfg.stack, package, f"behavior_trees/{name}")
    why = ("a demo robot has no image" if ctx.robot.transport == "local"
           else "the driver container could not be read")
    from panther_ops.core.fleet.templates import template_path

    def template(rel: str) -> bytes | None:  # the release's stock files (docs/conformance.md: equal)
        for directory in family_dirs(cfg.stack):  # the version's overlay first
            path = template_path("config", directory, package, "behavior_trees", *rel.split("/"))
            if path.is_file():
                return path.read_bytes()
        return None

    if (stock := template(name)) is not None:
        return stock, _template_note(cfg.stack, stock.decode(), why, upstream), template
    raise UsageError(f"{ctx.robot.name}: {upstream} could not be read ({why}) and panther-ops has no template "
                     f"of it for {cfg.stack.label()}")


def pull_project(ctx: RobotContext, kind: FileKind) -> tuple[bytes, str, Includes]:
    """A BT project in use on the robot (as :func:`pull`), and every file it includes, read
    from the same place as the project."""
    from panther_ops.core.robot.bt_pull import pulled_includes

    data, source, read = _bt_pull(ctx, read_config(ctx), kind)
    return data, source, pulled_includes(data, read)


def pull(ctx: RobotContext, kind: FileKind) -> tuple[bytes, str]:
    """The file of ``kind`` in use on the robot, and where it came from."""
    cfg = read_config(ctx)
    if kind is FileKind.JOY2TWIST:
        from panther_ops.core.robot.gamepad import pull_joy2twist, robot_model

        found = read_and_plan(ctx, lambda reads: pull_joy2twist(reads, cfg))
        if isinstance(found, tuple):
            return found
        if isinstance(found, InImage):
            return _joy2twist_from_image(ctx, cfg, found)
        gamepad = read_and_plan(ctx, lambda reads: config_file(cfg.stack, FileKind.JOY2TWIST,
                                                               robot_model=robot_model(reads, cfg)))
        return _image_or_template(ctx, cfg, gamepad)
    if kind in BT_ARGS:
        project, source, _ = _bt_pull(ctx, cfg, kind)
        return project, source
    cf = read_and_plan(ctx, lambda reads: robot_file(reads, cfg, kind))  # of its wheel type and model
    if cf.launch_arg:
        name = spec(cf.launch_arg).name_for(cfg.stack)
        current = cfg.compose.args.get(name)
        if current:
            host = cfg.host_path_of(current)
            if host and (data := _read(ctx, host)) is not None:
                return data, f"{host} (mounted, {name}:={current})"
    if cfg.reads_from_tree(cf) and (data := _read(ctx, cf.robot_path)) is not None:
        return data, f"{cf.robot_path} (config tree)"
    return _image_or_template(ctx, cfg, cf)


def _image_or_template(ctx: RobotContext, cfg: RobotConfig, cf: ConfigFile) -> tuple[bytes, str]:
    """``cf`` inside the robot's image, else panther-ops' template of it, said as such."""
    from_image = _from_image(ctx, cfg, cf.package, cf.filename)
    if from_image is not None:
        return from_image
    why = ("a demo robot has no image" if ctx.robot.transport == "local"
           else "the driver container could not be read")
    text = cf.template_text()
    upstream = _upstream(cfg.stack, cf.package, f"config/{cf.filename}")
    return text.encode(), _template_note(cfg.stack, text, why, upstream)


def _from_image(ctx: RobotContext, cfg: RobotConfig, package: str, filename: str,
                subdir: str = "config") -> tuple[bytes, str] | None:
    """The default file inside the running driver container (docker SDK on the same connection)."""
    return _container_read(ctx, cfg, cfg.service, f"/ros2_ws/install/{package}/share/{package}/{subdir}/{filename}")


def _container_read(ctx: RobotContext, cfg: RobotConfig, service: str, path: str) -> tuple[bytes, str] | None:
    """A file inside ``service``'s running container (docker SDK on the same connection), its
    symlinks followed (a ``colcon build --symlink-install`` image links ``install/<pkg>/share``
    to ``src``); None when it cannot be read."""
    import io
    import tarfile

    client = ctx.transport.docker()
    if client is None:
        return None
    try:
        containers = running_containers(client, service, posixpath.dirname(cfg.compose_path))
        if not containers:
            return None
        at = path
        for _ in range(8):  # a link to a link...: a loop ends here
            stream, _ = containers[0].get_archive(at)
            with tarfile.open(fileobj=io.BytesIO(b"".join(stream))) as tar:
                member = tar.next()
                if member is not None and member.issym():
                    at = posixpath.normpath(posixpath.join(posixpath.dirname(at), member.linkname))
                    continue
                fh = tar.extractfile(member) if member is not None and member.isfile() else None
                if fh is None:
                    return None
                shown = path if at == path else f"{path} (-> {at})"
                return fh.read(), f"{shown} in {containers[0].name} (the image's default)"
        return None
    except Exception:  # docker.errors.NotFound and friends: the caller falls back
        return None


def _joy2twist_from_image(ctx: RobotContext, cfg: RobotConfig, found: InImage) -> tuple[bytes, str]:
    """The gamepad's parameters in its image (panther_ros 2.0-2.1: husarion/joy2twist), else
    panther-ops' template of husarion/joy2twist's joy2twist_panther.yaml, saying so."""
    from panther_ops.core.fleet.templates import read_template
    from panther_ops.core.robot.gamepad import TEMPLATE_SOURCE

    got = _container_read(ctx, cfg, found.service, found.path)
    if got is not None:
        return got
    why = ("a demo robot has no image" if ctx.robot.transport == "local"
           else f"the {found.service} container could not be read")
    if posixpath.basename(found.path) != posixpath.basename(TEMPLATE_SOURCE):
        raise UsageError(f"{found.service} uses {found.path} of its image ({found.arg}), which could not be read "
                         f"({why})", hint="panther-ops' template is joy2twist_panther.yaml only")
    return read_template("joy2twist", "joy2twist_panther.yaml").encode(), (
        f"panther-ops' template, written from {TEMPLATE_SOURCE}: the image's file is {found.path} in "
        f"{found.service} ({found.arg}), which could not be read ({why})")
