"""Pure parts of `reimage`: image format, checksum files, xz sizes, device judgement, verdicts,
a backup manifest's modes and paths."""

from __future__ import annotations

import lzma

import pytest

from panther_ops.core.parse.numbers import NumberError, file_mode
from panther_ops.core.reimage.device import describe, refusals, verify_refusals
from panther_ops.core.reimage.image import (
    detect_format,
    normalise_sha256,
    sha256_from_file,
    xz_uncompressed_size,
)
from panther_ops.core.reimage.manifest import clean_path_problem
from panther_ops.core.reimage.verify import Verdict
from panther_ops.errors import UsageError
from panther_ops.transport.blockdev import DeviceFacts, Mount

H = "ab" * 32


@pytest.mark.parametrize(("name", "head", "fmt"), [
    ("a.img", b"\0" * 8, "raw"),
    ("a.IMG.XZ", b"\xfd7zXZ\0\0\0", "xz"),
    ("a.img.gz", b"\x1f\x8b\x08\0", "gz"),
])
def test_detect_format(name: str, head: bytes, fmt: str) -> None:
    assert detect_format(name, head) == fmt


@pytest.mark.parametrize(("name", "head", "msg"), [
    ("a.iso", b"\0", "a.iso: not a disk image: allowed are .img, .img.xz, .img.gz"),
    ("a.img.xz", b"\0" * 8, "a.img.xz: the name says xz-compressed but the content is uncompressed"),
    ("a.img", b"\x1f\x8b\x08\0", "a.img: the name says uncompressed but the content is gzip-compressed"),
])
def test_detect_format_refuses(name: str, head: bytes, msg: str) -> None:
    with pytest.raises(UsageError) as exc:
        detect_format(name, head)
    assert str(exc.value) == msg


def test_checksum_files() -> None:
    assert sha256_from_file(f"{H.upper()}  panther.img.xz\n", "/x/panther.img.xz", "f") == H
    assert sha256_from_file(f"# sums\n{'cd' * 32} other.img\n{H} *panther.img\n", "panther.img", "f") == H
    assert sha256_from_file(f"{H}\n", "panther.img", "f") == H
    assert normalise_sha256(f"sha256:{H}", "--sha256") == H
    with pytest.raises(UsageError, match=r"f: no sha256 line for panther.img"):
        sha256_from_file(f"{H} a.img\n{H} b.img\n", "panther.img", "f")
    with pytest.raises(UsageError, match=r"--sha256: 'abc' is not a sha256"):
        normalise_sha256("abc", "--sha256")


def test_xz_size_from_the_index_of_several_streams_with_padding() -> None:
    parts = [b"a" * 100_000, bytes(range(256)) * 5000, b""]
    blob = b"".join(lzma.compress(p) for p in parts[:2]) + b"\0" * 8 + lzma.compress(parts[2])
    assert xz_uncompressed_size(lambda off, n: blob[off:off + n], len(blob), "x") == sum(map(len, parts))
    with pytest.raises(UsageError, match=r"x: not a readable \.xz file"):
        xz_uncompressed_size(lambda off, n: blob[off:off + n], len(blob) - 3, "x")


def facts(**kw: object) -> DeviceFacts:
    base: dict[str, object] = dict(path="/dev/sdb", real_path="/dev/sdb", exists=True, is_block=True, name="sdb",
                                   devno="8:16", size_bytes=32 << 30, model="SanDisk Ultra")
    base.update(kw)
    return DeviceFacts(**base)  # type: ignore[arg-type]


def test_a_whole_unused_device_of_enough_size_may_be_written() -> None:
    assert refusals(facts(), 4 << 30) == []
    assert describe(facts()) == "/dev/sdb (32.0 GiB, SanDisk Ultra)"


def test_every_reason_is_named() -> None:
    f = facts(is_partition=True, parent="sda", holds_root=True, read_only=True, size_bytes=1 << 30,
              mounts=[Mount("8:1", "/dev/sdb1", "/"), Mount("8:2", "/dev/sdb2", "/media/boot")],
              holders=["dm-0"], swaps=["/dev/sdb3"], path="/dev/sdb1")
    assert refusals(f, 2 << 30) == [
        "/dev/sdb1 is a partition of /dev/sda: give the whole device, /dev/sda",
        "/dev/sdb1 holds this machine's root file system (/)",
        "/dev/sdb1: /dev/sdb2 is mounted at /media/boot",
        "/dev/sdb1: /dev/sdb3 is in use as swap",
        "/dev/sdb1 is in use by /dev/dm-0",
        "/dev/sdb1 is read-only",
        f"/dev/sdb1 (1.0 GiB, {1 << 30} bytes) is smaller than the image (2.0 GiB, {2 << 30} bytes)",
    ]


def test_not_a_block_device() -> None:
    assert refusals(facts(exists=False), 1) == ["/dev/sdb does not exist"]
    assert refusals(facts(is_block=False, is_regular=True), 1)[0].startswith("/dev/sdb is a regular file")
    assert verify_refusals(facts(is_block=False), 1) == ["/dev/sdb is not a block device"]
    assert verify_refusals(facts(mounts=[Mount("8:17", "/dev/sdb1", "/mnt")]), 1) == []


def test_verdict() -> None:
    ok = Verdict("/dev/sdb", 10, H, H, None, 0.5)
    assert ok.ok and ok.to_json()["first_difference"] is None
    bad = Verdict("/dev/sdb", 10, H, "cd" * 32, 7, 0.5)
    assert not bad.ok
    assert bad.message.startswith("/dev/sdb: differs from the image: first difference at byte 7 (0x7)")
    compared = Verdict("/dev/sdb", 10, H, None, None, 0.5)  # byte for byte: no device hash
    assert compared.ok and compared.to_json()["compared"] == "bytes"
    differs = Verdict("/dev/sdb", 10, H, None, 3, 0.5)
    assert not differs.ok and differs.message.endswith("first difference at byte 3 (0x3) (compared byte for byte)")


def test_mounts_are_grouped_by_source() -> None:
    points = [Mount("8:16", "/dev/sdb", f"/m{i}") for i in range(5)]
    assert refusals(facts(mounts=points), 1) == ["/dev/sdb is mounted at /m0, /m1, /m2 (and 2 more)"]


def test_reapply_keeps_the_new_images_and_puts_back_args_mounts_and_services() -> None:
    from pathlib import Path

    from panther_ops.core.reimage.reapply import reapply, same_line
    from panther_ops.core.robot.compose import ComposeFile

    factory = (Path(__file__).resolve().parents[2] / "templates/compose/panther-2.1.1.yaml").read_text()
    saved = ComposeFile.parse(factory)
    saved.set_arg("wheel_type", "WH04")
    saved.add_volume("~/maps", "/maps", ro=True)
    saved.add_service("nmea_gps", {"image": "husarion/nmea-gps:humble", "network_mode": "host"})
    newer = factory.replace("humble-2.1.1-20240828", "humble-2.1.2-20241108")
    text, done = reapply(saved.text(), newer, "compose.yaml")
    assert done == ["wheel_type:=WH04", "mount ~/maps:/maps:ro", "service nmea_gps"]
    result = ComposeFile.parse(text)
    assert result.driver_image == "husarion/panther:humble-2.1.2-20241108"
    assert result.args["wheel_type"] == "WH04"
    assert any(v.target == "/maps" and v.read_only for v in result.list_volumes())
    assert result.service("nmea_gps")["image"] == "husarion/nmea-gps:humble"
    assert reapply(text, text, "compose.yaml") == (text, [])
    assert same_line((2, 1, 1), (2, 1, 2)) and not same_line((2, 1, 1), (2, 2, 0))


def test_file_modes_are_octal_ascii_digits() -> None:
    assert file_mode("0644") == 0o644 and file_mode("755") == 0o755 and file_mode("4755") == 0o4755
    for bad in ("0o644", "0648", "64", "07777 ", "٠٦٤٤", 644, None):
        with pytest.raises(NumberError):
            file_mode(bad)


@pytest.mark.parametrize(("path", "problem"), [
    ("/home/husarion/compose.yaml", None),
    ("home/husarion/compose.yaml", "is not an absolute path"),
    ("//etc/passwd", "is not a clean path"),
    ("/home/husarion/../../etc/passwd", "is not a clean path"),
    ("/home/husarion/./x", "is not a clean path"),
    ("/home/husarion/", "is not a clean path"),
    ("/", "is the root directory"),
    ("/home/husarion/a\nb", "control character"),
])
def test_manifest_paths_are_clean_and_absolute(path: str, problem: str | None) -> None:
    found = clean_path_problem(path)
    assert (found is None) if problem is None else (problem in (found or ""))
