"""Whether a block device may be overwritten with an image: a pure judgement of facts read."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from panther_ops.transport.blockdev import DeviceFacts


def human_size(n: int) -> str:
    """A byte count for people: ``12 B``, ``1.5 KiB`` ... ``2.0 TiB`` (powers of 1024)."""
    value = float(n)
    for unit in ("B", "KiB", "MiB", "GiB", "TiB"):
        if value < 1024 or unit == "TiB":
            return f"{n} B" if unit == "B" else f"{value:.1f} {unit}"
        value /= 1024
    return f"{n} B"


def refusals(facts: DeviceFacts, image_size: int) -> list[str]:
    """Every reason the device must not be written (empty: it may be)."""
    dev = facts.path
    if not facts.exists:
        return [f"{dev} does not exist"]
    if facts.is_regular:
        return [f"{dev} is a regular file, not a block device (give the card's whole device, e.g. /dev/sdX)"]
    if not facts.is_block:
        return [f"{dev} is not a block device"]
    why: list[str] = []
    if facts.is_partition:
        why.append(f"{dev} is a partition of /dev/{facts.parent}: give the whole device, /dev/{facts.parent}")
    if facts.holds_root:
        why.append(f"{dev} holds this machine's root file system (/)")
    by_source: dict[str, list[str]] = {}
    for m in facts.mounts:
        if m.mount_point != "/":
            by_source.setdefault(m.source, []).append(m.mount_point)
    for source, points in by_source.items():
        where = ", ".join(points[:3]) + (f" (and {len(points) - 3} more)" if len(points) > 3 else "")
        who = dev if source in (facts.path, facts.real_path) else f"{dev}: {source}"
        why.append(f"{who} is mounted at {where}")
    if facts.swaps:
        why.append(f"{dev}: {', '.join(facts.swaps)} is in use as swap")
    if facts.holders:
        why.append(f"{dev} is in use by {', '.join('/dev/' + h for h in facts.holders)}")
    if facts.read_only:
        why.append(f"{dev} is read-only")
    if facts.size_bytes < image_size:
        why.append(
            f"{dev} ({human_size(facts.size_bytes)}, {facts.size_bytes} bytes) is smaller than the image "
            f"({human_size(image_size)}, {image_size} bytes)"
        )
    return why


def describe(facts: DeviceFacts) -> str:
    """The device as the confirmation names it: path, size, model."""
    return f"{facts.path} ({human_size(facts.size_bytes)}, {facts.model})"


def verify_refusals(facts: DeviceFacts, image_size: int) -> list[str]:
    """Why the device cannot be compared with the image (it is only read: mounted is fine)."""
    dev = facts.path
    if not facts.exists:
        return [f"{dev} does not exist"]
    if not facts.is_block:
        return [f"{dev} is not a block device"]
    if facts.size_bytes < image_size:
        return [f"{dev} ({facts.size_bytes} bytes) is smaller than the image ({image_size} bytes)"]
    return []
