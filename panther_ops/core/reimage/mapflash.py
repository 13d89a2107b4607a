"""Block-mapped `reimage flash`/`verify`/`bmap`: only the image's mapped ranges are written and
read back (docs/reimage.md, "Block-mapped flashing").

The map comes from a bmaptool ``.bmap`` (``--bmap``, or found beside the image as bmaptool finds
it: IMAGE.bmap, then with one extension after another taken off), else it is computed from the
image (``mapping.compute_map``: partition table, ext4/FAT allocation, sparse holes). The image's
own checksum (IMAGE.sha256 / --sha256) and the map's range checksums are checked as the image
is read for the write; a mismatch stops the write before the partition table is written
(``transport.mapped.ImageCorrupt``).
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, field
from typing import Any

from panther_ops.core.reimage.bmap import BlockMap, BlockRange, blocks_of, parse_bmap
from panther_ops.core.reimage.flash import Image, device_json
from panther_ops.core.reimage.mapping import compute_map
from panther_ops.errors import UsageError
from panther_ops.transport import blockdev, mapped
from panther_ops.transport.blockdev import DeviceFacts, Progress

COMPRESSED = (".xz", ".gz")


def find_bmap(image_path: str, given: str | None) -> str | None:
    """The bmap file to use: ``given`` (which must exist), else as bmaptool discovers one."""
    if given:
        if not os.path.isfile(given):
            raise UsageError(f"--bmap {given}: no such file")
        return given
    path = image_path
    while True:
        if os.path.isfile(path + ".bmap"):
            return path + ".bmap"
        path, ext = os.path.splitext(path)
        if not ext:
            return None


def default_bmap_path(image_path: str) -> str:
    """Where `reimage bmap` writes: beside the image, named after the decompressed image
    (panther.img.xz -> panther.img.bmap), as `bmaptool create panther.img` is used."""
    base = image_path
    for ext in COMPRESSED:
        if base.lower().endswith(ext):
            base = base[: -len(ext)]
    return base + ".bmap"


@dataclass
class Plan:
    """What is written and read back: byte spans with their names and expected checksums."""

    source: str
    block_size: int
    spans: list[tuple[int, int]]
    names: list[str]
    expected: list[str | None]
    kind: str | None
    notes: list[str] = field(default_factory=list)
    regions: list[dict[str, object]] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def mapped_bytes(self) -> int:
        return sum(e - s for s, e in self.spans)

    def to_json(self, image_size: int) -> dict[str, Any]:
        return {"source": self.source, "block_size": self.block_size, "ranges": len(self.spans),
                "bytes_mapped": self.mapped_bytes, "image_bytes": image_size,
                "mapped_percent": round(100 * self.mapped_bytes / image_size, 1) if image_size else None,
                "checksum_type": self.kind, "notes": self.notes, "partitions": self.regions,
                "seconds": round(self.seconds, 3)}


def _from_block_map(bm: BlockMap, source: str) -> Plan:
    spans = [bm.byte_span(r) for r in bm.ranges]
    names = [f"blocks {r.first}-{r.last}" if r.first != r.last else f"block {r.first}" for r in bm.ranges]
    kind = bm.checksum_type if any(r.checksum for r in bm.ranges) else None
    notes = [] if kind else [f"{source} has no range checksums (bmap version {bm.version}): the ranges "
                             "are read back against the image's bytes' sha256"]
    return Plan(source, bm.block_size, spans, names, [r.checksum for r in bm.ranges], kind, notes)


def load_bmap(path: str, image: Image) -> BlockMap:
    bm = parse_bmap(blockdev.read_at(path, 0, 64 << 20), path)
    if bm.image_size != image.size:
        raise UsageError(f"{path}: the block map is of an image of {bm.image_size} bytes, {image.path} has "
                         f"{image.size}: not this image's map")
    return bm


def computed_map(image: Image, progress: Progress | None = None) -> Plan:
    """The map of an image from its own bytes (a compressed one is decompressed for it)."""
    start = time.monotonic()
    if image.fmt == "raw":
        data = mapped.data_extents(image.path)
        m = compute_map(lambda offset, size: blockdev.read_at(image.path, offset, size), image.size, data)
        how = "computed from the image's partition table and file systems"
    else:
        if progress:
            progress("mapping", 0, None)
        with mapped.StreamAt(image.path, image.fmt) as stream:
            m = compute_map(stream.read, image.size)
        how = ("computed from the image's partition table and file systems (decompressed once for it: "
               "`reimage bmap` writes a .bmap beside it to save that pass)")
    block = 4096
    ranges = blocks_of(m.extents, image.size, block)
    bm = BlockMap(image.size, block, tuple(BlockRange(a, b) for a, b in ranges), None)
    plan = _from_block_map(bm, how)
    plan.notes = m.notes
    plan.regions = m.regions
    plan.seconds = time.monotonic() - start
    return plan


def read_map(image: Image, bmap_path: str | None, progress: Progress | None = None) -> Plan:
    """The map to write: the block map file ``bmap_path``, else one computed from the image's bytes."""
    if bmap_path is None:
        return computed_map(image, progress)
    start = time.monotonic()
    bm = load_bmap(bmap_path, image)
    plan = _from_block_map(bm, f"{bmap_path} (bmap version {bm.version})")
    plan.seconds = time.monotonic() - start
    return plan


@dataclass(frozen=True)
class MapVerdict:
    device: str
    ranges: int
    bytes: int
    bad: list[str]
    """The names of the ranges that differ."""
    first_difference: int | None
    seconds: float
    against: str

    @property
    def ok(self) -> bool:
        return not self.bad

    @property
    def message(self) -> str:
        if self.ok:
            return (f"{self.device}: all {self.ranges} mapped ranges ({self.bytes} bytes) read back as the image "
                    f"({self.against})")
        where = (f"first difference at byte {self.first_difference} (0x{self.first_difference:x})"
                 if self.first_difference is not None else "no differing byte found on a second read")
        more = f" and {len(self.bad) - 1} more range(s)" if len(self.bad) > 1 else ""
        return f"{self.device}: differs from the image in {self.bad[0]}{more}: {where} ({self.against})"

    def to_json(self) -> dict[str, Any]:
        return {"ok": self.ok, "device": self.device, "ranges": self.ranges, "bytes": self.bytes,
                "compared": self.against, "bad_ranges": self.bad, "first_difference": self.first_difference,
                "seconds": round(self.seconds, 3),
                "mib_per_s": round(self.bytes / (1 << 20) / self.seconds, 1) if self.seconds > 0 else None}


def _read_back(image: Image, device: str, plan: Plan, expected: list[str], kind: str, against: str,
               progress: Progress | None) -> MapVerdict:
    start = time.monotonic()
    got = mapped.device_span_hashes(device, plan.spans, kind, progress)
    bad = [i for i, (g, w) in enumerate(zip(got, expected, strict=True)) if g != w]
    first = mapped.first_difference(device, image.path, image.fmt, plan.spans[bad[0]]) if bad else None
    return MapVerdict(device, len(plan.spans), plan.mapped_bytes, [plan.names[i] for i in bad], first,
                      time.monotonic() - start, against)


@dataclass(frozen=True)
class MapFlashed:
    image: Image
    device: DeviceFacts
    plan: Plan
    write: mapped.MappedWrite | None
    verdict: MapVerdict | None
    stopped: str | None = None
    """Why the write was stopped (the image did not match a checksum): the card is not bootable."""

    def to_json(self) -> dict[str, Any]:
        w = self.write
        return {
            "image": self.image.to_json(),
            "device": device_json(self.device),
            "map": self.plan.to_json(self.image.size),
            "write": None if w is None else {
                "bytes_read": w.image_bytes, "bytes_written": w.bytes_written, "seconds": round(w.seconds, 3),
                "direct": w.direct, "file_sha256": w.file_sha256,
                "mib_per_s": round(w.bytes_written / (1 << 20) / w.seconds, 1) if w.seconds > 0 else None},
            "verify": None if self.verdict is None else self.verdict.to_json(),
            "stopped": self.stopped,
        }


def flash_mapped(image: Image, facts: DeviceFacts, plan: Plan, progress: Progress | None = None) -> MapFlashed:
    """Write the mapped ranges (checking the image as it is read), then read them back."""
    try:
        w = mapped.write_mapped(facts.real_path, image.path, image.fmt, image.size, plan.spans, facts.logical_block,
                                expected=plan.expected, kind=plan.kind, names=plan.names,
                                file_sha256=image.expected_sha256, progress=progress)
    except mapped.ImageCorrupt as exc:
        return MapFlashed(image, facts, plan, None, None, str(exc))
    against = "the sha256 of each range as written" + (f", checked against {plan.source}" if plan.kind else "")
    verdict = _read_back(image, facts.path, plan, w.span_sha256, "sha256", against, progress)
    return MapFlashed(image, facts, plan, w, verdict)


def verify_mapped(image: Image, device: str, plan: Plan, progress: Progress | None = None) -> MapVerdict:
    """`reimage verify` with a map: each mapped range of the device against the map's checksum
    (without one: the image's bytes of that range, hashed)."""
    from panther_ops.core.reimage.device import verify_refusals

    facts = blockdev.device_facts(device)
    why = verify_refusals(facts, image.size)
    if why:
        raise UsageError("cannot verify: " + "; ".join(why))
    if plan.kind and all(e is not None for e in plan.expected):
        expected = [e or "" for e in plan.expected]
        return _read_back(image, facts.path, plan, expected, plan.kind, f"{plan.kind} of each range from {plan.source}",
                          progress)
    expected = mapped.image_span_hashes(image.path, image.fmt, plan.spans, "sha256", progress, "image")
    return _read_back(image, facts.path, plan, expected, "sha256", "sha256 of each range of the image", progress)


def build_bmap(image: Image, progress: Progress | None = None) -> tuple[BlockMap, Plan]:
    """`reimage bmap`: the computed map with the sha256 of each range."""
    plan = computed_map(image, progress)
    hashes = mapped.image_span_hashes(image.path, image.fmt, plan.spans, "sha256", progress, "image")
    block = plan.block_size
    ranges = tuple(BlockRange(s // block, (e - 1) // block, h) for (s, e), h in zip(plan.spans, hashes, strict=True))
    return BlockMap(image.size, block, ranges, "sha256"), plan
