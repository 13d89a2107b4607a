"""A lab image with Python 3.10 standing in for a robot's ROS image (`panther-ops manager deploy`).

The lab's usual image is busybox with a `ros2` stand-in: enough for the driver, not for a
Python program. This module builds a second root file system — the same busybox, `ros2`
stand-in and entrypoint, plus a CPython 3.10 from this machine (pruned of tests, IDLE,
tkinter, ensurepip, compiled caches), the shared libraries `ldd` shows for the interpreter
and the extension modules kept, and the manager's dependencies as site-packages (py_trees,
pydot, pyparsing, PyYAML's pure-Python part; from the environment running the lab) — like
Ubuntu's python3 and python3-yaml in the real ROS image — and, as the real image's rclpy and
geometry_msgs (ros-core), the lab's stand-in of the part of them a publisher uses
(data/rclpy-standin: publishes into the `ros2` stand-in's state). No network, no pulls.

`use_python_image(lab, "r02")` imports it into that robot's dockerd under a tag of its own
(`panther-ops-lab/python:3.10`) AND under the robot's real driver tag, so on that robot
"the robot's own ROS image" has Python, as on a real Panther: the driver (still the `ros2`
stand-in) and a manager service on the driver's image both run from it.
`restore_driver_image(lab, "r02")` puts the busybox image back under the driver tag,
recreates the driver from it and deletes the Python image.

The tarball (~20 MB) is built once and cached in `<lab base>/.images/` under a key of its
inputs (interpreter, busybox, package versions), so later labs reuse it.
"""

from __future__ import annotations

import hashlib
import importlib.metadata
import importlib.util
import os
import re
import shutil
import subprocess
import tarfile
import tempfile
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from ._sys import LabError
from .files import DATA
from .image import IMPORT_CHANGES, VERSION_LABEL, build_rootfs, find_static_busybox, tar_dir, tar_file, with_version

PYTHON_TAG = "panther-ops-lab/python:3.10"
LABEL = "org.panther-ops.lab"
BUILDER = "pyimage-5"
#: stand-ins of the ROS image's own Python packages (rclpy, geometry_msgs), put in site-packages
STANDIN_PACKAGES = DATA / "rclpy-standin"
#: site-packages of the image: (import name, distribution)
PACKAGES = (("py_trees", "py_trees"), ("pydot", "pydot"), ("pyparsing", "pyparsing"), ("yaml", "PyYAML"))
#: stdlib directories left out (tests, GUIs, installers, build files)
SKIP_DIRS = {"test", "tests", "idlelib", "tkinter", "turtledemo", "ensurepip", "lib2to3", "distutils", "pydoc_data",
             "__pycache__", "site-packages", "venv"}
#: extension modules left out (tests, terminals, GUI, databases, TLS: not needed by the manager)
SKIP_EXT = re.compile(r"^(_test|_ctypes_test|_xxtestfuzz|xxlimited|_xxsubinterpreters|_tkinter|_curses|readline|nis|"
                      r"ossaudiodev|spwd|_crypt|_sqlite3|_dbm|_gdbm|audioop|_ssl|_hashlib)")
PREFIX = "usr/local"
LIBDIR = "usr/lib/x86_64-linux-gnu"


def find_python310() -> Path:
    """A CPython 3.10 interpreter on this machine (real path)."""
    candidates = [*sorted(Path("/root/.pyenv/versions").glob("3.10.*/bin/python3.10"), reverse=True)]
    for name in ("python3.10",):
        found = shutil.which(name)
        if found:
            candidates.append(Path(found))
    candidates.append(Path("/usr/bin/python3.10"))
    for c in candidates:
        if c.is_file() and os.access(c, os.X_OK):
            return c.resolve()
    raise LabError("no Python 3.10 on this machine (pyenv install 3.10 or apt-get install python3.10)")


def _interp_facts(python: Path) -> dict[str, str]:
    code = ("import sys, sysconfig; print(sys.version.split()[0]); print(sysconfig.get_path('stdlib')); "
            "print(sysconfig.get_config_var('DESTSHARED') or ''); print(sysconfig.get_config_var('LIBDIR') or ''); "
            "print(sysconfig.get_config_var('INSTSONAME') or '')")
    out = subprocess.run([str(python), "-I", "-c", code], capture_output=True, text=True, check=True).stdout.split("\n")
    return {"version": out[0], "stdlib": out[1], "dynload": out[2], "libdir": out[3], "soname": out[4]}


def _ldd(paths: Iterable[Path]) -> set[Path]:
    libs: set[Path] = set()
    for p in paths:
        cp = subprocess.run(["ldd", str(p)], capture_output=True, text=True, check=False)
        for line in cp.stdout.splitlines():
            m = re.search(r"=>\s*(/\S+)", line) or re.match(r"\s*(/\S+)\s+\(", line)
            if m:
                libs.add(Path(m.group(1)))
    return libs


def _stripped(path: Path) -> bytes:
    """The file without its debug sections (`strip --strip-debug`; as is without binutils)."""
    strip = shutil.which("strip")
    if strip is None:
        return path.read_bytes()
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / path.name
        cp = subprocess.run([strip, "--strip-debug", "-o", str(out), str(path)], capture_output=True, check=False)
        return out.read_bytes() if cp.returncode == 0 else path.read_bytes()


def _package_sources(module: str) -> list[tuple[str, Path]]:
    spec = importlib.util.find_spec(module)
    if spec is None or not spec.submodule_search_locations:
        raise LabError(f"Python package {module} is not installed in the lab's environment")
    root = Path(next(iter(spec.submodule_search_locations)))
    return [(f"{module}/{p.relative_to(root).as_posix()}", p) for p in sorted(root.rglob("*.py"))
            if "__pycache__" not in p.parts]


STAND_INS = ("ros2-standin.sh", "ros_entrypoint.sh", "nmea-listen.c", "bash-standin.sh", "joy2twist_panther.yaml")
"""The usual image's own files (tests/lab/data) the Python image carries: part of its key."""


def cache_key(python: Path) -> str:
    st, bb = python.stat(), find_static_busybox().stat()
    versions = []
    for _module, dist in PACKAGES:
        try:
            versions.append(f"{dist}={importlib.metadata.version(dist)}")
        except importlib.metadata.PackageNotFoundError:
            versions.append(f"{dist}=?")
    standins = hashlib.sha256(b"".join(p.read_bytes() for p in sorted(STANDIN_PACKAGES.rglob("*.py")))).hexdigest()
    stand_ins = hashlib.sha256(b"".join((DATA / n).read_bytes() for n in STAND_INS)).hexdigest()[:12]
    raw = f"{BUILDER} {python} {st.st_size} {st.st_mtime} {bb.st_size} {' '.join(versions)} {standins} {stand_ins}"
    return hashlib.sha256(raw.encode()).hexdigest()[:12]


def python_rootfs(cache_dir: Path) -> Path:
    """The Python root file system tarball (built if the cache has none for these inputs)."""
    python = find_python310()
    dest = cache_dir / f"python310-{cache_key(python)}.tar"
    if dest.is_file():
        return dest
    cache_dir.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=".python310-", suffix=".tar", dir=cache_dir)
    os.close(fd)
    try:
        _build(python, Path(tmp))
        os.replace(tmp, dest)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    for old in cache_dir.glob("python310-*.tar"):  # earlier inputs: no longer used
        if old != dest:
            old.unlink(missing_ok=True)
    return dest


def _build(python: Path, dest: Path) -> None:
    facts = _interp_facts(python)
    if not facts["version"].startswith("3.10."):
        raise LabError(f"{python} is Python {facts['version']}, not 3.10")
    stdlib, dynload = Path(facts["stdlib"]), Path(facts["dynload"] or Path(facts["stdlib"]) / "lib-dynload")
    exts = [p for p in sorted(dynload.glob("*.so")) if not SKIP_EXT.match(p.name)]
    libpython = Path(facts["libdir"]) / facts["soname"] if facts["soname"].endswith(".so.1.0") else None
    binaries = [python, *exts] + ([libpython] if libpython and libpython.is_file() else [])
    libs = {lib for lib in _ldd(binaries) if "python3.10" not in lib.name}
    with tempfile.TemporaryDirectory() as tmpdir:
        busybox_tar = build_rootfs(Path(tmpdir) / "busybox.tar", dest.parent)
        with tarfile.open(busybox_tar) as src, tarfile.open(dest, "w") as tar:
            for member in src.getmembers():
                if member.name == "etc/lab-image":
                    continue  # replaced below
                data = src.extractfile(member) if member.isfile() else None
                tar.addfile(member, data)
            _dirs(tar, ["lib64", "lib", "lib/x86_64-linux-gnu", "usr/lib", LIBDIR, f"{PREFIX}/lib",
                        f"{PREFIX}/lib/python3.10", f"{PREFIX}/lib/python3.10/lib-dynload",
                        f"{PREFIX}/lib/python3.10/site-packages"])
            for lib in sorted(libs):
                tar_file(tar, str(lib).lstrip("/"), lib.resolve().read_bytes(), 0o755)
            if libpython and libpython.is_file():
                tar_file(tar, f"{LIBDIR}/{facts['soname']}", _stripped(libpython), 0o755)
            tar_file(tar, f"{PREFIX}/bin/python3.10", _stripped(python), 0o755)
            _link(tar, f"{PREFIX}/bin/python3", "python3.10")
            _link(tar, "usr/bin/python3", f"/{PREFIX}/bin/python3.10")
            for ext in exts:
                tar_file(tar, f"{PREFIX}/lib/python3.10/lib-dynload/{ext.name}", _stripped(ext), 0o755)
            _stdlib(tar, stdlib)
            for module, _dist in PACKAGES:
                for rel, path in _package_sources(module):
                    tar_file(tar, f"{PREFIX}/lib/python3.10/site-packages/{rel}", path.read_bytes())
            site = f"{PREFIX}/lib/python3.10/site-packages"
            for path in sorted(STANDIN_PACKAGES.rglob("*")):
                if "__pycache__" in path.parts:
                    continue
                rel = path.relative_to(STANDIN_PACKAGES).as_posix()
                if path.is_dir():
                    _dirs(tar, [f"{site}/{rel}"])
                elif path.suffix == ".py":
                    tar_file(tar, f"{site}/{rel}", path.read_bytes())
            tar_file(tar, "etc/lab-image", b"panther-ops test lab stand-in image (busybox + Python 3.10, no ROS)\n")


def _stdlib(tar: tarfile.TarFile, stdlib: Path) -> None:
    made: set[str] = set(tar.getnames())
    for path in sorted(stdlib.rglob("*")):
        rel = path.relative_to(stdlib)
        if any(part in SKIP_DIRS or part.startswith("config-") for part in rel.parts) or rel.parts[0] == "lib-dynload":
            continue
        if path.is_file() and path.suffix == ".py":
            parent = f"{PREFIX}/lib/python3.10/{rel.parent.as_posix()}".rstrip("/.")
            parts = parent.split("/")
            for i in range(4, len(parts) + 1):
                d = "/".join(parts[:i])
                if d not in made:
                    made.add(d)
                    _dirs(tar, [d])
            tar_file(tar, f"{PREFIX}/lib/python3.10/{rel.as_posix()}", path.read_bytes())


def _dirs(tar: tarfile.TarFile, names: Iterable[str]) -> None:
    have = set(tar.getnames())
    for name in names:
        if name in have:
            continue
        have.add(name)
        tar_dir(tar, name)


def _link(tar: tarfile.TarFile, name: str, target: str) -> None:
    ti = tarfile.TarInfo(name)
    ti.type = tarfile.SYMTYPE
    ti.linkname = target
    tar.addfile(ti)


def python_changes(version: str | None = None) -> list[str]:
    """`docker import --change` lines: the stand-in's, with its own label (and its release's)."""
    return ([c for c in IMPORT_CHANGES if not c.startswith("LABEL ")] + [f"LABEL {LABEL}=python-stand-in"]
            + ([f"LABEL {VERSION_LABEL}={version}"] if version else []))


def use_python_image(lab: Any, name: str) -> str:
    """Import the Python image into robot `name` under its own tag and the robot's driver tag.

    The running containers are not touched; the next recreate of the driver (e.g. by
    `manager deploy`) runs it from the Python image, with the robot's release in /version.txt
    as its driver image has. Returns the image id.
    """
    tar = python_rootfs(Path(lab.base) / ".images")
    robot = lab.robot(name)
    client = lab.docker_client(name, timeout=120)
    try:
        repo, tag = PYTHON_TAG.rsplit(":", 1)
        client.api.import_image_from_data(with_version(tar.read_bytes(), robot.stack.key), repository=repo, tag=tag,
                                          changes=python_changes(robot.stack.key))
        image = client.images.get(PYTHON_TAG)
        driver_repo, driver_tag = robot.image.rsplit(":", 1)
        image.tag(driver_repo, driver_tag)
        return str(image.id)
    finally:
        client.close()


def restore_driver_image(lab: Any, name: str) -> None:
    """Undo `use_python_image`: the busybox stand-in under the driver tag again, the driver
    recreated from it, the Python image deleted."""
    robot = lab.robot(name)
    client = lab.docker_client(name, timeout=120)
    try:
        stand_in = client.images.list(filters={"label": [f"{LABEL}=stand-in", f"{VERSION_LABEL}={robot.stack.key}"]})
        if not stand_in:
            raise LabError(f"{name}: the busybox stand-in image of {robot.stack.key} is gone")
        driver_repo, driver_tag = robot.image.rsplit(":", 1)
        stand_in[0].tag(driver_repo, driver_tag)
    finally:
        client.close()
    cp = lab.compose(name, "up", "-d", "--force-recreate", robot.driver_container)
    if cp.returncode != 0:
        raise LabError(f"{name}: recreating the driver failed: {cp.stderr.strip()}")
    client = lab.docker_client(name, timeout=120)
    try:
        for image in client.images.list(filters={"label": f"{LABEL}=python-stand-in"}):
            users = client.containers.list(all=True, filters={"ancestor": image.id})
            if not users:
                client.images.remove(image.id, force=True)
    finally:
        client.close()
