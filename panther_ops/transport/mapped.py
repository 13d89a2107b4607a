"""Block-mapped I/O: write only an image's mapped byte spans to a device, read them back hashed,
and read what a block map is computed from (a sparse file's data extents; a compressed image's
decompressed bytes at given offsets).

The writer reads the whole image once, in order (decompressing, in ``blockdev.ChunkReader``'s
thread), hashing the image *file* as it is read and each mapped span as it passes; it writes
only the spans. As ``blockdev.write_image`` does, the first MiB is zeroed first and written
last: when a checksum does not match (a span's, from the map; the file's, at its end) the write
stops with ``ImageCorrupt`` before the partition table is written, so the card cannot boot a
half-written image.
"""

from __future__ import annotations

import contextlib
import fcntl
import hashlib
import io
import os
import time
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any, BinaryIO

from panther_ops.transport.blockdev import (
    BLKRRPART,
    CHUNK,
    HEAD,
    ChunkReader,
    Progress,
    first_diff,
    open_device,
    open_image,
    read_device_chunks,
    write_at,
    write_head,
)

Spans = list[tuple[int, int]]


class ImageCorrupt(Exception):
    """The image's bytes do not match its checksum: the write was stopped."""


class _HashedFile(io.RawIOBase):
    """A file read through, hashed as it is read (the compressed file under a decompressor)."""

    def __init__(self, fh: BinaryIO) -> None:
        self.fh = fh
        self.digest = hashlib.sha256()
        self.bytes_read = 0

    def readable(self) -> bool:
        return True

    def readinto(self, b: Any) -> int:
        n = self.fh.readinto(b)  # type: ignore[attr-defined]
        if n:
            self.digest.update(memoryview(b)[:n])
            self.bytes_read += n
        return int(n or 0)

    def drain(self) -> None:
        """Read (and hash) whatever the decompressor left unread."""
        while data := self.fh.read(CHUNK):
            self.digest.update(data)
            self.bytes_read += len(data)


@contextlib.contextmanager
def _hashed_image(path: str, fmt: str) -> Iterator[tuple[BinaryIO, _HashedFile]]:
    with open(path, "rb", buffering=0) as raw:
        hashed = _HashedFile(raw)
        buffered = io.BufferedReader(hashed, CHUNK)
        if fmt == "xz":
            import lzma

            with lzma.open(buffered, "rb") as fh:
                yield fh, hashed  # type: ignore[misc]
        elif fmt == "gz":
            import gzip

            with gzip.open(buffered, "rb") as fh:
                yield fh, hashed  # type: ignore[misc]
        else:
            yield buffered, hashed
        hashed.drain()


@dataclass
class MappedWrite:
    image_bytes: int
    """Bytes of the (decompressed) image read."""
    bytes_written: int
    seconds: float
    direct: bool
    file_sha256: str
    span_sha256: list[str]
    """The sha256 of each span's bytes, as written."""


def _check_span(i: int, spans: Spans, digest: Any, expected: list[str | None], names: list[str]) -> None:
    want = expected[i] if i < len(expected) else None
    if want is not None and digest.hexdigest() != want:
        start, end = spans[i]
        raise ImageCorrupt(f"{names[i]} (bytes {start}-{end - 1}) of the image has checksum {digest.hexdigest()}, "
                           f"the block map says {want}")


def write_mapped(
    device: str, path: str, fmt: str, size: int, spans: Spans, block: int, *,
    expected: list[str | None], kind: str | None, names: list[str], file_sha256: str | None,
    progress: Progress | None = None,
) -> MappedWrite:
    """Write the image's ``spans`` (sorted, disjoint, [start, end) bytes) to ``device``; each
    span's bytes are checked against ``expected`` (hashes of ``kind``) as they pass, the image
    file against ``file_sha256`` at its end. ImageCorrupt: stopped, the first MiB left zeroed."""
    start_time = time.monotonic()
    mapped_total = sum(e - s for s, e in spans)
    fd, direct = open_device(device, os.O_WRONLY)
    head = bytearray(min(HEAD, size))
    written = offset = reported = 0
    i = 0
    sha = [hashlib.sha256() for _ in spans]
    check = [hashlib.new(kind) for _ in spans] if kind and kind != "sha256" else sha
    try:
        write_head(fd, direct, device, bytes(len(head)), block)
        with _hashed_image(path, fmt) as (stream, hashed):
            reader = ChunkReader(stream)
            try:
                for view in reader.chunks():
                    end = offset + len(view)
                    while i < len(spans) and spans[i][0] < end:
                        a, b = max(spans[i][0], offset), min(spans[i][1], end)
                        part = view[a - offset:b - offset]
                        sha[i].update(part)
                        if check is not sha:
                            check[i].update(part)
                        keep = max(0, min(HEAD - a, b - a))
                        head[a:a + keep] = part[:keep]
                        if keep < b - a:
                            write_at(fd, direct, device, part[keep:], a + keep, block)
                        written += b - a
                        if b < spans[i][1]:
                            break
                        _check_span(i, spans, check[i], expected, names)
                        i += 1
                    offset = end
                    if progress and written != reported:
                        progress("write", written, mapped_total)
                        reported = written
            finally:
                reader.close()
        if offset != size:
            raise ImageCorrupt(f"the image gave {offset} bytes, {size} were expected")
        got = hashed.digest.hexdigest()
        if file_sha256 is not None and got != file_sha256:
            raise ImageCorrupt(f"the image file's sha256 is {got}, expected {file_sha256}")
        os.fsync(fd)
        write_head(fd, direct, device, head, block)
        with contextlib.suppress(OSError):
            fcntl.ioctl(fd, BLKRRPART)
    except ImageCorrupt:
        with contextlib.suppress(OSError):
            os.fsync(fd)
        raise
    finally:
        os.close(fd)
    return MappedWrite(offset, written, time.monotonic() - start_time, direct, got,
                       [h.hexdigest() for h in sha])


def device_span_hashes(device: str, spans: Spans, kind: str = "sha256", progress: Progress | None = None) -> list[str]:
    """The hash of each of the device's ``spans``, read with O_DIRECT (not from the page cache)."""
    out: list[str] = []
    total = sum(e - s for s, e in spans)
    done = 0
    chunks = read_device_chunks(device, 0, spans)
    try:
        for start, end in spans:
            h = hashlib.new(kind)
            left = end - start
            while left > 0:
                view, _ = next(chunks)
                h.update(view)
                left -= len(view)
                done += len(view)
                if progress:
                    progress("verify", done, total)
            out.append(h.hexdigest())
    finally:
        chunks.close()
    return out


def image_span_hashes(path: str, fmt: str, spans: Spans, kind: str = "sha256",
                      progress: Progress | None = None, phase: str = "image") -> list[str]:
    """The hash of each of the image's ``spans`` (a raw image is read only there; a compressed
    one is decompressed from its start)."""
    out: list[str] = []
    total = sum(e - s for s, e in spans)
    done = 0
    with open_image(path, fmt) as fh:
        pos = 0
        for start, end in spans:
            pos = _skip(fh, fmt, pos, start)
            h = hashlib.new(kind)
            while pos < end:
                data = fh.read(min(CHUNK, end - pos))
                if not data:
                    raise OSError(f"{path}: the image ended at byte {pos}, inside a mapped range")
                h.update(data)
                pos += len(data)
                done += len(data)
                if progress:
                    progress(phase, done, total)
            out.append(h.hexdigest())
    return out


def _skip(fh: BinaryIO, fmt: str, pos: int, to: int) -> int:
    if fmt == "raw":
        fh.seek(to)
        return to
    while pos < to:
        data = fh.read(min(CHUNK, to - pos))
        if not data:
            break
        pos += len(data)
    return pos


def first_difference(device: str, path: str, fmt: str, span: tuple[int, int]) -> int | None:
    """The first byte of ``span`` where the device differs from the image (None: identical)."""
    start, end = span
    with open_image(path, fmt) as fh:
        _skip(fh, fmt, 0, start)
        pos = start
        chunks = read_device_chunks(device, 0, [span])
        try:
            for view, _ in chunks:
                want = fh.read(len(view))
                if want != view:
                    return pos + first_diff(want, view)
                pos += len(view)
        finally:
            chunks.close()
    return None if pos >= end else pos


def data_extents(path: str) -> Spans | None:
    """The data extents of a sparse file (SEEK_DATA/SEEK_HOLE, as bmaptool's Filemap), or None
    when it has no holes (or the file system cannot tell)."""
    size = os.path.getsize(path)
    out: Spans = []
    with open(path, "rb") as fh:
        fd = fh.fileno()
        pos = 0
        try:
            while pos < size:
                try:
                    data = os.lseek(fd, pos, os.SEEK_DATA)
                except OSError:  # ENXIO: no data after pos
                    break
                hole = os.lseek(fd, data, os.SEEK_HOLE)
                out.append((data, min(hole, size)))
                pos = hole
        except OSError:
            return None
    if sum(e - s for s, e in out) >= size:
        return None
    return out


class StreamAt:
    """Reads at offsets of a compressed image's decompressed bytes: forward in one pass
    (decompressing again from the start when asked for an earlier offset)."""

    def __init__(self, path: str, fmt: str) -> None:
        self.path, self.fmt = path, fmt
        self.stack = contextlib.ExitStack()
        self.fh: BinaryIO | None = None
        self.pos = 0
        self.restarts = 0

    def __enter__(self) -> StreamAt:
        return self

    def __exit__(self, *exc: object) -> None:
        self.stack.close()

    def read(self, offset: int, size: int) -> bytes:
        if self.fh is None or offset < self.pos:
            self.stack.close()
            self.stack = contextlib.ExitStack()
            self.fh = self.stack.enter_context(open_image(self.path, self.fmt))
            self.pos = 0
            self.restarts += 1
        self.pos = _skip(self.fh, self.fmt, self.pos, offset)
        data = self.fh.read(size) if self.pos == offset else b""
        self.pos += len(data)
        return data
