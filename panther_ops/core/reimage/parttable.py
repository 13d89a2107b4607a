"""Partition tables of a disk image: MBR (DOS) and GPT, read from the image's bytes.

Pure: ``read(offset, size) -> bytes`` is given by the caller. Sectors are 512 bytes (SD card
images). Formats: the MBR's four entries at byte 446 and its 0x55AA signature; a protective
MBR entry of type 0xEE means GPT: its header at LBA 1 ("EFI PART", the entries' LBA, count and
size), the entries (type GUID, first and last LBA, UTF-16 name). Extended (logical) partitions
of an MBR are not followed: the extended partition is reported as one of unknown content.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

Reader = Callable[[int, int], bytes]
SECTOR = 512
_EMPTY_GUID = bytes(16)


@dataclass(frozen=True)
class Partition:
    number: int
    start: int
    """Byte offset in the image."""
    size: int
    kind: str
    """MBR: the type byte as 0xNN; GPT: the type GUID."""


@dataclass(frozen=True)
class Table:
    scheme: str
    """dos, gpt or none."""
    partitions: tuple[Partition, ...]
    extents: tuple[tuple[int, int], ...]
    """Where the table itself lies (bytes, [start, end))."""


def _guid(raw: bytes) -> str:
    a = raw[0:4][::-1].hex()
    b = raw[4:6][::-1].hex()
    c = raw[6:8][::-1].hex()
    return f"{a}-{b}-{c}-{raw[8:10].hex()}-{raw[10:16].hex()}".upper()


def read_table(read: Reader, image_size: int) -> Table:
    """The image's partition table (scheme ``none`` when it has no valid MBR signature)."""
    mbr = read(0, SECTOR)
    if len(mbr) < SECTOR or mbr[510:512] != b"\x55\xaa":
        return Table("none", (), ())
    entries = []
    for i in range(4):
        e = mbr[446 + 16 * i: 462 + 16 * i]
        kind = e[4]
        start = int.from_bytes(e[8:12], "little")
        count = int.from_bytes(e[12:16], "little")
        if kind and count:
            entries.append((i + 1, kind, start, count))
    if any(kind == 0xEE for _, kind, _, _ in entries):
        return _gpt(read, image_size)
    parts = tuple(Partition(n, s * SECTOR, c * SECTOR, f"0x{k:02x}") for n, k, s, c in entries)
    return Table("dos", parts, ((0, SECTOR),))


def _gpt(read: Reader, image_size: int) -> Table:
    head = read(SECTOR, SECTOR)
    if head[:8] != b"EFI PART":
        return Table("none", (), ((0, SECTOR),))
    entries_lba = int.from_bytes(head[72:80], "little")
    count = int.from_bytes(head[80:84], "little")
    size = int.from_bytes(head[84:88], "little")
    if size < 128 or count > 4096:
        return Table("none", (), ((0, 2 * SECTOR),))
    table_bytes = count * size
    raw = read(entries_lba * SECTOR, table_bytes)
    parts = []
    for i in range(count):
        e = raw[i * size:(i + 1) * size]
        if len(e) < 128 or e[:16] == _EMPTY_GUID:
            continue
        first = int.from_bytes(e[32:40], "little")
        last = int.from_bytes(e[40:48], "little")
        if last >= first:
            parts.append(Partition(i + 1, first * SECTOR, (last - first + 1) * SECTOR, _guid(e[:16])))
    primary_end = entries_lba * SECTOR + table_bytes + (-table_bytes % SECTOR)
    backup = max(0, image_size - (table_bytes + (-table_bytes % SECTOR)) - SECTOR)
    return Table("gpt", tuple(parts), ((0, max(2 * SECTOR, primary_end)), (backup, image_size)))
