"""The lab's stand-in for the `husarion/nmea-gps` image (GPS driver of panther_ros 2.0-2.1.0).

The real image runs ROS 2's nmea_navsat_driver, which cannot run here. The stand-in is the
lab's busybox root file system with a `ros2` that accepts the real image's two command forms
(the manual's `ros2 launch /husarion_utils/nmea_navsat.launch.py robot_namespace:=NS` and
`ros2 run nmea_navsat_driver nmea_socket_driver --ros-args -p port:=N`) and listens on that
UDP port with `nmea-listen`, a small static C program compiled here (busybox has no UDP
listener; tests/lab/image.py) that publishes a NavSatFix per GGA sentence by
nmea_navsat_driver's rules, served to the driver's `ros2 topic echo` stand-in (see
data/nmea-listen.c). Labelled `org.panther-ops.lab=nmea-stand-in`.

`use_nmea_image(lab, "r01")` imports it into that robot's dockerd under the real image name.
"""

from __future__ import annotations

import hashlib
import tarfile
from pathlib import Path
from typing import Any

from .files import DATA
from .image import build_rootfs, find_static_busybox, nmea_listener, tar_dir, tar_file

NMEA_IMAGE = "husarion/nmea-gps:humble-2.0.1-20240617"
LABEL = "org.panther-ops.lab"
CHANGES = (
    'ENTRYPOINT ["/ros_entrypoint.sh"]',
    'CMD ["ros2", "launch", "/husarion_utils/nmea_navsat.launch.py"]',
    "ENV PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin",
    "ENV ROS_DISTRO=humble",
    f"LABEL {LABEL}=nmea-stand-in",
)


def nmea_rootfs(cache: Path) -> Path:
    """The stand-in's root file system tarball (built once per inputs, cached in ``cache``)."""
    listener = nmea_listener(cache)
    ros2 = (DATA / "nmea-gps-ros2-standin.sh").read_bytes()
    key = hashlib.sha256(listener.read_bytes() + ros2 + find_static_busybox().read_bytes()).hexdigest()[:12]
    dest = cache / f"nmea-gps-{key}.tar"
    if dest.is_file():
        return dest
    base = build_rootfs(cache / f"nmea-base-{key}.tar", cache)
    tmp = dest.with_suffix(".tmp")
    with tarfile.open(base) as src, tarfile.open(tmp, "w") as tar:
        for member in src.getmembers():
            if member.name == "usr/bin/ros2":
                continue
            tar.addfile(member, src.extractfile(member) if member.isfile() else None)
        tar_file(tar, "usr/bin/ros2", ros2, 0o755)
        tar_dir(tar, "husarion_utils")
        tar_file(tar, "husarion_utils/nmea_navsat.launch.py", b"# stand-in: the lab's nmea-gps image has no ROS 2\n")
    tmp.replace(dest)
    base.unlink(missing_ok=True)
    return dest


def use_nmea_image(lab: Any, name: str) -> str:
    """Import the stand-in into robot ``name``'s dockerd as husarion/nmea-gps:…; returns the image id."""
    tar = nmea_rootfs(Path(lab.base) / ".images")
    client = lab.docker_client(name, timeout=120)
    try:
        repo, tag = NMEA_IMAGE.rsplit(":", 1)
        client.api.import_image_from_file(str(tar), repository=repo, tag=tag, changes=list(CHANGES))
        return str(client.images.get(NMEA_IMAGE).id)
    finally:
        client.close()
