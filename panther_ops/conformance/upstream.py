"""An upstream release: a tag of a local git mirror, read with ``git`` (no work tree needed).

`GitRelease` is the only part of the conformance tool that touches anything outside the
process (``git -C DIR ls-tree/show/archive``, read only). `classify` says which upstream
files are default files of a panther-ops kind (the registry's `FileKind`) and for which
robot (wheel type, robot model) they are meant.
"""

from __future__ import annotations

import io
import re
import subprocess
import tarfile
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path, PurePosixPath

from panther_ops.core.kinds import FileKind


class UpstreamError(RuntimeError):
    """The mirror or the tag cannot be read."""


@dataclass(frozen=True)
class GitRelease:
    """One tag of a bare (or normal) git repository on this machine."""

    git_dir: Path
    tag: str

    def _git(self, *args: str) -> bytes:
        try:
            done = subprocess.run(["git", "-C", str(self.git_dir), *args],
                                  capture_output=True, check=False, timeout=300)
        except (OSError, subprocess.TimeoutExpired) as exc:
            raise UpstreamError(f"git {' '.join(args)} in {self.git_dir}: {exc}") from None
        if done.returncode != 0:
            raise UpstreamError(f"git {' '.join(args)} in {self.git_dir}: "
                                f"{done.stderr.decode(errors='replace').strip()}")
        return done.stdout

    @cached_property
    def commit(self) -> str:
        return self._git("rev-parse", "--verify", f"{self.tag}^{{commit}}").decode().strip()

    @cached_property
    def paths(self) -> tuple[str, ...]:
        return tuple(self._git("ls-tree", "-r", "--name-only", "-z", self.commit).decode().split("\0")[:-1])

    def read(self, path: str) -> bytes:
        return self._git("show", f"{self.commit}:{path}")

    def extract(self, prefixes: list[str], dest: Path) -> None:
        """Write the files under ``prefixes`` (directories of the release) below ``dest``."""
        if not prefixes:
            return
        data = self._git("archive", "--format=tar", self.commit, "--", *prefixes)
        with tarfile.open(fileobj=io.BytesIO(data)) as tar:
            for member in tar.getmembers():
                if not member.isfile():
                    continue
                target = dest / PurePosixPath(member.name)
                if ".." in PurePosixPath(member.name).parts:
                    continue
                handle = tar.extractfile(member)
                if handle is not None:
                    target.parent.mkdir(parents=True, exist_ok=True)
                    target.write_bytes(handle.read())

    def repo_name(self) -> str:
        """``owner/name`` from a mirror laid out as ``.../owner+name/repo`` (else the directory name)."""
        for part in reversed(self.git_dir.resolve().parts):
            if "+" in part:
                owner, _, name = part.partition("+")
                return f"{owner}/{name}"
        return self.git_dir.resolve().name


_PACKAGE_NAME = re.compile(rb"<name>\s*([A-Za-z0-9_]+)\s*</name>")


def packages(paths: tuple[str, ...], read: Callable[[str], bytes]) -> dict[str, str]:
    """ROS package name -> its directory, from every ``package.xml`` of the release."""
    out: dict[str, str] = {}
    for path in paths:
        if PurePosixPath(path).name == "package.xml":
            m = _PACKAGE_NAME.search(read(path))
            if m:
                out[m.group(1).decode()] = str(PurePosixPath(path).parent)
    return out


@dataclass(frozen=True)
class Classified:
    """An upstream default file of a panther-ops kind, and the robot it is meant for."""

    kind: FileKind
    wheel_type: str | None = None
    robot_model: str = "panther"


_PREFIX = r"(?:panther|husarion_ugv)"
_RULES: tuple[tuple[re.Pattern[str], FileKind], ...] = tuple((re.compile(p), k) for p, k in (
    (rf"^{_PREFIX}_controller/config/(?P<wheel>WH\d\d)_controller\.yaml$", FileKind.CONTROLLER),
    (rf"^{_PREFIX}_description/config/(?P<wheel>WH\d\d)\.yaml$", FileKind.WHEEL),
    (rf"^{_PREFIX}_description/config/components\.yaml$", FileKind.COMPONENTS),
    (r"^panther_lights/config/led_config\.yaml$", FileKind.LED),
    (r"^husarion_ugv_lights/config/(?P<model>panther|lynx)_animations\.yaml$", FileKind.LED),
    (rf"^{_PREFIX}_lights/config/user_animations\.yaml$", FileKind.USER_ANIMATIONS),
    (rf"^{_PREFIX}_manager/behavior_trees/(?:Panther)?LightsBT\.btproj$", FileKind.BT_LIGHTS),
    (rf"^{_PREFIX}_manager/behavior_trees/(?:Panther)?SafetyBT\.btproj$", FileKind.BT_SAFETY),
    (r"^panther_bringup/config/shutdown_hosts\.yaml$", FileKind.SHUTDOWN_HOSTS),
    (r"^panther_manager/config/shutdown_hosts_config\.yaml$", FileKind.SHUTDOWN_HOSTS),
    (r"^husarion_ugv_manager/config/shutdown_hosts\.yaml$", FileKind.SHUTDOWN_HOSTS),
    (r"^panther_gazebo/config/battery_plugin_config\.yaml$", FileKind.BATTERY),
    (r"^husarion_ugv_gazebo/config/battery_plugin\.yaml$", FileKind.BATTERY),
    (r"^husarion_ugv_bringup/config/joy2twist_(?P<model>panther|lynx)\.yaml$", FileKind.JOY2TWIST),
    (r"^husarion_ugv_teleop/config/joy2twist_(?P<model>panther|lynx)\.yaml$", FileKind.JOY2TWIST),  # 2.3.2
))
"""Upstream path -> the kind whose validator must accept it (its `FileKind`, as ``config
push --as``). The robot: the wheel in the file name; a Lynx for ``lynx_*`` files and WH05."""


def classify(path: str) -> Classified | None:
    """The kind of an upstream default file, or None (not a file panther-ops writes)."""
    for pattern, kind in _RULES:
        m = pattern.match(path)
        if m:
            groups = m.groupdict()
            wheel = groups.get("wheel")
            model = groups.get("model") or ("lynx" if wheel == "WH05" else "panther")
            return Classified(kind, wheel, model)
    return None


_COPY = re.compile(r"^\s*copy_package_file\s+(\S+)\s+(\S+)\s*$")
_RM = re.compile(r"^\s*rm\s+(?:-\S+\s+)*/config/(\S+)")


def config_tree(script: str, paths: tuple[str, ...], pkgs: dict[str, str], robot_model: str) -> list[str]:
    """The files ``update_config_directory`` copies into ``/config`` for ``robot_model``.

    Each ``copy_package_file PKG PATH`` copies ``share/PKG/PATH`` (a file, or a directory
    with everything in it) to ``/config/PKG/PATH``; ``rm /config/...`` lines remove one.
    Returned as ``PKG/PATH`` under ``/config``, sorted.
    """
    out: set[str] = set()
    for raw in script.splitlines():
        line = raw.replace("${ROBOT_MODEL_NAME}", robot_model).replace("$ROBOT_MODEL_NAME", robot_model)
        copy = _COPY.match(line)
        if copy:
            package, rel = copy.groups()
            directory = pkgs.get(package)
            if directory is None:
                continue
            source = f"{directory}/{rel}"
            if source in paths:
                out.add(f"{package}/{rel}")
            else:
                out.update(f"{package}/{p[len(directory) + 1:]}" for p in paths if p.startswith(source + "/"))
            continue
        rm = _RM.match(line)
        if rm:
            out.discard(rm.group(1))
    return sorted(out)
