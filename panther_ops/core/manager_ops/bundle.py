"""The archive `panther-ops manager deploy` uploads: the manager package and its pure-Python
dependencies in one zipapp (``panther_ops_manager.pyz``).

One file instead of a tree of ~200 sources: one upload, one atomic rename, one backup entry,
and ``python3 panther_ops_manager.pyz`` runs it with the archive first on ``sys.path`` (no
``PYTHONPATH`` in the compose service, whose ``environment`` would otherwise replace the
one it inherits from ``x-common-config``; see docs/manager-deploy.md).

Contents: ``panther_ops/__init__.py`` (minimal: version and build id), every ``.py`` of
``panther_ops/manager``, ``py_trees`` with its dependencies ``pydot`` and ``pyparsing``, and
PyYAML's pure-Python part (its C loader is optional), each from this machine's environment,
their license texts under ``licenses/``, and ``__main__.py`` (runs ``panther_ops.manager``).
Pillow and paramiko are left out: the robot's driver renders the LEDs, and SSH shutdowns
use paramiko only when the image has it.

The archive is byte-for-byte reproducible (sorted entries, fixed times and modes, stored
uncompressed, so no zlib version changes it): the same sources give the same bytes and the
same build id, which makes a second deploy a no-op.
"""

from __future__ import annotations

import hashlib
import importlib.metadata
import importlib.util
import io
import zipfile
from collections.abc import Iterable
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import panther_ops
from panther_ops.errors import OpsError

ARCHIVE_NAME = "panther_ops_manager.pyz"
#: (import name, distribution name) of the pure-Python dependencies shipped in the archive
DEPENDENCIES = (("py_trees", "py_trees"), ("pydot", "pydot"), ("pyparsing", "pyparsing"), ("yaml", "PyYAML"))
_ZIP_TIME = (1980, 1, 1, 0, 0, 0)

MAIN = '''"""Run the panther-ops runtime manager from this archive (python3 panther_ops_manager.pyz ...)."""
import runpy

runpy.run_module("panther_ops.manager", run_name="__main__", alter_sys=True)
'''


class BundleError(OpsError):
    """The archive cannot be built on this machine (a dependency is missing)."""


@dataclass(frozen=True)
class ManagerBundle:
    """The archive and what is in it."""

    data: bytes
    version: str
    """``<panther-ops version>-<build>``: the name of the versioned directory on the robot."""
    build: str
    """12 hex digits of the SHA-256 of every member (path and content), the init file excluded."""
    members: tuple[str, ...] = ()
    dependencies: dict[str, str] = field(default_factory=dict)
    """distribution -> version shipped"""

    @property
    def sha256(self) -> str:
        return hashlib.sha256(self.data).hexdigest()


def _package_dir(name: str) -> Path:
    spec = importlib.util.find_spec(name)
    if spec is None or not spec.submodule_search_locations:
        raise BundleError(f"Python package {name} is not installed here: the manager needs it on the robot",
                          hint="install panther-ops with its dependencies (pip install panther-ops)")
    return Path(next(iter(spec.submodule_search_locations)))


def _sources(root: Path, prefix: str) -> Iterable[tuple[str, bytes]]:
    """Every .py file under root (no caches, no compiled extensions), as archive paths."""
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root)
        if "__pycache__" in rel.parts:
            continue
        yield f"{prefix}/{rel.as_posix()}", path.read_bytes()


def _license(dist: str) -> bytes | None:
    try:
        files = importlib.metadata.files(dist) or []
    except importlib.metadata.PackageNotFoundError:
        return None
    for f in files:
        name = f.name.upper()
        if name.startswith(("LICENSE", "LICENCE", "COPYING")):
            try:
                return f.read_text().encode()
            except (OSError, UnicodeDecodeError):
                continue
    return None


def _init(build: str) -> bytes:
    return (
        '"""panther-ops, as deployed on a robot: only the runtime manager (panther_ops.manager)."""\n\n'
        f'__version__ = "{panther_ops.__version__}"\n'
        f'__build__ = "{build}"\n'
    ).encode()


def _zip(members: dict[str, bytes]) -> bytes:
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_STORED) as zf:
        for name in sorted(members):
            info = zipfile.ZipInfo(name, date_time=_ZIP_TIME)
            info.create_system = 3
            info.external_attr = 0o644 << 16
            info.compress_type = zipfile.ZIP_STORED
            zf.writestr(info, members[name])
    return buf.getvalue()


@lru_cache(maxsize=1)
def build_bundle() -> ManagerBundle:
    """The archive of this installation's manager and dependencies (built once per process)."""
    members: dict[str, bytes] = dict(_sources(_package_dir("panther_ops.manager"), "panther_ops/manager"))
    versions: dict[str, str] = {}
    for module, dist in DEPENDENCIES:
        members.update(_sources(_package_dir(module), module))
        try:
            versions[dist] = importlib.metadata.version(dist)
        except importlib.metadata.PackageNotFoundError:
            versions[dist] = "?"
        text = _license(dist)
        if text is not None:
            members[f"licenses/{dist}.txt"] = text
    members["__main__.py"] = MAIN.encode()
    digest = hashlib.sha256()
    for name in sorted(members):
        digest.update(name.encode() + b"\0" + hashlib.sha256(members[name]).digest())
    build = digest.hexdigest()[:12]
    members["panther_ops/__init__.py"] = _init(build)
    return ManagerBundle(_zip(members), f"{panther_ops.__version__}-{build}", build, tuple(sorted(members)),
                         versions)


def bundle_build(data: bytes) -> str | None:
    """The build id written in an archive's ``panther_ops/__init__.py`` (None: not one of ours)."""
    try:
        with zipfile.ZipFile(io.BytesIO(data)) as zf:
            text = zf.read("panther_ops/__init__.py").decode()
    except (zipfile.BadZipFile, KeyError, UnicodeDecodeError):
        return None
    for line in text.splitlines():
        if line.startswith("__build__ = "):
            return line.split("=", 1)[1].strip().strip('"')
    return None
