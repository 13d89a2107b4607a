"""The backup's customisations re-applied onto the compose file of a newer image.

When the reinstalled robot runs another release of the same stack line (2.1.1 -> 2.1.x), its
new compose file is kept (its image tags above all) and what the operator had changed is
put back: the driver's launch arguments, the driver's mounts the new file lacks, and the
services the new file lacks (nmea-gps, the manager, ...). A pure function of the two texts.
"""

from __future__ import annotations

from panther_ops.core.robot.compose import ComposeFile


def same_line(old: tuple[int, ...], new: tuple[int, ...]) -> bool:
    """Both versions of one release line (major.minor): the files keep their places."""
    return old[:2] == new[:2]


def reapply(saved: str, current: str, path: str) -> tuple[str, list[str]]:
    """(the new compose text with the backup's customisations, what was re-applied)."""
    old = ComposeFile.parse(saved, path)
    new = ComposeFile.parse(current, path)
    so, sn = old.driver_service(), new.driver_service()
    done: list[str] = []
    for name, value in old.command(so).args.items():
        if new.set_arg(name, value, sn):
            done.append(f"{name}:={value}")
    have = {v.target for v in new.list_volumes(sn)}
    for v in old.list_volumes(so):
        if v.source and v.target not in have:
            new.add_volume(v.source, v.target, v.read_only, sn)
            done.append(f"mount {v.spec()}")
    for service in old.services():
        if service not in new.services():
            new.add_service(service, old.service(service))
            done.append(f"service {service}")
    return new.text(), done
