"""Block maps: bmaptool's XML format (read 1.x/2.x, write 2.0) and maps computed from images
that the test builds with sfdisk, mkfs.ext4 and mkfs.vfat on plain files (no device, no root).

The format's rules are bmap-tools 3.6's (bmaptools/BmapCreate.py, BmapCopy.py): a range's
checksum covers its bytes up to the image's end; the file's own checksum is taken with its value
replaced by ASCII zeros; 1.3 uses sha1 (`sha1=`, BmapFileSHA1), 1.4/2.x `chksum=` with
ChecksumType; before 1.3 no checksums.
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from panther_ops.core.reimage.bmap import BlockMap, BlockRange, blocks_of, parse_bmap, render_bmap
from panther_ops.core.reimage.fsalloc import ext4_unread, ext4_used, fat_used
from panther_ops.core.reimage.mapping import compute_map
from panther_ops.errors import UsageError
from panther_ops.transport.mapped import data_extents
from tests.clirun import run_cli
from tests.conftest import skip_or_fail

MIB = 1 << 20


def _sh(*argv: str, input: bytes | None = None) -> None:
    subprocess.run(argv, check=True, capture_output=True, input=input)


@pytest.fixture(scope="module")
def tools() -> None:
    missing = [t for t in ("sfdisk", "mkfs.ext4", "mkfs.vfat", "mcopy") if shutil.which(t) is None]
    if missing:
        skip_or_fail(f"missing {', '.join(missing)} (scripts/install-test-deps.sh installs them)")


def _reader(path: Path):  # type: ignore[no-untyped-def]
    data = path.read_bytes()
    return lambda off, n: data[off:off + n]


def _covered(extents: list[tuple[int, int]], start: int, end: int) -> bool:
    pos = start
    for s, e in sorted(extents):
        if s <= pos < e:
            pos = e
        if pos >= end:
            return True
    return pos >= end


def _mapped(extents: list[tuple[int, int]], size: int) -> int:
    """Bytes in the whole 4 KiB blocks the extents touch."""
    return sum((b - a + 1) * 4096 for a, b in blocks_of(extents, size))


# --- the XML format ------------------------------------------------------------------------------


def _v13(image: bytes, block: int, ranges: list[tuple[int, int]]) -> bytes:
    """A 1.3 bmap (sha1) laid out as bmaptool 3.x wrote it, with its file checksum."""
    rows = []
    for a, b in ranges:
        digest = hashlib.sha1(image[a * block:(b + 1) * block]).hexdigest()
        rows.append(f'        <Range sha1="{digest}"> {a}-{b} </Range>')
    count = sum(b - a + 1 for a, b in ranges)
    text = (f'<?xml version="1.0" ?>\n<bmap version="1.3">\n    <ImageSize> {len(image)} </ImageSize>\n'
            f"    <BlockSize> {block} </BlockSize>\n    <BlocksCount> {(len(image) + block - 1) // block} </BlocksCount>\n"
            f"    <MappedBlocksCount> {count} </MappedBlocksCount>\n    <BmapFileSHA1> {'0' * 40} </BmapFileSHA1>\n"
            "    <BlockMap>\n" + "\n".join(rows) + "\n    </BlockMap>\n</bmap>\n")
    digest = hashlib.sha1(text.encode()).hexdigest()
    return text.replace("0" * 40, digest, 1).encode()


def test_render_then_parse_round_trips_with_the_files_own_checksum() -> None:
    image = os.urandom(10 * 4096 + 100)  # a last partial block
    ranges = [(0, 1), (5, 5), (9, 10)]
    bm = BlockMap(len(image), 4096, tuple(
        BlockRange(a, b, hashlib.sha256(image[a * 4096:(b + 1) * 4096]).hexdigest()) for a, b in ranges), "sha256")
    text = render_bmap(bm)
    assert '<bmap version="2.0">' in text and "<ChecksumType> sha256 </ChecksumType>" in text
    assert "<MappedBlocksCount> 5 </MappedBlocksCount>" in text and "> 5 </Range>" in text
    back = parse_bmap(text.encode(), "x.bmap")
    assert back == bm
    assert back.mapped_bytes == 2 * 4096 + 4096 + 4096 + 100
    assert back.byte_span(back.ranges[-1]) == (9 * 4096, len(image))
    # the file's checksum is checked: one range changed
    tampered = text.replace("> 5 </Range>", "> 6 </Range>")
    with pytest.raises(UsageError, match=r"x\.bmap: the bmap file's own checksum is .* the file was changed or damaged"):
        parse_bmap(tampered.encode(), "x.bmap")


def test_version_1_3_sha1_and_1_0_without_checksums_are_read() -> None:
    image = os.urandom(8 * 4096)
    bm = parse_bmap(_v13(image, 4096, [(0, 2), (6, 7)]), "old.bmap")
    assert bm.version == "1.3" and bm.checksum_type == "sha1" and bm.mapped_blocks == 5
    assert bm.ranges[1].checksum == hashlib.sha1(image[6 * 4096:]).hexdigest()
    v10 = (b'<?xml version="1.0" ?><bmap version="1.0"><ImageSize> 8192 </ImageSize><BlockSize> 4096 </BlockSize>'
           b"<BlocksCount> 2 </BlocksCount><MappedBlocksCount> 1 </MappedBlocksCount>"
           b"<BlockMap><Range> 1 </Range></BlockMap></bmap>")
    bm = parse_bmap(v10, "v10.bmap")
    assert bm.checksum_type is None and bm.ranges == (BlockRange(1, 1, None),)


@pytest.mark.parametrize(("change", "message"), [
    (('version="2.0"', 'version="3.0"'), "bmap version 3.0 is not supported"),
    (("<BlocksCount> 3 </BlocksCount>", "<BlocksCount> 4 </BlocksCount>"), "<BlocksCount> 4 does not agree"),
    (("> 0-1 </Range>", "> 1-0 </Range>"), "outside the image's 3 blocks or runs backwards"),
    (("> 0-1 </Range>", "> 0-9 </Range>"), "outside the image's 3 blocks"),
    (("> 0-1 </Range>", "> zero </Range>"), "is not FIRST-LAST or N"),
    (("<ChecksumType> sha256 </ChecksumType>", "<ChecksumType> rot13 </ChecksumType>"), "'rot13' is not a hash"),
    (("<bmap ", "<!DOCTYPE x [<!ENTITY a 'b'>]><bmap "), "declares a document type or entities"),
    (("</bmap>", ""), "not XML"),
])
def test_bad_bmap_files_are_refused_naming_what(change: tuple[str, str], message: str) -> None:
    image = bytes(3 * 4096)
    h = hashlib.sha256(image[:8192]).hexdigest()
    text = render_bmap(BlockMap(len(image), 4096, (BlockRange(0, 1, h),), "sha256"))
    bad = text.replace(*change)
    # refresh the file checksum so that the change itself is what is judged
    stored = next(line.split()[1] for line in bad.splitlines() if "<BmapFileChecksum>" in line)
    bad = bad.replace(stored, "0" * 64, 1)
    bad = bad.replace("0" * 64, hashlib.sha256(bad.encode()).hexdigest(), 1)
    with pytest.raises(UsageError, match=message):
        parse_bmap(bad.encode(), "bad.bmap")


def test_blocks_of_rounds_outwards_and_merges() -> None:
    # adjacent blocks merge; the last range is clipped to the image
    assert blocks_of([(100, 200), (4096, 8193), (8200, 9000), (50000, 60000)], 52000) == [(0, 2), (12, 12)]
    assert blocks_of([(100, 200), (3 * 4096, 4 * 4096)], 52000) == [(0, 0), (3, 3)]


# --- maps computed from file systems ---------------------------------------------------------------


def _tree(tmp: Path, blob_mib: int) -> tuple[Path, bytes]:
    root = tmp / "tree"
    (root / "etc").mkdir(parents=True)
    (root / "etc" / "hostname").write_text("panther\n")
    blob = os.urandom(blob_mib * MIB)
    (root / "blob.bin").write_bytes(blob)
    return root, blob


def _maps_the_file(used: list[tuple[int, int]], data: bytes, blob: bytes) -> int:
    """Check that ``used`` maps the data of the file ``blob`` (one extent) in the file system
    ``data``; return how many bytes ``used`` maps."""
    at = data.find(blob[:4096])
    assert at >= 0 and _covered(used, at, at + len(blob))
    return _mapped(used, len(data))


def _only_mapped(image: bytes, extents: list[tuple[int, int]], fill: bytes = b"\xa5") -> bytes:
    """The image's mapped 4 KiB blocks over garbage (a card written by the map)."""
    copy = bytearray(fill * len(image))
    for a, b in blocks_of(extents, len(image)):
        copy[a * 4096:(b + 1) * 4096] = image[a * 4096:(b + 1) * 4096]
    return bytes(copy)


def test_ext4_map_holds_every_used_block_and_little_else(tools: None, tmp_path: Path) -> None:
    root, blob = _tree(tmp_path, 12)
    fs = tmp_path / "root.ext4"
    _sh("mkfs.ext4", "-q", "-F", "-d", str(root), str(fs), "128M")
    used = ext4_used(_reader(fs), fs.stat().st_size)
    assert used is not None
    data = fs.read_bytes()
    total = _maps_the_file(used, data, blob)
    assert 12 * MIB < total < 40 * MIB  # the file, the journal and metadata: not the free space
    # a copy of only the mapped blocks over garbage is a clean file system with the same file
    out = tmp_path / "copy.ext4"
    out.write_bytes(_only_mapped(data, used))
    subprocess.run(["e2fsck", "-fn", str(out)], check=True, capture_output=True)
    dumped = tmp_path / "dumped"
    _sh("debugfs", "-R", f"dump /blob.bin {dumped}", str(out))
    assert dumped.read_bytes() == blob


def _itables(text: str) -> list[tuple[int, int]]:
    """Each group's inode table (byte extents), from dumpe2fs's report."""
    block = int(re.search(r"^Block size:\s+(\d+)", text, re.M).group(1))  # type: ignore[union-attr]
    return [(int(a) * block, (int(b) + 1) * block) for a, b in re.findall(r"Inode table at (\d+)-(\d+)", text)]


def _minus(extents: list[tuple[int, int]], size: int, cut: list[tuple[int, int]]) -> set[int]:
    """The 1 KiB units of ``extents`` not in ``cut``."""
    def units(ex: list[tuple[int, int]]) -> set[int]:
        return {u for s, e in ex for u in range(s // 1024, min(e, size) // 1024)}
    return units(extents) - units(cut)


@pytest.mark.parametrize("how", ["image file", "nodiscard"])
def test_ext4_map_leaves_out_only_what_nothing_reads(how: str, tools: None, tmp_path: Path) -> None:
    """A used ext4 block is left out of the map only where ext4_unread names it (never an inode
    table of a group marked ITABLE_ZEROED, as mkfs on an image file marks them all); the map is
    the same with or without the sparse file's extents (a .img and its .xz); a copy of just the
    map over garbage fscks clean with the file intact. `-E nodiscard`: mkfs leaves the inode
    tables to the kernel's lazy init (not ITABLE_ZEROED): their unused tails are left out too."""
    root, blob = _tree(tmp_path, 12)
    img = tmp_path / "card.img"
    with open(img, "wb") as fh:
        fh.truncate(161 * MIB)
    _sh("sfdisk", "--quiet", str(img), input=b"label: dos\nstart=2048, type=83\n")
    opts = f"offset={MIB}" + (",nodiscard" if how == "nodiscard" else "")
    _sh("mkfs.ext4", "-q", "-F", "-E", opts, "-d", str(root), str(img), "160M")
    size = img.stat().st_size
    data = data_extents(str(img))
    assert data is not None  # mkfs leaves holes
    read = _reader(img)
    sparse = compute_map(read, size, data)
    stream = compute_map(read, size)  # as from the .xz: no holes known
    assert [r["filesystem"] for r in sparse.regions] == ["ext4"] and sparse.notes == []
    assert sparse.regions == stream.regions  # the partition's map does not depend on the holes
    fs = tmp_path / "root.ext4"
    fs.write_bytes(img.read_bytes()[MIB:])
    used, unread = ext4_used(_reader(fs), fs.stat().st_size), ext4_unread(_reader(fs), fs.stat().st_size)
    assert used and unread
    left_out = _minus([(s + MIB, e + MIB) for s, e in used], size, sparse.extents)
    assert left_out, "nothing left out"
    assert left_out <= {u for s, e in unread for u in range(s // 1024 + 1024, e // 1024 + 1024)}
    text = subprocess.run(["dumpe2fs", str(fs)], check=True, capture_output=True, text=True).stdout
    tables = [(s + MIB, e + MIB) for s, e in _itables(text)]
    zeroed = "ITABLE_ZEROED" in text
    assert zeroed == (how == "image file")
    if zeroed:  # every inode table written, holes and all
        assert all(_covered(sparse.extents, s, e) for s, e in tables)
    else:  # the tables' unused tails (holes here) left to the kernel's lazy init
        assert any(not _covered(sparse.extents, s, e) for s, e in tables)
    image = img.read_bytes()
    copy = _only_mapped(image, sparse.extents)
    out = tmp_path / "copy.ext4"
    out.write_bytes(copy[MIB:])
    subprocess.run(["e2fsck", "-fn", str(out)], check=True, capture_output=True)
    dumped = tmp_path / "dumped"
    _sh("debugfs", "-R", f"dump /blob.bin {dumped}", str(out))
    assert dumped.read_bytes() == blob
    if zeroed:
        # Why the inode tables are written: once a group's descriptor is damaged, e2fsck reads that
        # group's whole inode table. Ours holds zeros there and only the checksum is fixed; a copy of
        # the data extents alone (bmaptool's rule) has old bytes there, which e2fsck finds as garbage
        # inodes.
        theirs = bytearray(b"\xa5" * size)
        for s, e in data:
            theirs[s:e] = image[s:e]
        found = {}
        for name, fs_bytes in (("ours", copy[MIB:]), ("theirs", theirs[MIB:])):
            path = tmp_path / f"{name}.ext4"
            path.write_bytes(_bad_descriptor(bytearray(fs_bytes), 1))
            run = subprocess.run(["e2fsck", "-fy", str(path)], check=False, capture_output=True, text=True)
            assert run.returncode in (0, 1), run.stderr  # 1: errors corrected
            found[name] = run.stdout.count("seems to contain garbage")
        assert found["ours"] == 0 and found["theirs"] > 100, found


def _bad_descriptor(fs: bytearray, group: int) -> bytes:
    """The file system with ``group``'s descriptor checksum (bg_checksum) flipped."""
    block = 1024 << int.from_bytes(fs[1024 + 0x18:1024 + 0x1C], "little")
    first = int.from_bytes(fs[1024 + 0x14:1024 + 0x18], "little")
    size = int.from_bytes(fs[1024 + 0xFE:1024 + 0x100], "little") or 32
    at = (first + 1) * block + group * size + 0x1E
    fs[at] ^= 0xFF
    return bytes(fs)


@pytest.mark.parametrize("fat", ["16", "32"])
def test_fat_map_holds_the_fat_and_every_used_cluster(fat: str, tools: None, tmp_path: Path) -> None:
    fs = tmp_path / "boot.vfat"
    with open(fs, "wb") as fh:
        fh.truncate(96 * MIB)
    _sh("mkfs.vfat", "-F", fat, str(fs))
    blob = os.urandom(5 * MIB + 123)
    (tmp_path / "kernel.img").write_bytes(blob)
    _sh("mcopy", "-i", str(fs), str(tmp_path / "kernel.img"), "::kernel.img")
    used = fat_used(_reader(fs), fs.stat().st_size)
    assert used is not None
    data = fs.read_bytes()
    total = _maps_the_file(used, data, blob)
    assert 5 * MIB < total < 7 * MIB
    out = tmp_path / "copy.vfat"
    out.write_bytes(_only_mapped(data, used, fill=b"\x5a"))
    subprocess.run(["fsck.fat", "-n", str(out)], check=True, capture_output=True)
    _sh("mcopy", "-i", str(out), "::kernel.img", str(tmp_path / "back.img"))
    assert (tmp_path / "back.img").read_bytes() == blob


def _card(tmp: Path, label: str) -> tuple[Path, bytes]:
    """A 192 MiB card image: a FAT32 boot partition (1-65 MiB) and an ext4 root (65 MiB-), not sparse."""
    img = tmp / f"card-{label}.img"
    with open(img, "wb") as fh:
        fh.write(b"\xee" * (192 * MIB))  # not sparse, not zeros: only the map can leave things out
    table = (b"label: dos\nstart=2048, size=131072, type=c\nstart=133120, type=83\n" if label == "dos" else
             b"label: gpt\nstart=2048, size=131072, type=EBD0A0A2-B9E5-4433-87C0-68B6B72699C7\n"
             b"start=133120, size=253952, type=0FC63DAF-8483-4772-8E79-3D69D8477DE4\n")
    _sh("sfdisk", "--quiet", str(img), input=table)
    _sh("mkfs.vfat", "-F", "32", "--offset", "2048", str(img), str(131072 // 2))
    root, blob = _tree(tmp, 8)
    _sh("mkfs.ext4", "-q", "-F", "-E", f"offset={133120 * 512}", "-d", str(root), str(img), f"{253952 // 2}k")
    return img, blob


@pytest.mark.parametrize("label", ["dos", "gpt"])
def test_card_image_map_from_its_partition_table(label: str, tools: None, tmp_path: Path) -> None:
    img, blob = _card(tmp_path, label)
    m = compute_map(_reader(img), img.stat().st_size)
    assert [r["filesystem"] for r in m.regions] == ["fat", "ext4"] and m.notes == []
    data = img.read_bytes()
    assert _covered(m.extents, 0, 1024 * 1024)
    # the file (in extents around group 1's superblock backup and descriptors) is in the map
    root = tmp_path / "root.ext4"
    root.write_bytes(_only_mapped(data, m.extents)[133120 * 512:])
    subprocess.run(["e2fsck", "-fn", str(root)], check=True, capture_output=True)
    _sh("debugfs", "-R", f"dump /blob.bin {tmp_path / 'dumped'}", str(root))
    assert (tmp_path / "dumped").read_bytes() == blob
    if label == "gpt":  # the backup table at the end
        assert _covered(m.extents, len(data) - 33 * 512, len(data))
    total = _mapped(m.extents, len(data))
    assert total < 60 * MIB, total  # of 192 MiB


def test_an_unknown_file_system_is_mapped_whole_and_said(tools: None, tmp_path: Path) -> None:
    img = tmp_path / "odd.img"
    with open(img, "wb") as fh:
        fh.truncate(64 * MIB)
    _sh("sfdisk", "--quiet", str(img), input=b"label: dos\nstart=2048, size=32768, type=83\nstart=34816, type=7\n")
    with open(img, "r+b") as fh:  # partition 1: bytes that are no file system
        fh.seek(MIB)
        fh.write(os.urandom(MIB))
    m = compute_map(_reader(img), img.stat().st_size)
    assert any("partition 1 (type 0x83, 16.0 MiB): no ext2/3/4 or FAT file system read there: mapped whole" in n
               for n in m.notes)
    assert _covered(m.extents, MIB, 17 * MIB) and _covered(m.extents, 17 * MIB, 64 * MIB)
    # the same image as a sparse file: its holes are left out where nothing says what the bytes are
    data = data_extents(str(img))
    assert data is not None
    sparse = compute_map(_reader(img), img.stat().st_size, data)
    assert sum(e - s for s, e in sparse.extents) < 4 * MIB
    assert any("its holes left out (sparse image)" in n for n in sparse.notes)


def test_reimage_bmap_writes_a_map_reimage_reads_back(
    tools: None, tmp_path: Path, capsys: pytest.CaptureFixture[str],
) -> None:
    img, _ = _card(tmp_path, "dos")
    code, doc, _, err = run_cli(capsys, "reimage", "bmap", str(img), "--json")
    assert code == 0, err
    target = Path(doc["bmap"])
    assert target == img.with_name(img.name + ".bmap")
    bm = parse_bmap(target.read_bytes(), str(target))
    assert bm.mapped_bytes == doc["map"]["bytes_mapped"] and bm.checksum_type == "sha256"
    data = img.read_bytes()
    for r in bm.ranges:
        s, e = bm.byte_span(r)
        assert hashlib.sha256(data[s:e]).hexdigest() == r.checksum
    assert [p["filesystem"] for p in doc["map"]["partitions"]] == ["fat", "ext4"]
