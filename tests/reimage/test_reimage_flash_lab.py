"""`reimage flash`/`verify` on real loop devices the tests make (standing for SD cards).

Every block device written here is a loop device this module attached to a backing file in
its own tmp dir, and detached in teardown. The machine's root device is only ever *refused*
(with a wrong checksum besides, so even a broken refusal could not write to it).
Marked `lab`: without root or losetup/sfdisk/mkfs.ext4/mount they skip, and fail under CI=true.
"""

from __future__ import annotations

import contextlib
import gzip
import hashlib
import lzma
import os
import shutil
import subprocess
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from panther_ops.transport import blockdev
from tests.clirun import run_cli
from tests.conftest import skip_or_fail

pytestmark = pytest.mark.lab

MIB = 1 << 20
IMAGE_BYTES = 256 * MIB
TOOLS = ("losetup", "partx", "sfdisk", "mkfs.ext4", "mount", "umount")

MakeLoop = Callable[..., str]


def _sh(*argv: str, input: bytes | None = None) -> str:
    return subprocess.run(argv, check=True, capture_output=True, input=input).stdout.decode()


@pytest.fixture(scope="module")
def loop_ready() -> None:
    why = [f"missing binary {t}" for t in TOOLS if shutil.which(t) is None]
    if os.geteuid() != 0:
        why.insert(0, "loop devices need root")
    if why:
        skip_or_fail("; ".join(why))


@pytest.fixture
def loop(loop_ready: None, tmp_path: Path) -> Iterator[MakeLoop]:
    """make(size_bytes, partscan=False, backing=None) -> /dev/loopN on a file in tmp_path."""
    made: list[str] = []
    mounts: list[Path] = []

    def make(size: int, *, partscan: bool = False, backing: Path | None = None) -> str:
        if backing is None:
            backing = tmp_path / f"card{len(made)}.bin"
            with open(backing, "wb") as fh:
                fh.truncate(size)
        dev = _sh("losetup", "--find", "--show", *(["-P"] if partscan else []), str(backing)).strip()
        made.append(dev)
        if partscan and not list(Path(f"/sys/block/{Path(dev).name}").glob("*p1")):
            _sh("partx", "--update", dev)  # where the kernel did not scan the table on attaching
        return dev

    make.mounts = mounts  # type: ignore[attr-defined]
    yield make
    for m in mounts:
        subprocess.run(["umount", str(m)], check=False, capture_output=True)
    for dev in made:
        subprocess.run(["partx", "--delete", dev], check=False, capture_output=True)
        subprocess.run(["losetup", "-d", dev], check=False, capture_output=True)


def _partitioned_image(path: Path, tmp: Path) -> None:
    """256 MiB: a DOS partition table, an ext4 file system with files in partition 1 (1-200 MiB)."""
    with open(path, "wb") as fh:
        fh.truncate(IMAGE_BYTES)
    _sh("sfdisk", "--quiet", str(path), input=b"label: dos\nstart=2048, size=407552, type=83\n"
        b"start=409600, type=83\n")
    content = tmp / "rootfs"
    (content / "etc").mkdir(parents=True)
    (content / "etc" / "hostname").write_text("panther\n")
    (content / "home").mkdir()
    (content / "home" / "blob").write_bytes(os.urandom(8 * MIB))
    _sh("mkfs.ext4", "-q", "-F", "-E", f"offset={MIB}", "-d", str(content), str(path), f"{407552 // 2}k")


def _sidecar(path: Path) -> None:
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    Path(str(path) + ".sha256").write_text(f"{digest}  {path.name}\n")


@pytest.fixture(scope="module")
def images(loop_ready: None, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """random.img (256 MiB of random bytes), disk.img (partitioned, ext4) and disk.img.xz/.gz,
    each with its .sha256 beside it."""
    d = tmp_path_factory.mktemp("images")
    rnd = d / "random.img"
    with open(rnd, "wb") as fh:
        for _ in range(IMAGE_BYTES // (16 * MIB)):
            fh.write(os.urandom(16 * MIB))
    disk = d / "disk.img"
    _partitioned_image(disk, d)
    raw = disk.read_bytes()
    (d / "disk.img.xz").write_bytes(lzma.compress(raw, preset=0))
    (d / "disk.img.gz").write_bytes(gzip.compress(raw, compresslevel=1))
    out = {"random": rnd, "disk": disk, "disk.xz": d / "disk.img.xz", "disk.gz": d / "disk.img.gz"}
    for p in out.values():
        _sidecar(p)
    return out


def _device_bytes(dev: str, length: int, offset: int = 0) -> bytes:
    with open(dev, "rb") as fh:
        fh.seek(offset)
        return fh.read(length)


def _same(dev: str, image: Path) -> bool:
    """The device's first bytes are the image's decompressed bytes."""
    opener = lzma.open if image.suffix == ".xz" else gzip.open if image.suffix == ".gz" else open
    with opener(image, "rb") as fh:  # type: ignore[operator]
        want = fh.read()
    return _device_bytes(dev, len(want)) == want


def _mark(dev: str, offsets: tuple[int, ...]) -> dict[int, bytes]:
    """Random bytes written at ``offsets`` (1 KiB each): any write by a refused flash would
    change them (the first MiB is zeroed before anything else)."""
    marks = {off: os.urandom(1024) for off in offsets}
    fd = os.open(dev, os.O_WRONLY)
    try:
        for off, data in marks.items():
            os.pwrite(fd, data, off)
        os.fsync(fd)
    finally:
        os.close(fd)
    return marks


def _unchanged(dev: str, marks: dict[int, bytes]) -> bool:
    return all(_device_bytes(dev, len(data), off) == data for off, data in marks.items())


# --- flash and verify ------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["random", "disk.xz", "disk.gz", "disk"])
def test_flash_verifies_and_the_device_holds_the_image(
    name: str, images: dict[str, Path], loop: MakeLoop, capsys: pytest.CaptureFixture[str],
) -> None:
    image = images[name]
    dev = loop(300 * MIB)
    _mark(dev, (0, 200 * MIB))
    code, doc, _, err = run_cli(capsys, "reimage", "flash", str(image), "--device", dev, "--yes", "--full", "--json")
    assert code == 0, err
    assert doc["ok"] is True and doc["verify"]["first_difference"] is None and doc["mode"] == "full"
    assert doc["image"]["bytes"] == IMAGE_BYTES and doc["write"]["bytes"] == IMAGE_BYTES
    assert doc["image"]["format"] == {"random": "raw", "disk": "raw", "disk.xz": "xz", "disk.gz": "gz"}[name]
    assert doc["device"]["path"] == dev and doc["device"]["bytes"] == 300 * MIB
    assert "loop device of" in doc["device"]["model"]
    assert doc["verify"]["compared"] == "bytes" and doc["verify"]["device_sha256"] is None
    assert doc["verify"]["image_sha256"] == doc["image"]["data_sha256"]
    assert _same(dev, image)
    assert "writing:" not in err and "verifying:" not in err  # no progress with --json (as fleet commands)
    if name.startswith("disk"):  # the partition table (written last) is there
        table = _sh("sfdisk", "--dump", dev)
        assert "start=        2048, size=      407552" in table and "start=      409600" in table


def test_a_byte_changed_after_writing_fails_verify_naming_the_offset(
    images: dict[str, Path], loop: MakeLoop, capsys: pytest.CaptureFixture[str],
) -> None:
    image = images["disk.xz"]
    dev = loop(300 * MIB)
    code, _, out, err = run_cli(capsys, "reimage", "flash", str(image), "--device", dev, "--yes", "--full")
    assert code == 0, err
    assert "verified:" in out
    # progress of both phases on stderr (plain lines: not a terminal)
    assert "writing: 256.0 MiB of 256.0 MiB (100%)" in err and "verifying: 256.0 MiB of 256.0 MiB (100%)" in err
    code, doc, _, err = run_cli(capsys, "reimage", "verify", str(image), "--device", dev, "--full", "--json")
    assert code == 0 and doc["ok"] is True, err
    offset = 123 * MIB + 4567
    old = _device_bytes(dev, 1, offset)
    fd = os.open(dev, os.O_WRONLY)
    try:
        os.pwrite(fd, bytes([old[0] ^ 0x5A]), offset)
        os.fsync(fd)
    finally:
        os.close(fd)
    code, doc, _, err = run_cli(capsys, "reimage", "verify", str(image), "--device", dev, "--full", "--json")
    assert code == 3, err
    assert doc["ok"] is False and doc["verify"]["first_difference"] == offset
    assert doc["verify"]["device_sha256"] != doc["verify"]["image_sha256"]
    code, _, out, _ = run_cli(capsys, "reimage", "verify", str(image), "--device", dev, "--full")
    assert code == 3
    assert f"VERIFY FAILED: {dev}: differs from the image: first difference at byte {offset}" in out


def test_a_change_after_the_write_phase_fails_the_flash_itself(images: dict[str, Path], loop: MakeLoop) -> None:
    """The flash's own read-back: the core's verify step against a device changed after writing."""
    from panther_ops.core.reimage.flash import check_sha256, eligible_device, flash, inspect_image, read_back

    image = images["random"]
    dev = loop(260 * MIB)
    img = inspect_image(str(image), None, require_checksum=True)
    facts = eligible_device(dev, img)
    done = flash(img, facts, check_sha256(img))
    assert done.verdict.ok
    fd = os.open(dev, os.O_WRONLY)
    try:
        os.pwrite(fd, b"\0" * 4, IMAGE_BYTES - 4)
        os.fsync(fd)
    finally:
        os.close(fd)
    v = read_back(img, facts, done.write.sha256)
    assert not v.ok
    expected = next(i for i in range(IMAGE_BYTES - 4, IMAGE_BYTES) if image.read_bytes()[i] != 0)
    assert v.first_difference == expected


# --- refusals: exit 2, nothing written ------------------------------------------------------------


@contextlib.contextmanager
def _mounted(loop: MakeLoop, dev: str, mnt: Path) -> Iterator[Path]:
    """The ext4 file system on `dev` mounted at `mnt` during the block (the loop fixture unmounts it
    too, should the test stop half way)."""
    mnt.mkdir()
    _sh("mount", "-t", "ext4", dev, str(mnt))
    loop.mounts.append(mnt)  # type: ignore[attr-defined]
    try:
        yield mnt
    finally:
        _sh("umount", str(mnt))


def _refused(capsys: pytest.CaptureFixture[str], image: Path, dev: str, *extra: str) -> str:
    code, _, _, err = run_cli(capsys, "reimage", "flash", str(image), "--device", dev, *extra)
    assert code == 2, err
    return " ".join(err.split())


def test_refuses_a_mounted_device(
    images: dict[str, Path], loop: MakeLoop, tmp_path: Path, capsys: pytest.CaptureFixture[str],
) -> None:
    dev = loop(300 * MIB)
    _sh("mkfs.ext4", "-q", "-F", dev, "64M")
    marks = _mark(dev, (0, 128 * MIB))
    with _mounted(loop, dev, tmp_path / "mnt") as mnt:
        err = _refused(capsys, images["random"], dev, "--yes")
        assert f"{dev} is mounted at {mnt}" in err and "nothing was written" in err
        # a bad image and a bad device: with --full the image is named first (docs/reimage.md)
        err = _refused(capsys, images["random"], dev, "--yes", "--full", "--sha256", "0" * 64)
        assert f"{images['random']}: sha256 is " in err and "is mounted" not in err
    assert _unchanged(dev, marks)


def test_refuses_a_device_smaller_than_the_image(
    images: dict[str, Path], loop: MakeLoop, capsys: pytest.CaptureFixture[str],
) -> None:
    dev = loop(128 * MIB)
    marks = _mark(dev, (0, 64 * MIB))
    for image in (images["random"], images["disk.xz"], images["disk.gz"]):
        err = _refused(capsys, image, dev, "--yes")
        assert f"{dev} (128.0 MiB, {128 * MIB} bytes) is smaller than the image (256.0 MiB, {IMAGE_BYTES} bytes)" in err
    assert _unchanged(dev, marks)


def test_refuses_a_regular_file(images: dict[str, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    target = tmp_path / "card.bin"
    target.write_bytes(b"x" * MIB)
    err = _refused(capsys, images["random"], str(target), "--yes")
    assert f"{target} is a regular file, not a block device" in err
    assert target.read_bytes() == b"x" * MIB


def test_refuses_a_partition(images: dict[str, Path], loop: MakeLoop, tmp_path: Path,
                             capsys: pytest.CaptureFixture[str]) -> None:
    backing = tmp_path / "parted.bin"
    with open(backing, "wb") as fh:
        fh.truncate(600 * MIB)
    _sh("sfdisk", "--quiet", str(backing), input=b"label: dos\nstart=2048, type=83\n")
    dev = loop(0, partscan=True, backing=backing)
    part = f"{dev}p1"
    assert Path(part).exists()
    marks = _mark(part, (0, 128 * MIB))
    err = _refused(capsys, images["random"], part, "--yes")
    assert f"{part} is a partition of {dev}: give the whole device, {dev}" in err
    assert _unchanged(part, marks)
    # the whole device holding that partition is refused while the partition is mounted
    _sh("mkfs.ext4", "-q", "-F", part, "64M")
    with _mounted(loop, part, tmp_path / "mnt") as mnt:
        err = _refused(capsys, images["random"], dev, "--yes")
        assert f"{dev}: {part} is mounted at {mnt}" in err


def test_refuses_a_wrong_or_missing_checksum(
    images: dict[str, Path], loop: MakeLoop, tmp_path: Path, capsys: pytest.CaptureFixture[str],
) -> None:
    dev = loop(300 * MIB)
    marks = _mark(dev, (0, 128 * MIB))
    err = _refused(capsys, images["disk.xz"], dev, "--yes", "--full", "--sha256", "0" * 64)
    assert f"{images['disk.xz']}: sha256 is " in err and f"but --sha256 says {'0' * 64}: refused" in err
    bare = tmp_path / "bare.img"  # no .sha256 beside it
    os.link(images["random"], bare)
    err = _refused(capsys, bare, dev, "--yes")
    assert "no checksum to check it against: give --sha256 HASH or put bare.img.sha256 beside it" in err
    err = _refused(capsys, bare, dev, "--yes", "--sha256", "not-a-hash")
    assert "--sha256: 'not-a-hash' is not a sha256" in err
    assert _unchanged(dev, marks)


def test_refuses_the_device_holding_root(images: dict[str, Path], capsys: pytest.CaptureFixture[str]) -> None:
    st = os.stat("/")
    name = os.path.basename(os.path.realpath(f"/sys/dev/block/{os.major(st.st_dev)}:{os.minor(st.st_dev)}"))
    if not Path(f"/dev/{name}").exists():
        pytest.skip(f"/ is not on a block device here ({name})")
    roots = [f"/dev/{name}"]
    parent = blockdev.device_facts(roots[0]).parent
    if parent:
        roots.append(f"/dev/{parent}")
    for dev in roots:
        # with --full a wrong checksum is named first, whatever the device: nothing about the disk is said
        err = _refused(capsys, images["random"], dev, "--yes", "--full", "--sha256", "0" * 64)
        assert f"{images['random']}: sha256 is " in err and "root file system" not in err
        # block-mapped (checked as it is written): the device is refused before anything is written
        err = _refused(capsys, images["random"], dev, "--yes", "--sha256", "0" * 64)
        assert f"{dev} holds this machine's root file system (/)" in err
        err = _refused(capsys, images["random"], dev, "--yes", "--full", "--sha256", "0" * 64)
        assert f"{images['random']}: sha256 is " in err and "root file system" not in err
        # a good image, and no --yes besides: two refusals stand between this test and the disk
        err = _refused(capsys, images["random"], dev)
        assert f"{dev} holds this machine's root file system (/)" in err


def test_without_yes_nothing_is_written_and_the_device_is_named(
    images: dict[str, Path], loop: MakeLoop, capsys: pytest.CaptureFixture[str],
) -> None:
    dev = loop(300 * MIB)
    marks = _mark(dev, (0, 128 * MIB))
    err = _refused(capsys, images["random"], dev)
    assert f"would erase {dev} (300.0 MiB, loop device of " in err and "pass --yes; nothing was written" in err
    assert _unchanged(dev, marks)


# --- the writer's fallback where O_DIRECT is refused ----------------------------------------------


def test_buffered_fallback_where_o_direct_is_refused(loop_ready: None, tmp_path: Path) -> None:
    """ramfs refuses O_DIRECT (EINVAL): the writer and the reader fall back to buffered I/O."""
    import io

    mnt = tmp_path / "ramfs"
    mnt.mkdir()
    _sh("mount", "-t", "ramfs", "ramfs", str(mnt))
    try:
        target = mnt / "card.bin"
        target.write_bytes(b"\xff" * (6 * MIB))
        data = os.urandom(5 * MIB + 512)
        fd, direct = blockdev.open_device(str(target), os.O_RDONLY, exclusive=False)
        os.close(fd)
        assert direct is False
        w = blockdev.write_image(str(target), io.BytesIO(data), len(data), 512)
        assert w.direct is False and w.bytes_written == len(data)
        assert w.sha256 == hashlib.sha256(data).hexdigest()
        assert target.read_bytes() == data + b"\xff" * (MIB - 512)
        assert blockdev.compare_bytes(str(target), io.BytesIO(data), len(data)) is None
        changed = bytearray(data)
        changed[3 * MIB + 5] ^= 0x5A  # in a 64-byte run of a differing chunk, not at its start
        assert blockdev.compare_bytes(str(target), io.BytesIO(bytes(changed)), len(data)) == 3 * MIB + 5
    finally:
        _sh("umount", str(mnt))
