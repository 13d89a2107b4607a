"""Block maps in bmaptool's XML format (the Yocto project's bmap-tools): read 1.x and 2.x, write 2.0.

Pure: bytes in, a ``BlockMap`` out, and back. The format, as bmap-tools 3.6 reads and writes
it (``bmaptools/BmapCreate.py``, ``bmaptools/BmapCopy.py``):

- ``<bmap version="M.m">`` with ``ImageSize`` (bytes), ``BlockSize``, ``BlocksCount`` (the image's
  blocks, the last one possibly partial), ``MappedBlocksCount`` and ``BlockMap`` of ``Range``
  elements whose text is ``FIRST-LAST`` or ``N`` (block numbers, inclusive).
- Checksums: none before 1.3; 1.3: sha1, the range's attribute ``sha1`` and the file's
  ``BmapFileSHA1``; 1.4 and 2.x (1.4 is 2.0 under an older number): ``ChecksumType`` names the
  hash (sha256 as written by bmaptool), the range's attribute ``chksum``, the file's
  ``BmapFileChecksum``.
- A range's checksum covers its bytes in the image, ending at the image's end for a last
  partial block; the file's checksum is that of the file with its own value replaced by as many
  ASCII zeros.
- A major version above 2 is refused (bmaptool refuses it too).
"""

from __future__ import annotations

import hashlib
import re
from dataclasses import dataclass
from xml.etree import ElementTree

from panther_ops.core.reimage.device import human_size
from panther_ops.errors import UsageError

WRITTEN_VERSION = "2.0"
DEFAULT_BLOCK = 4096
_RANGE = re.compile(r"^\s*(\d+)\s*(?:-\s*(\d+)\s*)?$")
_HEXCHARS = re.compile(r"^[0-9a-fA-F]+$")


@dataclass(frozen=True)
class BlockRange:
    first: int
    last: int
    checksum: str | None = None


@dataclass(frozen=True)
class BlockMap:
    image_size: int
    block_size: int
    ranges: tuple[BlockRange, ...]
    checksum_type: str | None
    version: str = WRITTEN_VERSION

    @property
    def blocks_count(self) -> int:
        return (self.image_size + self.block_size - 1) // self.block_size

    @property
    def mapped_blocks(self) -> int:
        return sum(r.last - r.first + 1 for r in self.ranges)

    def byte_span(self, r: BlockRange) -> tuple[int, int]:
        """[start, end) of a range in the image (the last block ends at the image's end)."""
        return r.first * self.block_size, min((r.last + 1) * self.block_size, self.image_size)

    @property
    def mapped_bytes(self) -> int:
        return sum(e - s for s, e in (self.byte_span(r) for r in self.ranges))


def _text(root: ElementTree.Element, tag: str, where: str, *, required: bool = True) -> str | None:
    el = root.find(tag)
    if el is None or el.text is None or not el.text.strip():
        if required:
            raise UsageError(f"{where}: no <{tag}> in the block map")
        return None
    return el.text.strip()


def _int(root: ElementTree.Element, tag: str, where: str) -> int:
    value = _text(root, tag, where)
    assert value is not None
    if not value.isdigit():
        raise UsageError(f"{where}: <{tag}> is {value[:40]!r}, not a whole number")
    return int(value)


def _checksum_names(version: str, root: ElementTree.Element, where: str) -> tuple[str | None, str, str]:
    """(hash name or None, the range attribute, the file checksum's element) for a version."""
    m = re.fullmatch(r"\s*(\d+)\.(\d+)\s*", version)
    if not m:
        raise UsageError(f"{where}: bmap version {version!r} is not MAJOR.MINOR")
    major, minor = int(m.group(1)), int(m.group(2))
    if major > 2:
        raise UsageError(f"{where}: bmap version {version} is not supported (allowed: 1.x and 2.x)")
    if major == 2 or (major == 1 and minor == 4):
        kind = (_text(root, "ChecksumType", where) or "").lower()
        try:
            hashlib.new(kind)
        except ValueError:
            raise UsageError(f"{where}: <ChecksumType> {kind!r} is not a hash this machine knows "
                             "(allowed: sha256, sha1, ...)") from None
        return kind, "chksum", "BmapFileChecksum"
    if major == 1 and minor == 3:
        return "sha1", "sha1", "BmapFileSHA1"
    return None, "", ""


def file_checksum(data: bytes, kind: str, stored: str) -> str:
    """The bmap file's own checksum: of the file with the stored value replaced by zeros."""
    pos = data.find(stored.encode())
    zeroed = data[:pos] + b"0" * len(stored) + data[pos + len(stored):] if pos >= 0 else data
    return hashlib.new(kind, zeroed).hexdigest()


def _xml_root(data: bytes, where: str) -> ElementTree.Element:
    # a bmap has no document type: one with a DOCTYPE or an entity is refused before parsing
    # (no entity expansion of any kind, as defusedxml would refuse)
    if b"<!DOCTYPE" in data or b"<!ENTITY" in data:
        raise UsageError(f"{where}: not a bmap file (it declares a document type or entities)")
    try:
        root = ElementTree.fromstring(data)  # noqa: S314 (no DOCTYPE/ENTITY: checked above)
    except ElementTree.ParseError as exc:
        raise UsageError(f"{where}: not a bmap file (not XML: {exc})") from None
    if root.tag != "bmap":
        raise UsageError(f"{where}: not a bmap file (the root element is <{root.tag}>, not <bmap>)")
    return root


def parse_bmap(data: bytes, where: str) -> BlockMap:
    """A block map from a bmap file's bytes; UsageError naming ``where`` and what is wrong
    (not XML, a missing element, a bad range, the file's own checksum not matching)."""
    root = _xml_root(data, where)
    version = str(root.attrib.get("version", ""))
    kind, attr, file_tag = _checksum_names(version, root, where)
    image_size = _int(root, "ImageSize", where)
    block_size = _int(root, "BlockSize", where)
    blocks = _int(root, "BlocksCount", where)
    mapped = _int(root, "MappedBlocksCount", where)
    if block_size <= 0 or block_size % 512:
        raise UsageError(f"{where}: <BlockSize> {block_size} is not a positive multiple of 512")
    if blocks != (image_size + block_size - 1) // block_size:
        raise UsageError(f"{where}: <BlocksCount> {blocks} does not agree with <ImageSize> {image_size} "
                         f"in blocks of {block_size}")
    if kind:
        stored = (_text(root, file_tag, where) or "").lower()
        if len(stored) != len(hashlib.new(kind).hexdigest()) or not _HEXCHARS.match(stored):
            raise UsageError(f"{where}: <{file_tag}> {stored[:80]!r} is not a {kind} checksum")
        actual = file_checksum(data, kind, stored)
        if actual != stored:
            raise UsageError(f"{where}: the bmap file's own checksum is {actual} but <{file_tag}> says "
                             f"{stored}: the file was changed or damaged")
    block_map = root.find("BlockMap")
    if block_map is None:
        raise UsageError(f"{where}: no <BlockMap> in the block map")
    ranges: list[BlockRange] = []
    last_end = -1
    for el in block_map.findall("Range"):
        text = el.text or ""
        m = _RANGE.match(text)
        if not m:
            raise UsageError(f"{where}: <Range> {text.strip()[:40]!r} is not FIRST-LAST or N (block numbers)")
        first = int(m.group(1))
        last = int(m.group(2)) if m.group(2) is not None else first
        if first > last or last >= blocks:
            raise UsageError(f"{where}: <Range> {text.strip()} is outside the image's {blocks} blocks "
                             "or runs backwards")
        if first <= last_end:
            raise UsageError(f"{where}: <Range> {text.strip()} overlaps or precedes the range before it")
        last_end = last
        checksum = el.attrib.get(attr) if attr else None
        if checksum is not None:
            checksum = checksum.strip().lower()
            if kind and (len(checksum) != len(hashlib.new(kind).hexdigest()) or not _HEXCHARS.match(checksum)):
                raise UsageError(f"{where}: <Range> {text.strip()}: {attr}={checksum[:80]!r} is not a {kind} checksum")
        ranges.append(BlockRange(first, last, checksum))
    result = BlockMap(image_size, block_size, tuple(ranges), kind, version.strip())
    if result.mapped_blocks != mapped:
        raise UsageError(f"{where}: <MappedBlocksCount> {mapped} but the ranges hold {result.mapped_blocks} blocks")
    return result


def render_bmap(bmap: BlockMap) -> str:
    """The map as a version 2.0 bmap file (sha256 range checksums; every range must carry one),
    laid out as bmaptool writes it, with the file's own checksum filled in."""
    if bmap.checksum_type != "sha256" or any(r.checksum is None for r in bmap.ranges):
        raise ValueError("a 2.0 bmap is written with a sha256 checksum on every range")
    pct = 100.0 * bmap.mapped_blocks / bmap.blocks_count if bmap.blocks_count else 0.0
    lines = [
        '<?xml version="1.0" ?>',
        "<!-- The block map of a disk image, written by panther-ops (reimage bmap) in the format",
        "     of bmap-tools: the blocks of the image that hold data (partition tables, file",
        "     systems' metadata and allocated blocks). Only these need to be written to a card;",
        "     the others are free space. -->",
        f'<bmap version="{WRITTEN_VERSION}">',
        f"    <!-- Image size in bytes: {human_size(bmap.image_size)} -->",
        f"    <ImageSize> {bmap.image_size} </ImageSize>",
        "",
        "    <!-- Size of a block in bytes -->",
        f"    <BlockSize> {bmap.block_size} </BlockSize>",
        "",
        "    <!-- Count of blocks in the image file -->",
        f"    <BlocksCount> {bmap.blocks_count} </BlocksCount>",
        "",
        f"    <!-- Count of mapped blocks: {human_size(bmap.mapped_blocks * bmap.block_size)} or {pct:.1f}% -->",
        f"    <MappedBlocksCount> {bmap.mapped_blocks} </MappedBlocksCount>",
        "",
        "    <!-- Type of checksum used in this file -->",
        "    <ChecksumType> sha256 </ChecksumType>",
        "",
        "    <!-- The checksum of this bmap file. When it is calculated, the value of",
        '         the checksum has be zero (all ASCII "0" symbols).  -->',
        f"    <BmapFileChecksum> {'0' * 64} </BmapFileChecksum>",
        "",
        "    <!-- The block map: ranges of blocks, or single blocks; 'chksum' is the",
        "         sha256 of the range's bytes. -->",
        "    <BlockMap>",
    ]
    for r in bmap.ranges:
        span = f"{r.first}-{r.last}" if r.first != r.last else f"{r.first}"
        lines.append(f'        <Range chksum="{r.checksum}"> {span} </Range>')
    lines += ["    </BlockMap>", "</bmap>", ""]
    text = "\n".join(lines)
    digest = hashlib.sha256(text.encode()).hexdigest()
    return text.replace("0" * 64, digest, 1)


def blocks_of(
    extents: list[tuple[int, int]], image_size: int, block_size: int = DEFAULT_BLOCK,
) -> list[tuple[int, int]]:
    """Byte extents [start, end) as merged inclusive block ranges, rounded outwards to whole
    blocks and clipped to the image."""
    out: list[tuple[int, int]] = []
    for start, stop in sorted(extents):
        end = min(stop, image_size)
        if end <= start:
            continue
        first, last = start // block_size, (end - 1) // block_size
        if out and first <= out[-1][1] + 1:
            out[-1] = (out[-1][0], max(out[-1][1], last))
        else:
            out.append((first, last))
    return out
