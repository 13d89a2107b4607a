"""`reimage flash` and `reimage verify`: the steps, in order, on this machine's card reader.

The image first, whatever the device: its name and format, its expected checksum, its sha256
checked against it, then its decompressed size → judge the device → confirm → write
(``transport.blockdev``) → read back and compare. A bad image is named before anything about
the device is read. Refusals raise UsageError before anything is written; progress goes to the
caller's callback.
"""

from __future__ import annotations

import os
import time
import zlib
from dataclasses import dataclass
from typing import Any

from panther_ops.core.reimage.device import describe, refusals, verify_refusals
from panther_ops.core.reimage.image import detect_format, normalise_sha256, sha256_from_file, xz_uncompressed_size
from panther_ops.core.reimage.verify import Verdict
from panther_ops.errors import UsageError
from panther_ops.transport import blockdev
from panther_ops.transport.blockdev import DeviceFacts, Progress


@dataclass(frozen=True)
class Image:
    path: str
    fmt: str
    size: int
    file_bytes: int
    expected_sha256: str | None
    checksum_from: str | None
    file_sha256: str | None = None
    """The file's sha256, computed and found equal to ``expected_sha256`` (None: not checked)."""

    def to_json(self) -> dict[str, Any]:
        return {"path": self.path, "format": self.fmt, "bytes": self.size, "file_bytes": self.file_bytes,
                "sha256": self.expected_sha256, "checksum_from": self.checksum_from}


def inspect_image(
    path: str, sha256: str | None, *, require_checksum: bool, progress: Progress | None = None,
    check_now: bool = True,
) -> Image:
    """The image's format, expected sha256 (from ``sha256`` or IMAGE.sha256; required with
    ``require_checksum``), the file's sha256 checked against it, then its decompressed size,
    in that order: a wrong checksum is named before a compressed image is decompressed, and
    before anything about a device is read. UsageError naming the image. Without
    ``check_now`` the expected sha256 is only read (block-mapped flashing checks it as the
    image is written)."""
    if not os.path.exists(path):
        raise UsageError(f"{path}: no such image file")
    if not os.path.isfile(path):
        raise UsageError(f"{path}: not a regular file")
    fmt = detect_format(path, blockdev.read_at(path, 0, 8))
    expected, source = None, None
    sidecar = path + ".sha256"
    if sha256:
        expected, source = normalise_sha256(sha256, "--sha256"), "--sha256"
    elif os.path.isfile(sidecar):
        with open(sidecar, encoding="utf-8", errors="replace") as fh:
            expected, source = sha256_from_file(fh.read(), path, sidecar), sidecar
    elif require_checksum:
        raise UsageError(f"{path}: no checksum to check it against: give --sha256 HASH or put "
                         f"{os.path.basename(sidecar)} beside it")
    file_bytes = os.path.getsize(path)
    actual = None
    if expected is not None and check_now:
        actual = _sha256_checked(path, expected, source, progress)
    if fmt == "raw":
        size = file_bytes
    elif fmt == "xz":
        size = xz_uncompressed_size(lambda off, n: blockdev.read_at(path, off, n), file_bytes, path)
    else:
        try:
            size = blockdev.gz_size(path, progress)
        except (EOFError, OSError, zlib.error) as exc:
            raise UsageError(f"{path}: not a readable .gz file ({exc}): refused, nothing was written") from exc
    if size == 0:
        raise UsageError(f"{path}: the image is empty")
    return Image(path, fmt, size, file_bytes, expected, source, actual)


def _sha256_checked(path: str, expected: str, source: str | None, progress: Progress | None) -> str:
    actual = blockdev.file_sha256(path, progress)
    if actual != expected:
        raise UsageError(f"{path}: sha256 is {actual} but {source} says {expected}: refused, nothing was written")
    return actual


def check_sha256(image: Image, progress: Progress | None = None) -> str:
    """The image file's sha256, which must be the expected one (else UsageError: nothing written);
    computed once (``inspect_image`` checks it when the expected one is known)."""
    if image.file_sha256 is not None:
        return image.file_sha256
    if image.expected_sha256 is None:
        return blockdev.file_sha256(image.path, progress)
    return _sha256_checked(image.path, image.expected_sha256, image.checksum_from, progress)


def eligible_device(device: str, image: Image) -> DeviceFacts:
    """The device's facts when it may be overwritten with ``image``; else UsageError naming why."""
    facts = blockdev.device_facts(device)
    why = refusals(facts, image.size)
    if why:
        raise UsageError("refused, nothing was written: " + "; ".join(why))
    return facts


@dataclass(frozen=True)
class Flashed:
    image: Image
    device: DeviceFacts
    image_file_sha256: str
    write: blockdev.WriteResult
    verdict: Verdict

    def to_json(self) -> dict[str, Any]:
        w = self.write
        return {
            "image": {**self.image.to_json(), "file_sha256": self.image_file_sha256,
                      "data_sha256": w.sha256},
            "device": device_json(self.device),
            "write": {"bytes": w.bytes_written, "seconds": round(w.seconds, 3), "direct": w.direct,
                      "mib_per_s": round(w.bytes_written / (1 << 20) / w.seconds, 1) if w.seconds > 0 else None},
            "verify": self.verdict.to_json(),
        }


def device_json(facts: DeviceFacts) -> dict[str, Any]:
    return {"path": facts.path, "bytes": facts.size_bytes, "model": facts.model, "description": describe(facts)}


def flash(
    image: Image, facts: DeviceFacts, file_sha256: str, progress: Progress | None = None,
) -> Flashed:
    """Write the (checked) image to the (judged, confirmed) device, then read it back."""
    raw = image.fmt == "raw"  # its data's sha256 is the file's, already checked
    with blockdev.open_image(image.path, image.fmt) as stream:
        written = blockdev.write_image(facts.real_path, stream, image.size, facts.logical_block, progress,
                                       digest=not raw)
    if raw:
        written.sha256 = file_sha256
    if written.bytes_written != image.size:
        raise UsageError(f"{image.path}: the image gave {written.bytes_written} bytes, its index says {image.size}")
    return Flashed(image, facts, file_sha256, written, read_back(image, facts, written.sha256, progress))


def read_back(image: Image, facts: DeviceFacts, data_sha256: str, progress: Progress | None = None) -> Verdict:
    """The device's first image-size bytes against the image's, byte for byte (the image read
    again, decompressed in a thread beside the device reads): identical, or the first differing
    byte. Nothing is hashed: the image's data sha256 was known before writing."""
    start = time.monotonic()
    with blockdev.open_image(image.path, image.fmt) as stream:
        first = blockdev.compare_bytes(facts.real_path, stream, image.size, progress)
    return Verdict(facts.path, image.size, data_sha256, None, first, time.monotonic() - start)


def verify(image: Image, device: str, progress: Progress | None = None) -> Verdict:
    """`reimage verify`: the device (mounted or not: it is only read) against the image."""
    facts = blockdev.device_facts(device)
    why = verify_refusals(facts, image.size)
    if why:
        raise UsageError("cannot verify: " + "; ".join(why))
    start = time.monotonic()
    with blockdev.open_image(image.path, image.fmt) as stream:
        cmp = blockdev.compare(facts.real_path, stream, image.size, progress)
    return Verdict(facts.path, image.size, cmp.image_sha256, cmp.device_sha256, cmp.first_difference,
                   time.monotonic() - start)

