"""Block devices of this machine: what they are (sysfs, mountinfo) and writing/reading them.

Only facts are gathered here (``device_facts``); whether a device may be written is decided
by ``panther_ops.core.reimage.device`` from them. The writer opens the device exclusively
(``O_EXCL``: the kernel refuses a device that is mounted or held), with ``O_DIRECT`` in large
page-aligned chunks (falling back to buffered writes where the device refuses ``O_DIRECT``),
writes zeros over the first MiB first, the rest of the image, then the first MiB last, and
syncs after each step, so an interrupted write never leaves a partition table pointing at
half-written data.

Size (~500 lines): every side effect on a block device is here, by the layer rule (facts,
the exclusive direct writer, the read-back and byte comparison), and nothing else.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import mmap
import os
import queue
import stat
import threading
import time
from collections.abc import Callable, Generator, Iterator
from dataclasses import dataclass, field
from typing import BinaryIO

CHUNK = 8 << 20
"""Bytes per write/read: large, a multiple of every logical block size."""
HEAD = 1 << 20
"""The first MiB (partition table, boot sectors): written last."""
SYSFS = "/sys/class/block"
BLKRRPART = 0x125F
"""ioctl: re-read the partition table."""

Progress = Callable[[str, int, "int | None"], None]
"""progress(phase, bytes done, bytes in all or None)."""


@dataclass(frozen=True)
class Mount:
    devno: str
    source: str
    mount_point: str


@dataclass
class DeviceFacts:
    """What this machine says about a path given as a device (nothing is judged here)."""

    path: str
    real_path: str
    exists: bool = False
    is_block: bool = False
    is_regular: bool = False
    name: str = ""
    devno: str = ""
    is_partition: bool = False
    parent: str | None = None
    size_bytes: int = 0
    logical_block: int = 512
    model: str = ""
    read_only: bool = False
    partitions: list[str] = field(default_factory=list)
    holders: list[str] = field(default_factory=list)
    mounts: list[Mount] = field(default_factory=list)
    swaps: list[str] = field(default_factory=list)
    holds_root: bool = False


def _read(path: str) -> str:
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            return fh.read().strip()
    except OSError:
        return ""


def _mountinfo() -> list[Mount]:
    mounts = []
    for line in _read("/proc/self/mountinfo").splitlines():
        left, _, right = line.partition(" - ")
        parts, rparts = left.split(), right.split()
        if len(parts) < 5 or len(rparts) < 2:
            continue
        mounts.append(Mount(parts[2], _unescape(rparts[1]), _unescape(parts[4])))
    return mounts


def _unescape(text: str) -> str:
    """mountinfo's octal escapes (a space is \\040)."""
    return text.encode("latin-1").decode("unicode_escape") if "\\" in text else text


def _sys_name(devno: str) -> str:
    return os.path.basename(os.path.realpath(f"/sys/dev/block/{devno}"))


def _related(name: str) -> tuple[list[str], list[str], set[str]]:
    """(partitions, holders, every sysfs name whose use makes ``name`` busy)."""
    base = f"{SYSFS}/{name}"
    parts = sorted(p for p in _listdir(base) if os.path.exists(f"{base}/{p}/partition"))
    seen: set[str] = set()
    holders: list[str] = []
    todo = [name, *parts]
    while todo:
        n = todo.pop()
        if n in seen:
            continue
        seen.add(n)
        for h in _listdir(f"{SYSFS}/{n}/holders"):
            if h not in seen:
                holders.append(h)
                todo.append(h)
    return parts, sorted(set(holders)), seen


def _listdir(path: str) -> list[str]:
    try:
        return os.listdir(path)
    except OSError:
        return []


def _model(name: str) -> str:
    base = f"{SYSFS}/{name}"
    backing = _read(f"{base}/loop/backing_file")
    if backing:
        return f"loop device of {backing}"
    words = [_read(f"{base}/device/vendor"), _read(f"{base}/device/model")]
    text = " ".join(w for w in words if w)
    return text or _read(f"{base}/device/name") or "unknown model"


def device_facts(path: str) -> DeviceFacts:
    """Everything needed to judge ``path`` as a target: sysfs, /proc/self/mountinfo, /proc/swaps."""
    real = os.path.realpath(path)
    facts = DeviceFacts(path=path, real_path=real)
    try:
        st = os.stat(real)
    except OSError:
        return facts
    facts.exists = True
    facts.is_regular = stat.S_ISREG(st.st_mode)
    facts.is_block = stat.S_ISBLK(st.st_mode)
    if not facts.is_block:
        return facts
    facts.devno = f"{os.major(st.st_rdev)}:{os.minor(st.st_rdev)}"
    facts.name = _sys_name(facts.devno)
    base = f"{SYSFS}/{facts.name}"
    facts.is_partition = os.path.exists(f"{base}/partition")
    if facts.is_partition:
        facts.parent = os.path.basename(os.path.dirname(os.path.realpath(base)))
    facts.size_bytes = int(_read(f"{base}/size") or 0) * 512
    facts.logical_block = int(_read(f"{base}/queue/logical_block_size") or 512)
    facts.read_only = _read(f"{base}/ro") == "1"
    facts.model = _model(facts.parent if facts.parent else facts.name)
    facts.partitions, facts.holders, busy = _related(facts.name)
    busy_devnos = {_read(f"{SYSFS}/{n}/dev") for n in busy}
    busy_paths = {f"/dev/{n}" for n in busy}
    root_dev = os.stat("/").st_dev
    root_devno = f"{os.major(root_dev)}:{os.minor(root_dev)}"
    for m in _mountinfo():
        source = os.path.realpath(m.source) if m.source.startswith("/dev/") else m.source
        if m.devno in busy_devnos or source in busy_paths:
            facts.mounts.append(m)
            if m.mount_point == "/":
                facts.holds_root = True
    if root_devno in busy_devnos:
        facts.holds_root = True
    for line in _read("/proc/swaps").splitlines()[1:]:
        src = line.split()[0] if line.split() else ""
        if src and os.path.realpath(src) in busy_paths:
            facts.swaps.append(src)
    return facts


# --- the image's bytes ------------------------------------------------------------------


def file_sha256(path: str, progress: Progress | None = None, phase: str = "checksum") -> str:
    """The sha256 of a file: one thread reads while this one hashes."""
    h = hashlib.sha256()
    total = os.path.getsize(path)
    done = 0
    with open(path, "rb", buffering=0) as fh:
        reader = ChunkReader(fh)
        try:
            for view in reader.chunks():
                h.update(view)
                done += len(view)
                if progress:
                    progress(phase, done, total)
        finally:
            reader.close()
    return h.hexdigest()


def read_at(path: str, offset: int, size: int) -> bytes:
    """``size`` bytes of a file from ``offset`` (negative: from the end)."""
    with open(path, "rb") as fh:
        fh.seek(offset, os.SEEK_END if offset < 0 else os.SEEK_SET)
        return fh.read(size)


@contextlib.contextmanager
def open_image(path: str, fmt: str) -> Iterator[BinaryIO]:
    """The image's decompressed bytes as a stream (``fmt``: raw, xz or gz)."""
    if fmt == "xz":
        import lzma

        with lzma.open(path, "rb") as fh:
            yield fh  # type: ignore[misc]
    elif fmt == "gz":
        import gzip

        with gzip.open(path, "rb") as fh:
            yield fh  # type: ignore[misc]
    else:
        with open(path, "rb") as fh:
            yield fh


def gz_size(path: str, progress: Progress | None = None) -> int:
    """The decompressed size of a gzip file (its trailer holds it only modulo 4 GiB)."""
    total = 0
    with open_image(path, "gz") as fh:
        while data := fh.read(CHUNK):
            total += len(data)
            if progress:
                progress("size", total, None)
    return total


# --- writing and reading the device ------------------------------------------------------


class AlignedBuffer:
    """A page-aligned buffer (anonymous mmap), as O_DIRECT needs."""

    def __init__(self, size: int) -> None:
        self.mm = mmap.mmap(-1, size)
        self.view = memoryview(self.mm)

    def close(self) -> None:
        """Unmapped now, or when the last slice handed out is dropped."""
        with contextlib.suppress(BufferError):
            self.view.release()
            self.mm.close()


def open_device(path: str, flags: int, exclusive: bool = True) -> tuple[int, bool]:
    """(fd, direct): opened exclusively (the kernel refuses a mounted or held device), with
    O_DIRECT where the device accepts it."""
    base = flags | (os.O_EXCL if exclusive else 0) | getattr(os, "O_CLOEXEC", 0)
    direct = getattr(os, "O_DIRECT", 0)
    if direct:
        try:
            return os.open(path, base | direct), True
        except OSError as exc:
            if exc.errno != errno.EINVAL:
                raise
    return os.open(path, base), False


def _fill(stream: BinaryIO, view: memoryview) -> int:
    """Read into ``view`` until full or the stream ends."""
    got = 0
    while got < len(view):
        n = stream.readinto(view[got:])  # type: ignore[attr-defined]
        if not n:
            break
        got += n
    return int(got)


@dataclass
class WriteResult:
    bytes_written: int
    sha256: str
    seconds: float
    direct: bool


def _pwrite_all(fd: int, data: memoryview, offset: int) -> None:
    while len(data):
        n = os.pwrite(fd, data, offset)
        data, offset = data[n:], offset + n


def write_at(fd: int, direct: bool, path: str, data: memoryview, offset: int, block: int) -> None:
    """Write ``data`` at ``offset``; a tail that is not whole blocks goes through a buffered fd."""
    whole = len(data) - len(data) % block if direct else len(data)
    if whole:
        _pwrite_all(fd, data[:whole], offset)
    if whole < len(data):
        plain = os.open(path, os.O_WRONLY | getattr(os, "O_CLOEXEC", 0))
        try:
            _pwrite_all(plain, data[whole:], offset + whole)
            os.fsync(plain)
        finally:
            os.close(plain)


class ChunkReader:
    """A thread filling page-aligned buffers from the stream (decompressing; hashing when
    ``digest``) while the caller uses the ones already full; ``limit``: stop after that many
    bytes (reads stay whole 4 KiB blocks, as O_DIRECT needs)."""

    def __init__(self, stream: BinaryIO, *, limit: int | None = None, digest: bool = False, count: int = 3) -> None:
        self.stream = stream
        self.limit = limit
        self.bufs = [AlignedBuffer(CHUNK) for _ in range(count)]
        self.free: queue.Queue[int] = queue.Queue()
        self.full: queue.Queue[tuple[int, int] | BaseException | None] = queue.Queue()
        for i in range(count):
            self.free.put(i)
        self.digest = hashlib.sha256() if digest else None
        self.thread = threading.Thread(target=self._run, name="image-reader", daemon=True)

    def _run(self) -> None:
        done = 0
        try:
            while (i := self.free.get()) >= 0:
                want = CHUNK if self.limit is None else min(CHUNK, self.limit - done)
                if want <= 0:
                    break
                n = min(want, _fill(self.stream, self.bufs[i].view[: want + (-want % 4096)]))
                if n and self.digest is not None:
                    self.digest.update(self.bufs[i].view[:n])
                if n:
                    self.full.put((i, n))
                done += n
                if n < want:
                    break
            self.full.put(None)
        except BaseException as exc:  # handed to the consumer, which raises it
            self.full.put(exc)

    def chunks(self) -> Generator[memoryview, None, None]:
        """Each full buffer in turn; it is handed back to the reader when the next is asked for."""
        self.thread.start()
        while (item := self.full.get()) is not None:
            if isinstance(item, BaseException):
                raise item
            i, n = item
            yield self.bufs[i].view[:n]
            self.free.put(i)

    def close(self) -> None:
        self.free.put(-1)
        if self.thread.is_alive():
            self.thread.join()
        for b in self.bufs:
            b.close()


def write_head(fd: int, direct: bool, device: str, data: bytes | bytearray | memoryview, block: int) -> None:
    buf = AlignedBuffer(HEAD)
    try:
        buf.view[: len(data)] = data
        write_at(fd, direct, device, buf.view[: len(data)], 0, block)
    finally:
        buf.close()
    os.fsync(fd)


def write_image(
    device: str, stream: BinaryIO, size: int, block: int, progress: Progress | None = None, *, digest: bool = True,
) -> WriteResult:
    """Write the stream to ``device``: the first MiB zeroed, the rest, then the first MiB.

    ``digest``: hash what is written (WriteResult.sha256; else "": the caller knows it)."""
    start = time.monotonic()
    fd, direct = open_device(device, os.O_WRONLY)
    reader = ChunkReader(stream, digest=digest)
    head = bytearray()
    offset = 0
    try:
        write_head(fd, direct, device, bytes(min(HEAD, size)), block)
        for view in reader.chunks():
            n = len(view)
            keep = max(0, min(HEAD - offset, n))  # the first MiB is kept for the end
            head += view[:keep]
            if keep < n:
                write_at(fd, direct, device, view[keep:], offset + keep, block)
            offset += n
            if progress:
                progress("write", offset, size)
        os.fsync(fd)
        write_head(fd, direct, device, head, block)
        with contextlib.suppress(OSError):
            import fcntl

            fcntl.ioctl(fd, BLKRRPART)
    finally:
        os.close(fd)
        reader.close()
    sha = reader.digest.hexdigest() if reader.digest is not None else ""
    return WriteResult(offset, sha, time.monotonic() - start, direct)


def read_device_chunks(
    device: str, length: int, spans: list[tuple[int, int]] | None = None,
) -> Generator[tuple[memoryview, bool], None, None]:
    """The device's first ``length`` bytes (or its byte ``spans`` [start, end), in turn, each
    starting on a 4 KiB boundary) in chunks, read with O_DIRECT where accepted (never from the
    page cache: what is on the device, not what was written to it)."""
    fd, direct = open_device(device, os.O_RDONLY, exclusive=False)
    buf = AlignedBuffer(CHUNK)
    try:
        if not direct:
            with contextlib.suppress(OSError):
                os.posix_fadvise(fd, 0, 0, os.POSIX_FADV_DONTNEED)
        for start, end in spans if spans is not None else [(0, length)]:
            yield from _read_span(device, fd, direct, buf, start, end)
    finally:
        os.close(fd)
        buf.close()


def _read_span(
    device: str, fd: int, direct: bool, buf: AlignedBuffer, start: int, end: int,
) -> Generator[tuple[memoryview, bool], None, None]:
    offset = start
    while offset < end:
        want = min(CHUNK, end - offset)
        aligned = want if not direct or want % 4096 == 0 else want + (-want % 4096)
        n = os.preadv(fd, [buf.view[:aligned]], offset)
        if n <= 0:
            raise OSError(errno.EIO, f"{device}: read ended at byte {offset} of {end}")
        n = min(n, want)
        yield buf.view[:n], direct
        offset += n


def equal_bytes(a: memoryview, b: memoryview) -> bool:
    """Whether two equally long byte views hold the same bytes, compared 8 bytes at a time in C
    (a memoryview of format "B" is compared byte by byte through the struct codes)."""
    whole = len(a) - len(a) % 8
    if whole and a[:whole].cast("Q") != b[:whole].cast("Q"):
        return False
    return bytes(a[whole:]) == bytes(b[whole:])


def first_diff(a: bytes | memoryview, b: memoryview) -> int:
    """The first index where ``a`` and ``b`` differ (they do), halving with C comparisons."""
    n = min(len(a), len(b))
    a, b = memoryview(a)[:n], b[:n]
    lo, hi = 0, n
    if equal_bytes(a, b):
        return n
    while hi - lo > 64:  # a[lo:hi] differs from b[lo:hi]
        mid = (lo + hi) // 2
        if not equal_bytes(a[lo:mid], b[lo:mid]):
            hi = mid
        else:
            lo = mid
    return next(i for i in range(lo, hi) if a[i] != b[i])


def compare_bytes(device: str, stream: BinaryIO, length: int, progress: Progress | None = None) -> int | None:
    """The first offset where the device's first ``length`` bytes differ from the stream's (None:
    identical), compared chunk by chunk; the device is read with O_DIRECT where accepted, the
    stream (decompressed) by a thread beside those reads. OSError when the device is shorter."""
    reader = ChunkReader(stream, limit=length)
    done = 0
    pending = memoryview(b"")
    images = reader.chunks()
    device_chunks = read_device_chunks(device, length)
    try:
        for view, _ in device_chunks:
            pos = 0
            while pos < len(view):
                if not pending:
                    nxt = next(images, None)
                    if nxt is None:  # the image ended before its size: it differs from here
                        return done + pos
                    pending = nxt
                n = min(len(pending), len(view) - pos)
                if not equal_bytes(pending[:n], view[pos:pos + n]):
                    return done + pos + first_diff(pending[:n], view[pos:pos + n])
                pending, pos = pending[n:], pos + n
            done += len(view)
            if progress:
                progress("verify", done, length)
    finally:
        pending.release()
        device_chunks.close()
        images.close()
        reader.close()
    return None


@dataclass
class Comparison:
    image_sha256: str
    device_sha256: str
    first_difference: int | None


def compare(device: str, stream: BinaryIO, length: int, progress: Progress | None = None) -> Comparison:
    """Read the device and the image side by side: both sha256s and the first differing byte."""
    hi, hd = hashlib.sha256(), hashlib.sha256()
    first: int | None = None
    done = 0
    for view, _ in read_device_chunks(device, length):
        want = stream.read(len(view))
        hi.update(want)
        hd.update(view)
        if first is None and want != view:
            first = done + first_diff(want, view)
        done += len(view)
        if progress:
            progress("verify", done, length)
    return Comparison(hi.hexdigest(), hd.hexdigest(), first)
