"""Block-mapped `reimage flash`/`verify`/`bmap` on loop devices this module makes (issue 27).

A card image built like a Panther card: a DOS partition table, a FAT32 boot partition with
files, an ext4 root with ~200 MiB of files, in a 768 MiB image (the rest free). Every block
device written is a loop device attached here to a backing file in the test's tmp dir (the
`loop` fixture of test_reimage_flash_lab), pre-filled with a pattern that is neither zeros nor
the image, so only what the map says is written is there. bmaptool (Debian's bmap-tools) is run
both ways. Marked `lab`: without root or the tools they skip, and fail under CI=true.
"""

from __future__ import annotations

import filecmp
import hashlib
import lzma
import os
import shutil
import subprocess
from pathlib import Path

import pytest

from tests.clirun import run_cli
from tests.conftest import skip_or_fail
from tests.reimage.test_reimage_flash_lab import MakeLoop, _sh, loop, loop_ready  # noqa: F401 (fixtures)

pytestmark = pytest.mark.lab

MIB = 1 << 20
IMAGE_BYTES = 768 * MIB
CARD_BYTES = 800 * MIB
BOOT = (2048, 131072)  # sectors: 1 MiB, 64 MiB
ROOT_START = 133120
PATTERN = b"\xa5\x5a\xc3\x3c" * 1024


@pytest.fixture(scope="module")
def tools(loop_ready: None) -> None:  # noqa: F811
    missing = [t for t in ("bmaptool", "mkfs.vfat", "mcopy", "e2fsck", "fsck.fat") if shutil.which(t) is None]
    if missing:
        skip_or_fail(f"missing {', '.join(missing)} (scripts/install-test-deps.sh installs them)")


def _sidecar(path: Path) -> None:
    Path(f"{path}.sha256").write_text(f"{hashlib.sha256(path.read_bytes()).hexdigest()}  {path.name}\n")


@pytest.fixture(scope="module")
def card(tools: None, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """card.img (sparse as mkfs leaves it), card.img.xz, the trees put in them, .sha256 files."""
    d = tmp_path_factory.mktemp("card")
    boot, root = d / "boot", d / "root"
    boot.mkdir()
    (boot / "config.txt").write_text("arm_64bit=1\nkernel=vmlinuz\n")
    (boot / "vmlinuz").write_bytes(os.urandom(9 * MIB + 77))
    for sub in ("etc", "usr/lib", "home/husarion"):
        (root / sub).mkdir(parents=True)
    (root / "etc" / "hostname").write_text("panther\n")
    for i in range(40):  # ~200 MiB of files of many sizes
        (root / "usr/lib" / f"lib{i}.so").write_bytes(os.urandom((i % 7 + 1) * 1300 * 1024 + i))  # 197 MiB
    (root / "home/husarion" / "compose.yaml").write_text("services: {}\n")
    img = d / "card.img"
    with open(img, "wb") as fh:
        fh.truncate(IMAGE_BYTES)
    _sh("sfdisk", "--quiet", str(img), input=f"label: dos\nstart={BOOT[0]}, size={BOOT[1]}, type=c\n"
        f"start={ROOT_START}, type=83\n".encode())
    vfat = d / "boot.vfat"  # made apart, then put in partition 1
    with open(vfat, "wb") as fh:
        fh.truncate(BOOT[1] * 512)
    _sh("mkfs.vfat", "-F", "32", str(vfat))
    for f in boot.iterdir():
        _sh("mcopy", "-i", str(vfat), str(f), f"::{f.name}")
    _sh("dd", f"if={vfat}", f"of={img}", "bs=1M", f"seek={BOOT[0] * 512}", "oflag=seek_bytes", "conv=notrunc,sparse",
        "status=none")
    vfat.unlink()
    root_kib = (IMAGE_BYTES // 512 - ROOT_START) // 2
    _sh("mkfs.ext4", "-q", "-F", "-E", f"offset={ROOT_START * 512}", "-d", str(root), str(img), f"{root_kib}k")
    xz = d / "card.img.xz"
    xz.write_bytes(lzma.compress(img.read_bytes(), preset=0))
    for p in (img, xz):
        _sidecar(p)
    return {"img": img, "xz": xz, "boot": boot, "root": root, "dir": d}


def _card_device(loop: MakeLoop, tmp: Path) -> str:  # noqa: F811
    """A loop device over a backing file full of PATTERN (its partitions added with partx once
    the image's table is on it)."""
    tmp.mkdir(parents=True, exist_ok=True)
    backing = tmp / "card.bin"
    with open(backing, "wb") as fh:
        for _ in range(CARD_BYTES // len(PATTERN)):
            fh.write(PATTERN)
    return loop(0, backing=backing)


def _read(dev: str, offset: int, n: int) -> bytes:
    """``n`` bytes of the device at ``offset`` (4 KiB-aligned), read with O_DIRECT: not from the page cache."""
    import mmap

    assert offset % 4096 == 0
    fd = os.open(dev, os.O_RDONLY | os.O_DIRECT)
    try:
        buf = mmap.mmap(-1, n + (-n % 4096))
        os.preadv(fd, [buf], offset)
        return bytes(buf[:n])
    finally:
        os.close(fd)


def _poke(dev: str, offset: int) -> int:
    """Flip the byte at ``offset`` on the device; returns the offset."""
    fd = os.open(dev, os.O_RDWR)
    try:
        old = os.pread(fd, 1, offset)
        os.pwrite(fd, bytes([old[0] ^ 0x5A]), offset)
        os.fsync(fd)
    finally:
        os.close(fd)
    subprocess.run(["blockdev", "--flushbufs", dev], check=False, capture_output=True)
    return offset


def _mounts_and_matches(dev: str, card: dict[str, Path], tmp: Path, loop: MakeLoop) -> None:  # noqa: F811
    """Both partitions fsck clean and every file is byte-identical to the tree put in: the ext4
    root mounted (read-only); the FAT boot partition read with mtools from the partition's
    device (this machine's kernel has no vfat module to mount it with)."""
    _sh("partx", "--update", dev)  # adds, resizes or drops each partition, whatever the kernel had
    subprocess.run(["fsck.fat", "-n", f"{dev}p1"], check=True, capture_output=True)
    subprocess.run(["e2fsck", "-fn", f"{dev}p2"], check=True, capture_output=True)
    for f in card["boot"].iterdir():
        back = tmp / f"from-card-{f.name}"
        _sh("mcopy", "-n", "-i", f"{dev}p1", f"::{f.name}", str(back))
        assert back.read_bytes() == f.read_bytes(), f.name
        back.unlink()
    mnt = tmp / "mnt"
    mnt.mkdir(exist_ok=True)
    _sh("mount", "-o", "ro", "-t", "ext4", f"{dev}p2", str(mnt))
    loop.mounts.append(mnt)  # type: ignore[attr-defined]
    try:
        tree = card["root"]
        files = [str(p.relative_to(tree)) for p in tree.rglob("*") if p.is_file()]
        assert len(files) > 40
        _, mismatch, errors = filecmp.cmpfiles(tree, mnt, files, shallow=False)
        assert mismatch == [] and errors == [], (mismatch, errors)
    finally:
        _sh("umount", str(mnt))


def test_flash_writes_only_the_map_and_the_card_mounts_with_every_file(
    card: dict[str, Path], loop: MakeLoop, tmp_path: Path, capsys: pytest.CaptureFixture[str],  # noqa: F811
) -> None:
    for image in (card["img"], card["xz"]):
        dev = _card_device(loop, tmp_path / image.suffix.strip("."))
        code, doc, _, err = run_cli(capsys, "reimage", "flash", str(image), "--device", dev, "--yes", "--json")
        assert code == 0 and doc["ok"] is True, err
        m, w, v = doc["map"], doc["write"], doc["verify"]
        assert doc["mode"] == "mapped" and m["source"].startswith("computed from the image's partition table")
        assert [p["filesystem"] for p in m["partitions"]] == ["fat", "ext4"] and m["notes"] == []
        assert 197 * MIB < m["bytes_mapped"] < 0.5 * IMAGE_BYTES  # the files, not the free space
        assert w["bytes_written"] == m["bytes_mapped"] == v["bytes"] and w["bytes_read"] == IMAGE_BYTES
        assert w["file_sha256"] == doc["image"]["sha256"] and v["bad_ranges"] == []
        assert doc["seconds"] > 0 and w["seconds"] > 0 and v["seconds"] > 0
        # the free space of the card still holds what was there before (it was not written)
        assert _read(dev, IMAGE_BYTES - 4096, 4096) == PATTERN[:4096]
        _mounts_and_matches(dev, card, tmp_path, loop)
        code, doc, _, err = run_cli(capsys, "reimage", "verify", str(image), "--device", dev, "--json")
        assert code == 0 and doc["ok"] is True and doc["mode"] == "mapped", err


def test_full_writes_every_byte(
    card: dict[str, Path], loop: MakeLoop, tmp_path: Path, capsys: pytest.CaptureFixture[str],  # noqa: F811
) -> None:
    dev = _card_device(loop, tmp_path)
    code, doc, _, err = run_cli(capsys, "reimage", "flash", str(card["img"]), "--device", dev, "--yes", "--full",
                                "--json")
    assert code == 0 and doc["write"]["bytes"] == IMAGE_BYTES, err
    assert _read(dev, IMAGE_BYTES - 4096, 4096) == card["img"].read_bytes()[-4096:]


def test_interop_with_bmaptool_both_ways(
    card: dict[str, Path], loop: MakeLoop, tmp_path: Path, capsys: pytest.CaptureFixture[str],  # noqa: F811
) -> None:
    # ours -> bmaptool: `reimage bmap` of the .xz (named after the image, beside it), `bmaptool copy` takes it
    work = tmp_path / "w"
    work.mkdir()
    xz = work / "card.img.xz"
    os.link(card["xz"], xz)
    code, doc, _, err = run_cli(capsys, "reimage", "bmap", str(xz), "--json")
    assert code == 0, err
    ours = work / "card.img.bmap"
    assert doc["bmap"] == str(ours) and ours.exists()
    dev = _card_device(loop, tmp_path / "a")
    r = subprocess.run(["bmaptool", "copy", "--bmap", str(ours), str(xz), dev], check=False, capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stderr
    _mounts_and_matches(dev, card, tmp_path, loop)
    code, vdoc, _, err = run_cli(capsys, "reimage", "verify", str(card["img"]), "--device", dev, "--bmap", str(ours),
                                 "--json")
    assert code == 0 and vdoc["ok"] is True, err
    assert vdoc["verify"]["compared"].startswith("sha256 of each range from")
    # bmaptool -> ours: `bmaptool create` of the image, used by `reimage flash --bmap`
    theirs = tmp_path / "theirs.bmap"
    subprocess.run(["bmaptool", "create", "-o", str(theirs), str(card["img"])], check=True, capture_output=True)
    dev = _card_device(loop, tmp_path / "b")
    code, doc, _, err = run_cli(capsys, "reimage", "flash", str(card["img"]), "--device", dev, "--yes",
                                "--bmap", str(theirs), "--json")
    assert code == 0 and doc["ok"] is True, err
    assert doc["map"]["source"] == f"{theirs} (bmap version 2.0)" and doc["map"]["checksum_type"] == "sha256"
    _mounts_and_matches(dev, card, tmp_path, loop)


def test_a_changed_byte_on_the_card_is_found_with_its_offset(
    card: dict[str, Path], loop: MakeLoop, tmp_path: Path, capsys: pytest.CaptureFixture[str],  # noqa: F811
) -> None:
    dev = _card_device(loop, tmp_path)
    code, doc, _, err = run_cli(capsys, "reimage", "flash", str(card["img"]), "--device", dev, "--yes", "--json")
    assert code == 0, err
    data = card["img"].read_bytes()
    at = data.find((card["root"] / "usr/lib/lib3.so").read_bytes()[:4096])  # a file's data: mapped
    offset = _poke(dev, at + 1234)
    code, doc, _, err = run_cli(capsys, "reimage", "verify", str(card["img"]), "--device", dev, "--json")
    assert code == 3, err
    assert doc["ok"] is False and doc["verify"]["first_difference"] == offset and doc["verify"]["bad_ranges"]
    code, _, out, _ = run_cli(capsys, "reimage", "verify", str(card["xz"]), "--device", dev)
    assert code == 3 and f"first difference at byte {offset} (0x{offset:x})" in out


def _no_partition_table(dev: str) -> bool:
    return _read(dev, 0, 512)[510:512] != b"\x55\xaa"


def test_a_corrupted_image_stops_the_flash_exit_3(
    card: dict[str, Path], loop: MakeLoop, tmp_path: Path, capsys: pytest.CaptureFixture[str],  # noqa: F811
) -> None:
    data = bytearray(card["img"].read_bytes())
    at = data.find((card["root"] / "usr/lib/lib5.so").read_bytes()[:4096])
    data[at + 99] ^= 0xFF
    bad = tmp_path / "bad.img"
    bad.write_bytes(data)
    Path(f"{bad}.sha256").write_text(card["img"].with_name("card.img.sha256").read_text().split()[0] + "\n")
    # 1. against the image's .sha256 (checked as the image is read)
    dev = _card_device(loop, tmp_path / "a")
    code, doc, _, err = run_cli(capsys, "reimage", "flash", str(bad), "--device", dev, "--yes", "--json")
    assert code == 3 and doc["ok"] is False and "the image file's sha256 is" in doc["stopped"], err
    assert _no_partition_table(dev)
    code, _, _, err = run_cli(capsys, "reimage", "flash", str(bad), "--device", dev, "--yes")
    assert code == 3 and "NOT bootable" in err
    # 2. against the map's range checksums (a .bmap of the good image, no .sha256)
    code, _, _, err = run_cli(capsys, "reimage", "bmap", str(card["img"]), "--out", str(tmp_path / "good.bmap"))
    assert code == 0, err
    os.unlink(f"{bad}.sha256")
    dev = _card_device(loop, tmp_path / "b")
    code, doc, _, err = run_cli(capsys, "reimage", "flash", str(bad), "--device", dev, "--yes",
                                "--bmap", str(tmp_path / "good.bmap"), "--json")
    assert code == 3 and "the block map says" in doc["stopped"], err
    assert _no_partition_table(dev)
    # 3. a wrong --sha256 given for a good image: the same
    code, doc, _, err = run_cli(capsys, "reimage", "flash", str(card["xz"]), "--device", dev, "--yes",
                                "--sha256", "0" * 64, "--json")
    assert code == 3 and "expected " + "0" * 64 in doc["stopped"], err
    assert _no_partition_table(dev)


def _uninit_groups(dev: str) -> int:
    text = subprocess.run(["dumpe2fs", dev], check=True, capture_output=True, text=True).stdout
    return text.count("INODE_UNINIT")


def test_holes_left_out_of_the_map_stay_old_and_the_card_takes_new_files(
    card: dict[str, Path], loop: MakeLoop, tmp_path: Path, capsys: pytest.CaptureFixture[str],  # noqa: F811
) -> None:
    """The sparse image's ext4 holes that nothing reads (UNINIT groups' bitmaps, the reserved GDT
    blocks' backups: ``fsalloc.ext4_unread``) are not written: the card keeps its old bytes there.
    The card still fscks clean, and after the kernel puts files in new directories (spread over
    the block groups, so UNINIT groups are set up from those unwritten bitmaps) it fscks clean
    again and holds them."""
    from panther_ops.core.reimage.fsalloc import ext4_unread
    from panther_ops.transport.mapped import data_extents

    img = card["img"]
    part = img.read_bytes()[ROOT_START * 512:]
    unread = ext4_unread(lambda off, n: part[off:off + n], len(part))
    data = data_extents(str(img))
    assert unread and data
    holes = []  # whole 4 KiB blocks of the image, named by ext4_unread and holes in the file
    for s, e in unread:
        for b in range(-(-(ROOT_START * 512 + s) // 4096), (ROOT_START * 512 + e) // 4096):
            if not any(a <= b * 4096 and b * 4096 + 4096 <= z for a, z in data):
                holes.append(b * 4096)
    assert len(holes) > 8, holes
    dev = _card_device(loop, tmp_path)
    code, doc, _, err = run_cli(capsys, "reimage", "flash", str(img), "--device", dev, "--yes", "--json")
    assert code == 0 and doc["ok"] is True, err
    assert all(_read(dev, at, 4096) == PATTERN for at in holes)  # left as they were
    _mounts_and_matches(dev, card, tmp_path, loop)
    before = _uninit_groups(f"{dev}p2")
    mnt = tmp_path / "rw"
    mnt.mkdir()
    _sh("mount", "-t", "ext4", f"{dev}p2", str(mnt))
    loop.mounts.append(mnt)  # type: ignore[attr-defined]
    new = {f"d{i}/f{j}": os.urandom(3000 + 977 * j) for i in range(24) for j in range(20)}
    try:
        for name, body in new.items():
            (mnt / name).parent.mkdir(exist_ok=True)
            (mnt / name).write_bytes(body)
    finally:
        _sh("umount", str(mnt))
    subprocess.run(["e2fsck", "-fn", f"{dev}p2"], check=True, capture_output=True)
    assert _uninit_groups(f"{dev}p2") < before  # the kernel set up groups it had not used
    _sh("mount", "-o", "ro", "-t", "ext4", f"{dev}p2", str(mnt))
    try:
        assert all((mnt / name).read_bytes() == body for name, body in new.items())
    finally:
        _sh("umount", str(mnt))
