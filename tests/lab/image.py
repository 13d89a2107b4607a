"""The lab's container image: a busybox-static root file system with a `ros2` stand-in.

Built once per lab as a ~3 MB tarball, then `docker import`ed into each robot's dockerd under
every image name the compose templates use (nothing can be pulled here): each stack's driver
image with its release's `/version.txt` (what the real Dockerfiles write: the panther /
husarion_ugv package version, husarion/husarion_ugv_ros@2.2.2:docker/Dockerfile.hardware,
husarion/panther-docker@2.1.2:Dockerfile.hardware), the `ros2` stand-in answering that
release's interfaces; the other images (joy2twist) without one.

The gamepad of husarion/panther-docker@2.0.4 and @2.1.1:demo/compose.minimal-setup.yaml runs
`bash -c "ros2 launch joy2twist ... joy2twist_params_file:=$(ros2 pkg prefix joy2twist)/share/
joy2twist/config/joy2twist_panther.yaml ..."`: the image has a `bash` stand-in (busybox sh,
data/bash-standin.sh) and that file (data/joy2twist_panther.yaml, written from
husarion/joy2twist's), since the ros2 stand-in fails a launch whose `*_file:=` is missing. It is
laid out as the real image has it: husarion/joy2twist@2f8ad45:Dockerfile copies the package to
/ros2_ws/src/joy2twist and runs `colcon build --symlink-install` in /ros2_ws, so `ros2 pkg prefix
joy2twist` is /ros2_ws/install/joy2twist and its share/joy2twist/config/joy2twist_panther.yaml is
a symlink to /ros2_ws/src/joy2twist/config/joy2twist_panther.yaml (ament_cmake's symlink install
of joy2twist/CMakeLists.txt's `install(DIRECTORY launch config ...)`).

The image also holds `nmea-listen` (data/nmea-listen.c, compiled here once per source: gcc,
libc6-dev), the NMEA driver stand-in that the driver's `ros2` runs with `launch_nmea_gps:=True` and the nmea-gps
stand-in image runs as its node.
"""

from __future__ import annotations

import hashlib
import io
import os
import shutil
import struct
import subprocess
import tarfile
from pathlib import Path

from ._sys import LabError
from .files import DATA

#: `docker import --change` instructions. The real images have STOPSIGNAL SIGINT, which
#: `docker import` of engine 20.10 refuses; the ros2 stand-in ends at once on SIGINT and
#: SIGTERM alike, so recreating a container never waits for the 10 s stop timeout.
IMPORT_CHANGES = (
    'ENTRYPOINT ["/ros_entrypoint.sh"]',
    'CMD ["ros2", "launch", "--help"]',
    "ENV PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin",
    "ENV ROS_DISTRO=humble",
    "LABEL org.panther-ops.lab=stand-in",
)


def import_changes(distro: str) -> list[str]:
    """`IMPORT_CHANGES` for a driver image of ``distro``: the real images set ROS_DISTRO from their
    Dockerfile's `ARG ROS_DISTRO` (humble on 2.0-2.2, jazzy on husarion_ugv_ros@2.3.x:docker/Dockerfile.hardware)."""
    return [f"ENV ROS_DISTRO={distro}" if c.startswith("ENV ROS_DISTRO=") else c for c in IMPORT_CHANGES]


VERSION_FILE = "version.txt"
VERSION_LABEL = "org.panther-ops.lab.version"
"""Label of a driver stand-in image: the release its /version.txt names."""


def with_version(rootfs: bytes, version: str, distro: str = "humble") -> bytes:
    """A root file system tarball with `/version.txt` holding ``version`` added, its ROS under
    /opt/ros/<distro> (the base has /opt/ros/humble; a Jazzy image, husarion_ugv 2.3, has /opt/ros/jazzy)."""
    out = io.BytesIO()
    with tarfile.open(fileobj=io.BytesIO(rootfs)) as src, tarfile.open(fileobj=out, mode="w") as tar:
        for member in src.getmembers():
            if member.name != VERSION_FILE:
                data = src.extractfile(member) if member.isfile() else None
                if member.name.startswith("opt/ros/humble"):
                    member.name = f"opt/ros/{distro}" + member.name[len("opt/ros/humble"):]
                tar.addfile(member, data)
        tar_file(tar, VERSION_FILE, f"{version}\n".encode())
    return out.getvalue()

JOY2TWIST_SOURCE = "ros2_ws/src/joy2twist/config/joy2twist_panther.yaml"
"""Where the content of joy2twist's parameters file is in the image (the package's source)."""
JOY2TWIST_DEFAULT = "ros2_ws/install/joy2twist/share/joy2twist/config/joy2twist_panther.yaml"
"""`$(ros2 pkg prefix joy2twist)/share/joy2twist/config/joy2twist_panther.yaml`: a symlink to
`/` + `JOY2TWIST_SOURCE` (colcon --symlink-install)."""


def find_static_busybox() -> Path:
    for cand in ("/bin/busybox", "/usr/bin/busybox"):
        p = Path(cand)
        if p.is_file() and _is_static_elf(p):
            return p
    found = shutil.which("busybox")
    if found and _is_static_elf(Path(found)):
        return Path(found)
    raise LabError("no statically linked busybox found: apt-get install busybox-static")


def _is_static_elf(path: Path) -> bool:
    """True if the ELF file has no PT_INTERP program header (no dynamic loader)."""
    with open(path, "rb") as f:
        head = f.read(64)
        if head[:4] != b"\x7fELF" or head[4] != 2:  # 64-bit only
            return False
        (phoff,) = struct.unpack_from("<Q", head, 0x20)
        phentsize, phnum = struct.unpack_from("<HH", head, 0x36)
        f.seek(phoff)
        table = f.read(phentsize * phnum)
    return all(
        struct.unpack_from("<I", table, i * phentsize)[0] != 3  # PT_INTERP
        for i in range(phnum)
    )


def tar_dir(tar: tarfile.TarFile, name: str, mode: int = 0o755) -> None:
    """Add a directory `name` to an image's root file system."""
    ti = tarfile.TarInfo(name)
    ti.type = tarfile.DIRTYPE
    ti.mode = mode
    tar.addfile(ti)


def tar_file(tar: tarfile.TarFile, name: str, data: bytes, mode: int = 0o644) -> None:
    """Add a file `name` holding `data` to an image's root file system."""
    ti = tarfile.TarInfo(name)
    ti.size = len(data)
    ti.mode = mode
    tar.addfile(ti, io.BytesIO(data))


def nmea_listener(cache: Path) -> Path:
    """`nmea-listen`, statically linked, compiled once per source into ``cache``."""
    src = DATA / "nmea-listen.c"
    key = hashlib.sha256(src.read_bytes()).hexdigest()[:12]
    out = cache / f"nmea-listen-{key}"
    if out.is_file():
        return out
    cache.mkdir(parents=True, exist_ok=True)
    tmp = out.with_suffix(f".{os.getpid()}.tmp")
    cp = subprocess.run(["gcc", "-static", "-Os", "-o", str(tmp), str(src)], capture_output=True, text=True,
                        check=False)
    if cp.returncode != 0:
        tmp.unlink(missing_ok=True)
        raise LabError(f"compiling nmea-listen failed (apt-get install gcc libc6-dev): {cp.stderr.strip()}")
    tmp.replace(out)
    return out


def build_rootfs(dest: Path, cache: Path | None = None) -> Path:
    """Write the image's root file system as a tarball to `dest` (~3 MB); `nmea-listen` is
    compiled into ``cache`` (default: beside `dest`)."""
    busybox = find_static_busybox()
    listener = nmea_listener(cache or dest.parent)
    applets = subprocess.run([str(busybox), "--list"], capture_output=True, text=True, check=True).stdout.split()

    dest.parent.mkdir(parents=True, exist_ok=True)
    tmp = dest.with_suffix(".tmp")
    with tarfile.open(tmp, "w") as tar:
        for d in (
            "bin",
            "sbin",
            "usr",
            "usr/bin",
            "usr/sbin",
            "usr/local",
            "usr/local/bin",
            "etc",
            "proc",
            "sys",
            "dev",
            "run",
            "run/husarion",
            "var",
            "var/log",
            "opt",
            "opt/ros",
            "opt/ros/humble",
            "opt/ros/humble/share",
            "ros2_ws",
            "ros2_ws/src",
            "ros2_ws/src/joy2twist",
            "ros2_ws/src/joy2twist/config",
            "ros2_ws/install",
            "ros2_ws/install/joy2twist",
            "ros2_ws/install/joy2twist/share",
            "ros2_ws/install/joy2twist/share/joy2twist",
            "ros2_ws/install/joy2twist/share/joy2twist/config",
            "root/.ssh",
            "config",
        ):
            tar_dir(tar, d)
        tar_dir(tar, "root", 0o700)
        tar_dir(tar, "tmp", 0o1777)
        tar_file(tar, "bin/busybox", busybox.read_bytes(), 0o755)
        for a in applets:
            if a in ("busybox", "bash"):
                continue
            ti = tarfile.TarInfo(f"bin/{a}")
            ti.type = tarfile.SYMTYPE
            ti.linkname = "busybox"
            tar.addfile(ti)
        tar_file(tar, "usr/bin/ros2", (DATA / "ros2-standin.sh").read_bytes(), 0o755)
        tar_file(tar, "bin/bash", (DATA / "bash-standin.sh").read_bytes(), 0o755)
        tar_file(tar, JOY2TWIST_SOURCE, (DATA / "joy2twist_panther.yaml").read_bytes())
        link = tarfile.TarInfo(JOY2TWIST_DEFAULT)
        link.type = tarfile.SYMTYPE
        link.linkname = f"/{JOY2TWIST_SOURCE}"
        tar.addfile(link)
        tar_file(tar, "usr/bin/nmea-listen", listener.read_bytes(), 0o755)
        tar_file(tar, "ros_entrypoint.sh", (DATA / "ros_entrypoint.sh").read_bytes(), 0o755)
        tar_file(tar, "etc/passwd", b"root:x:0:0:root:/root:/bin/sh\n")
        tar_file(tar, "etc/group", b"root:x:0:\n")
        tar_file(tar, "etc/lab-image", b"panther-ops test lab stand-in image (busybox, no ROS)\n")
    tmp.replace(dest)
    return dest
