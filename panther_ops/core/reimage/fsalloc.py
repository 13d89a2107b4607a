"""Which bytes of a file system are in use: ext2/3/4 (block group bitmaps) and FAT12/16/32 (the FAT).

Pure: ``read(offset, size) -> bytes`` reads the image; offsets are the file system's own (the
caller adds the partition's start). Each reader returns the used byte extents, or None when the
bytes are not that file system (or one it cannot judge: then the caller maps everything).

ext4 (the kernel's fs/ext4/ext4.h layout): the superblock at byte 1024 (magic 0xEF53 at 56);
the group descriptors in the block after the superblock's; per group its block bitmap (one bit
per block, set: in use). A group flagged BLOCK_UNINIT has no bitmap on disk: its superblock
backup and group descriptors (where the group has them) and the bitmaps and inode table its
descriptor names are taken as used. META_BG (descriptors spread through the file system) is not
read: None. ``ext4_unread`` names the used blocks whose old contents nothing reads (left out of
a sparse image's map where they are holes: ``mapping``).

FAT (Microsoft's FAT specification): the BIOS parameter block of the boot sector; everything
before the data region (boot sector, reserved sectors with FSInfo and the backup boot sector,
the FATs, FAT12/16's root directory) is in use, and each data cluster whose FAT entry is not 0.
"""

from __future__ import annotations

import sys
from array import array
from collections.abc import Callable, Iterable
from dataclasses import dataclass

Reader = Callable[[int, int], bytes]
Extents = list[tuple[int, int]]

_EXT_MAGIC = 0xEF53
_INCOMPAT_META_BG = 0x10
_INCOMPAT_64BIT = 0x80
_COMPAT_SPARSE_SUPER2 = 0x200
_RO_COMPAT_SPARSE_SUPER = 0x1
_RO_COMPAT_GDT_CSUM = 0x10
_RO_COMPAT_METADATA_CSUM = 0x400
_BG_INODE_UNINIT = 0x1
_BG_BLOCK_UNINIT = 0x2
_BG_ITABLE_ZEROED = 0x4


def _u16(b: bytes, off: int) -> int:
    return int.from_bytes(b[off:off + 2], "little")


def _u32(b: bytes, off: int) -> int:
    return int.from_bytes(b[off:off + 4], "little")


def _has_backup(group: int, sparse: bool, backups: tuple[int, int] | None = None) -> bool:
    """Whether ``group`` holds a superblock backup: every group, or with sparse_super 0, 1 and the
    powers of 3, 5 and 7, or with sparse_super2 group 0 and the two groups the superblock names."""
    if backups is not None:
        return group == 0 or group in backups
    if group <= 1 or not sparse:
        return True
    for base in (3, 5, 7):
        n = group
        while n % base == 0:
            n //= base
        if n == 1:
            return True
    return False


def _runs(bits: bytes, count: int) -> list[tuple[int, int]]:
    """[first, end) runs of set bits among the first ``count`` (little-endian bit order)."""
    out: list[tuple[int, int]] = []
    start = None
    n = min(count, len(bits) * 8)
    i = 0
    while i < n:
        byte = bits[i >> 3]
        if byte in (0, 0xFF) and i % 8 == 0 and i + 8 <= n:
            full = byte == 0xFF
            if full and start is None:
                start = i
            elif not full and start is not None:
                out.append((start, i))
                start = None
            i += 8
            continue
        if byte >> (i & 7) & 1:
            if start is None:
                start = i
        elif start is not None:
            out.append((start, i))
            start = None
        i += 1
    if start is not None:
        out.append((start, n))
    return out


@dataclass(frozen=True)
class _Group:
    start: int
    """First block."""
    count: int
    bitmap: int
    ibitmap: int
    itable: int
    flags: int
    itable_unused: int


@dataclass(frozen=True)
class _Ext4:
    block: int
    blocks: int
    first_data: int
    gdt_blocks: int
    reserved_gdt: int
    sparse: bool
    backups: tuple[int, int] | None
    """sparse_super2: the two groups holding backups (s_backup_bgs)."""
    csum: bool
    """Group descriptors carry checksums (uninit_bg or metadata_csum): the kernel and e2fsck trust
    their UNINIT flags and bg_itable_unused."""
    inodes_per_group: int
    inode_size: int
    itable_blocks: int
    groups: tuple[_Group, ...]


def _ext4(read: Reader, size: int) -> _Ext4 | None:
    sb = read(1024, 1024)
    if len(sb) < 1024 or _u16(sb, 56) != _EXT_MAGIC:
        return None
    incompat, ro_compat = _u32(sb, 0x60), _u32(sb, 0x64)
    if incompat & _INCOMPAT_META_BG:
        return None
    block = 1024 << _u32(sb, 0x18)
    is64 = bool(incompat & _INCOMPAT_64BIT)
    blocks = _u32(sb, 0x4) | ((_u32(sb, 0x150) << 32) if is64 else 0)
    first_data = _u32(sb, 0x14)
    per_group = _u32(sb, 0x20)
    desc_size = _u16(sb, 0xFE) if is64 else 32
    if not per_group or desc_size < 32 or blocks * block > size or block > 65536:
        return None
    count = (blocks - first_data + per_group - 1) // per_group
    gdt = read((first_data + 1) * block, count * desc_size)
    if len(gdt) < count * desc_size:
        return None
    inodes_per_group, inode_size = _u32(sb, 0x28), (_u16(sb, 0x58) or 128)
    itable_blocks = (inodes_per_group * inode_size + block - 1) // block
    groups = []
    for g in range(count):
        d = gdt[g * desc_size:(g + 1) * desc_size]
        hi = desc_size >= 64
        itable = _u32(d, 0x8) | ((_u32(d, 0x28) << 32) if hi else 0)
        bitmap = _u32(d, 0x0) | ((_u32(d, 0x20) << 32) if hi else 0)
        start = first_data + g * per_group
        if bitmap >= blocks or itable + itable_blocks > blocks:
            return None
        groups.append(_Group(start, min(per_group, blocks - start), bitmap,
                             _u32(d, 0x4) | ((_u32(d, 0x24) << 32) if hi else 0), itable, _u16(d, 0x12),
                             _u16(d, 0x1C) | ((_u16(d, 0x32) << 16) if hi else 0)))
    backups = (_u32(sb, 0x24C), _u32(sb, 0x250)) if _u32(sb, 0x5C) & _COMPAT_SPARSE_SUPER2 else None
    csum = bool(ro_compat & (_RO_COMPAT_GDT_CSUM | _RO_COMPAT_METADATA_CSUM))
    return _Ext4(block, blocks, first_data, (count * desc_size + block - 1) // block, _u16(sb, 0xCE),
                 bool(ro_compat & _RO_COMPAT_SPARSE_SUPER), backups, csum, inodes_per_group, inode_size,
                 itable_blocks, tuple(groups))


def ext4_used(read: Reader, size: int) -> Extents | None:
    """The used byte extents of an ext2/3/4 file system of ``size`` bytes, or None."""
    fs = _ext4(read, size)
    if fs is None:
        return None
    block = fs.block
    used: Extents = [(0, (fs.first_data + 1 + fs.gdt_blocks + fs.reserved_gdt) * block)]
    for g, grp in enumerate(fs.groups):
        # every group's own metadata, whatever its bitmap says
        used += [(grp.bitmap * block, (grp.bitmap + 1) * block), (grp.ibitmap * block, (grp.ibitmap + 1) * block),
                 (grp.itable * block, (grp.itable + fs.itable_blocks) * block)]
        if grp.flags & _BG_BLOCK_UNINIT:
            if _has_backup(g, fs.sparse, fs.backups):
                used.append((grp.start * block, (grp.start + 1 + fs.gdt_blocks + fs.reserved_gdt) * block))
            continue
        bits = read(grp.bitmap * block, (grp.count + 7) // 8)
        for a, b in _runs(bits, grp.count):
            used.append(((grp.start + a) * block, (grp.start + b) * block))
    return used


def ext4_unread(read: Reader, size: int) -> Extents | None:
    """The byte extents, among those ``ext4_used`` counts, whose old contents neither the kernel nor
    e2fsck reads before writing them: where mke2fs itself, formatting a block device, leaves the
    device's old bytes. None: not ext2/3/4 (as ``ext4_used``).

    - the block bitmap of a group flagged BLOCK_UNINIT and the inode bitmap of one flagged
      INODE_UNINIT, when the descriptors carry checksums (the kernel's ext4_read_block_bitmap_nowait
      and ext4_read_inode_bitmap build them in memory; e2fsprogs' rw_bitmaps.c neither reads nor
      writes them);
    - the backup copies of the reserved GDT blocks (in groups holding a superblock backup but
      group 0): the resize inode lists them (e2fsprogs' res_gdt.c), nothing reads them until an
      online or offline resize writes descriptors there;
    - the inode table blocks past the group's last used inode (bg_itable_unused) in a group NOT
      flagged ITABLE_ZEROED, with checksummed descriptors: the kernel's lazy init thread
      (ext4_init_inode_table) zeroes exactly those blocks on the first mount, as after
      `mke2fs -E lazy_itable_init=1`. A group flagged ITABLE_ZEROED promises zeros there (mkfs on an
      image file sets it because its holes read as zeros): its inode table is always written.
    """
    fs = _ext4(read, size)
    if fs is None:
        return None
    block, out = fs.block, []
    for g, grp in enumerate(fs.groups):
        if fs.csum and grp.flags & _BG_BLOCK_UNINIT:
            out.append((grp.bitmap * block, (grp.bitmap + 1) * block))
        if fs.csum and grp.flags & _BG_INODE_UNINIT:
            out.append((grp.ibitmap * block, (grp.ibitmap + 1) * block))
        if g and fs.reserved_gdt and _has_backup(g, fs.sparse, fs.backups):
            first = grp.start + 1 + fs.gdt_blocks
            out.append((first * block, (first + fs.reserved_gdt) * block))
        if fs.csum and not grp.flags & _BG_ITABLE_ZEROED:
            used = fs.inodes_per_group - min(grp.itable_unused, fs.inodes_per_group)
            first = -(-used // (block // fs.inode_size))  # the kernel's used_blks
            if first < fs.itable_blocks:
                out.append(((grp.itable + first) * block, (grp.itable + fs.itable_blocks) * block))
    return out


def fat_used(read: Reader, size: int) -> Extents | None:
    """The used byte extents of a FAT12/16/32 file system of ``size`` bytes, or None."""
    bs = read(0, 512)
    if len(bs) < 512 or bs[510:512] != b"\x55\xaa" or bs[0] not in (0xEB, 0xE9):
        return None
    bps, spc = _u16(bs, 11), bs[13]
    reserved, fats, root_entries = _u16(bs, 14), bs[16], _u16(bs, 17)
    total = _u16(bs, 19) or _u32(bs, 32)
    fat_sectors = _u16(bs, 22) or _u32(bs, 36)
    if bps not in (512, 1024, 2048, 4096) or spc == 0 or spc & (spc - 1) or not fats or not fat_sectors:
        return None
    if not reserved or total * bps > size:
        return None
    root_sectors = (root_entries * 32 + bps - 1) // bps
    data_start = reserved + fats * fat_sectors + root_sectors
    if data_start >= total:
        return None
    clusters = (total - data_start) // spc
    kind = 12 if clusters < 4085 else 16 if clusters < 65525 else 32
    fat_bytes = {12: (clusters + 2) * 3 // 2 + 1, 16: (clusters + 2) * 2, 32: (clusters + 2) * 4}[kind]
    if fat_bytes > fat_sectors * bps + 4:
        return None
    fat = read(reserved * bps, min(fat_bytes, fat_sectors * bps))
    used: Extents = [(0, data_start * bps)]
    cluster_bytes = spc * bps
    base = data_start * bps
    start = None
    for n, entry in enumerate(_fat_entries(fat, kind, clusters), 2):
        if entry:
            if start is None:
                start = n
        elif start is not None:
            used.append((base + (start - 2) * cluster_bytes, base + (n - 2) * cluster_bytes))
            start = None
    if start is not None:
        used.append((base + (start - 2) * cluster_bytes, base + clusters * cluster_bytes))
    return used


def _fat_entries(fat: bytes, kind: int, clusters: int) -> Iterable[int]:
    """The FAT entries of clusters 2 .. clusters+1 (an entry past the FAT's bytes: 0). FAT16/32
    are read as one array (a card's FAT32 has ~10^5-10^6 entries), FAT12 pair by pair."""
    if kind == 12:
        return ((_u16(fat, n * 3 // 2) >> 4 if n & 1 else _u16(fat, n * 3 // 2) & 0xFFF)
                for n in range(2, clusters + 2))
    width = kind // 8
    raw = fat[2 * width:(clusters + 2) * width]
    entries = array("I" if kind == 32 else "H", raw + bytes(clusters * width - len(raw)))
    if sys.byteorder == "big":
        entries.byteswap()
    return (e & 0x0FFFFFFF for e in entries) if kind == 32 else entries
