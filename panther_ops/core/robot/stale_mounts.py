"""Mounts a launch-argument change leaves unused: removed in the same plan and diff.

`config push` mounts a file into the driver and points a launch argument at it; a later change
that points the argument elsewhere or drops it (``config set wheel_type WHxx`` migrating the
controller file, ``config unset controller_config_path``, a push of a file under another name)
would leave that mount in compose.yaml, still pulling the old file into the container. A mount is
removed only where panther-ops can show it is unused: it mounted exactly the file an argument of
the driver named before the change, no argument names it (or a path inside it) after, and
nothing else in compose.yaml mentions its container path or its host path (another service's
volume, a script, the environment). The file itself stays on the robot.
"""

from __future__ import annotations

import posixpath
from collections.abc import Mapping

from panther_ops.core.kinds.arg_catalogue import ArgType
from panther_ops.core.robot.compose import ComposeFile
from panther_ops.core.robot.robot_config import RobotConfig
from panther_ops.errors import UsageError


def _file_arg(name: str) -> bool:
    from panther_ops.core.robot.launch_args import spec

    try:
        return spec(name).type is ArgType.PATH
    except UsageError:
        return False


def drop_unused_mounts(cfg: RobotConfig, before: Mapping[str, str]) -> list[str]:
    """Remove (in ``cfg.compose``) the driver's mounts of files that the arguments ``before``
    named and the current ones do not; what was removed, one line each."""
    now = [posixpath.normpath(v) for v in cfg.compose.args.values() if v.startswith("/")]
    removed: list[str] = []
    for name, old in before.items():
        if not old.startswith("/") or cfg.compose.args.get(name) == old or not _file_arg(name):
            continue
        target = posixpath.normpath(old)
        if any(v == target or v.startswith(target + "/") for v in now):
            continue
        volume = next((v for v in cfg.compose.list_volumes(cfg.service)
                       if posixpath.normpath(v.target) == target and v.source
                       and v.source.startswith(("/", "~", "."))), None)
        if volume is None or volume.source is None:
            continue
        trial = ComposeFile.parse(cfg.compose.text(), cfg.compose.path)
        if not trial.remove_volume(volume.target, cfg.service):
            continue
        rest = trial.text()
        if volume.target in rest or volume.source in rest or cfg.resolve(volume.source) in rest:
            continue  # mentioned elsewhere: not shown to be unused
        if cfg.compose.remove_volume(volume.target, cfg.service):
            removed.append(f"unmounted {volume.source}:{volume.target} ({name} no longer reads it; "
                           f"the file stays on the robot)")
    return removed
