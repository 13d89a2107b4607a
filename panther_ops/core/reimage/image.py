"""Disk images: their format, their expected checksum and their decompressed size.

Pure functions of bytes already read; the reading is done by the caller
(``panther_ops.transport.blockdev``).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import PurePath

from panther_ops.errors import UsageError

XZ_MAGIC = b"\xfd7zXZ\x00"
GZ_MAGIC = b"\x1f\x8b"
FORMATS = ("raw", "xz", "gz")
SUFFIXES = (".img", ".img.xz", ".img.gz")
_HEX = re.compile(r"^[0-9a-fA-F]{64}$")


def detect_format(name: str, head: bytes) -> str:
    """raw, xz or gz from the file's first bytes; the name must end in .img, .img.xz or .img.gz
    and agree with them."""
    lower = name.lower()
    if not lower.endswith(SUFFIXES):
        raise UsageError(f"{name}: not a disk image: allowed are {', '.join(SUFFIXES)}")
    fmt = "xz" if head.startswith(XZ_MAGIC) else "gz" if head.startswith(GZ_MAGIC) else "raw"
    want = "xz" if lower.endswith(".xz") else "gz" if lower.endswith(".gz") else "raw"
    if fmt != want:
        shown = {"raw": "uncompressed", "xz": "xz-compressed", "gz": "gzip-compressed"}
        raise UsageError(f"{name}: the name says {shown[want]} but the content is {shown[fmt]}")
    return fmt


def normalise_sha256(value: str, where: str) -> str:
    """A sha256 in lower-case hex, else a UsageError naming ``where``."""
    text = value.strip()
    if text.lower().startswith("sha256:"):
        text = text[7:]
    if not _HEX.match(text):
        raise UsageError(f"{where}: {value.strip()[:80]!r} is not a sha256 (64 hexadecimal digits)")
    return text.lower()


def sha256_from_file(text: str, image_name: str, where: str) -> str:
    """The image's sha256 from a checksum file: ``HASH  NAME`` lines (sha256sum's format, the
    name may be starred) or a lone hash."""
    lines = [ln.strip() for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    base = PurePath(image_name).name
    for ln in lines:
        parts = ln.split(None, 1)
        if len(parts) == 2 and PurePath(parts[1].lstrip("*")).name == base:
            return normalise_sha256(parts[0], where)
    if len(lines) == 1:
        return normalise_sha256(lines[0].split()[0], where)
    raise UsageError(f"{where}: no sha256 line for {base}")


def _varint(data: bytes, pos: int) -> tuple[int, int]:
    value = shift = 0
    for i in range(9):
        if pos + i >= len(data):
            break
        byte = data[pos + i]
        value |= (byte & 0x7F) << shift
        shift += 7
        if not byte & 0x80:
            return value, pos + i + 1
    raise ValueError("bad variable-length integer in the xz index")


def xz_uncompressed_size(read_at: Callable[[int, int], bytes], file_size: int, name: str) -> int:
    """The decompressed size of an .xz file from its streams' indexes (read from the end)."""
    total = 0
    pos = file_size
    try:
        while pos > 0:
            while pos >= 4 and read_at(pos - 4, 4) == b"\0\0\0\0":  # stream padding
                pos -= 4
            footer = read_at(pos - 12, 12)
            if len(footer) != 12 or footer[10:12] != b"YZ":
                raise ValueError("no xz stream footer")
            index_size = (int.from_bytes(footer[4:8], "little") + 1) * 4
            index = read_at(pos - 12 - index_size, index_size)
            if not index or index[0] != 0:
                raise ValueError("no xz index")
            records, p = _varint(index, 1)
            blocks = 0
            for _ in range(records):
                unpadded, p = _varint(index, p)
                size, p = _varint(index, p)
                blocks += unpadded + (-unpadded % 4)
                total += size
            pos -= 12 + index_size + blocks + 12
            if pos < 0 or read_at(pos, 6) != XZ_MAGIC:
                raise ValueError("no xz stream header where the index says")
    except (ValueError, OSError) as exc:
        raise UsageError(f"{name}: not a readable .xz file ({exc})") from exc
    return total
