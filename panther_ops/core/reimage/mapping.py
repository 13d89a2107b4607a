"""The block map of an image that has no .bmap: from its partition table and file systems.

Pure: the image is read through ``read(offset, size)``. Which bytes are mapped (must be
written to a card):

- the partition table (MBR sector; GPT's primary and backup headers and entries);
- in a partition holding ext2/3/4 or FAT: the blocks that file system uses (``fsalloc``), less
  the ext4 blocks whose old contents nothing reads (``fsalloc.ext4_unread``: UNINIT groups'
  bitmaps, the reserved GDT blocks' backups, inode table tails the kernel zeroes itself), left
  out whatever the image holds there, so that a ``.img`` and its ``.xz`` have the same map. A
  hole in a sparse image is not otherwise left out of a file system's blocks: it reads as zeros
  in the image and the file system may rely on that (mkfs on an image file marks its inode
  tables ITABLE_ZEROED and leaves them as holes);
- everything else (space outside every partition: boot loaders may live there; a partition of
  a type or file system not read here; an image with no partition table): mapped whole,
  except that where the image file is sparse (``data`` given: its data extents, as
  ``SEEK_DATA``/``SEEK_HOLE`` report them) its holes are not mapped, as bmaptool does.

Every fallback is named in ``notes``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from panther_ops.core.reimage.device import human_size
from panther_ops.core.reimage.fsalloc import Extents, ext4_unread, ext4_used, fat_used
from panther_ops.core.reimage.parttable import Partition, read_table

Reader = Callable[[int, int], bytes]


@dataclass
class Mapped:
    extents: Extents
    notes: list[str] = field(default_factory=list)
    regions: list[dict[str, object]] = field(default_factory=list)
    """Per partition: number, start, bytes, type, file system, used bytes."""


def _clip(extents: Extents, lo: int, hi: int) -> Extents:
    return [(max(s, lo), min(e, hi)) for s, e in extents if min(e, hi) > max(s, lo)]


def _within(data: Extents | None, lo: int, hi: int) -> Extents:
    """[lo, hi), less the image file's holes when it is sparse."""
    return [(lo, hi)] if data is None else _clip(data, lo, hi)


def _merged(extents: Extents) -> Extents:
    merged: Extents = []
    for s, e in sorted(extents):
        if merged and s <= merged[-1][1]:
            merged[-1] = (merged[-1][0], max(merged[-1][1], e))
        elif e > s:
            merged.append((s, e))
    return merged


def _total(extents: Extents) -> int:
    return sum(e - s for s, e in _merged(extents))


def _minus(extents: Extents, cut: Extents) -> Extents:
    """``extents`` less every byte in ``cut``."""
    out: Extents = []
    cut = _merged(cut)
    for s, e in _merged(extents):
        pos = s
        for a, b in cut:
            if b <= pos or a >= e:
                continue
            if a > pos:
                out.append((pos, a))
            pos = max(pos, b)
        if pos < e:
            out.append((pos, e))
    return out


def _partition(read: Reader, p: Partition, image_size: int, data: Extents | None, out: Mapped) -> None:
    end = min(p.start + p.size, image_size)
    def sub(off: int, n: int) -> bytes:
        return read(p.start + off, max(0, min(n, end - p.start - off)))

    fs, used = "", None
    for name, reader in (("ext4", ext4_used), ("fat", fat_used)):
        used = reader(sub, end - p.start)
        if used is not None:
            fs = name
            break
    if used is None:
        mapped = _within(data, p.start, end)
        how = "its holes left out (sparse image)" if data is not None else "mapped whole"
        out.notes.append(f"partition {p.number} (type {p.kind}, {human_size(end - p.start)}): no ext2/3/4 or "
                         f"FAT file system read there: {how}")
    else:
        mapped = _clip([(p.start + s, p.start + e) for s, e in used], p.start, end)
        unread = ext4_unread(sub, end - p.start) if fs == "ext4" else None
        if unread:
            mapped = _minus(mapped, [(p.start + s, p.start + e) for s, e in unread])
    out.extents += mapped
    out.regions.append({"partition": p.number, "start": p.start, "bytes": end - p.start, "type": p.kind,
                        "filesystem": fs or None, "mapped_bytes": _total(mapped)})


def compute_map(read: Reader, image_size: int, data: Extents | None = None) -> Mapped:
    """The mapped byte extents of an image (see the module's doc)."""
    out = Mapped([])
    table = read_table(read, image_size)
    if table.scheme == "none":
        out.extents = _within(data, 0, image_size)
        how = "its holes left out (sparse image)" if data is not None else "the whole image is mapped"
        out.notes.append(f"no partition table (MBR or GPT) in the image: {how}")
        return out
    out.extents += list(table.extents)
    covered: Extents = list(table.extents)
    for p in sorted(table.partitions, key=lambda p: p.start):
        if p.start >= image_size:
            out.notes.append(f"partition {p.number} starts past the image's end: ignored")
            continue
        _partition(read, p, image_size, data, out)
        covered.append((p.start, min(p.start + p.size, image_size)))
    pos = 0
    for s, e in sorted(covered):
        if s > pos:
            out.extents += _within(data, pos, s)
        pos = max(pos, e)
    if pos < image_size:
        out.extents += _within(data, pos, image_size)
    return out
