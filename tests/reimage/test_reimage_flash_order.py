"""`reimage flash` and `reimage verify` judge the image first, whatever the device
(docs/reimage.md: 1. checksum, 2. device): a bad image is named before anything about the
device is read, and a compressed image is not decompressed before its checksum matched.

The device here is never a real one: `blockdev.device_facts` is replaced by a stand-in that
records being asked (and describes an eligible card), and every write or read of a device
fails the test.
"""

from __future__ import annotations

import gzip
import hashlib
from pathlib import Path
from typing import Any

import pytest

from panther_ops.cli.app import main
from panther_ops.transport import blockdev, mapped
from panther_ops.transport.blockdev import DeviceFacts

IMAGE = b"\x00" * 4096 + b"a card image" * 1000
CARD = "/dev/panther-ops-test-card"
YES = {"flash": ["--yes", "--full"], "verify": ["--full"]}
"""The order checksum-first holds for --full (every byte written: the image's sha256 is checked
before anything is written). Block-mapped flashing checks it as the image is read for the write
(tests/reimage/test_reimage_bmap_lab.py)."""


@pytest.fixture
def asked(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """What was asked of the device layer: ``device_facts`` answers an eligible 1 GiB card; a
    write or a read-back of a device fails the test."""
    calls: list[str] = []

    def facts(path: str) -> DeviceFacts:
        calls.append(f"facts {path}")
        return DeviceFacts(path=path, real_path=path, exists=True, is_block=True, size_bytes=1 << 30,
                           model="stand-in card")

    def never(*args: Any, **kwargs: Any) -> Any:
        raise AssertionError(f"the device was written or read: {args}")

    monkeypatch.setattr(blockdev, "device_facts", facts)
    for name in ("write_image", "compare_bytes", "compare"):
        monkeypatch.setattr(blockdev, name, never)
    for name in ("write_mapped", "device_span_hashes", "first_difference"):
        monkeypatch.setattr(mapped, name, never)
    return calls


def _run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str]:
    capsys.readouterr()
    code = main(list(argv))
    return code, " ".join(capsys.readouterr().err.split())


@pytest.mark.parametrize("command", ["flash", "verify"])
def test_a_wrong_checksum_is_named_before_the_device_is_looked_at(
    command: str, asked: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str],
) -> None:
    image = tmp_path / "card.img"
    image.write_bytes(IMAGE)
    (tmp_path / "card.img.sha256").write_text(f"{'0' * 64}  card.img\n")
    code, err = _run(capsys, "reimage", command, str(image), "--device", CARD, *YES[command])
    assert code == 2
    assert f"{image}: sha256 is {hashlib.sha256(IMAGE).hexdigest()} but {image}.sha256 says {'0' * 64}" in err
    assert asked == []  # nothing about the device was read


def test_flash_judges_the_device_once_the_image_is_good(
    asked: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str],
) -> None:
    image = tmp_path / "card.img"
    image.write_bytes(IMAGE)
    code, err = _run(capsys, "reimage", "flash", str(image), "--device", CARD,
                     "--sha256", hashlib.sha256(IMAGE).hexdigest())
    assert code == 2 and asked == [f"facts {CARD}"]
    assert f"would erase {CARD} (1.0 GiB, stand-in card): pass --yes; nothing was written" in err


def test_a_compressed_image_is_not_decompressed_before_its_checksum_matched(
    asked: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch,
) -> None:
    image = tmp_path / "card.img.gz"
    image.write_bytes(gzip.compress(IMAGE))
    measured: list[str] = []
    real = blockdev.gz_size
    monkeypatch.setattr(blockdev, "gz_size", lambda path, progress=None: measured.append(path) or real(path))
    code, err = _run(capsys, "reimage", "flash", str(image), "--device", CARD, "--yes", "--full",
                     "--sha256", "0" * 64)
    assert code == 2 and f"{image}: sha256 is " in err
    assert measured == [] and asked == []


@pytest.mark.parametrize("command", ["flash", "verify"])
def test_an_unreadable_gz_image_is_named_whatever_the_device(
    command: str, asked: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str],
) -> None:
    """Its checksum matches (taken of the damaged file), its content does not decompress."""
    image = tmp_path / "card.img.gz"
    whole = gzip.compress(IMAGE)
    image.write_bytes(whole[: len(whole) // 2])
    (tmp_path / "card.img.gz.sha256").write_text(hashlib.sha256(image.read_bytes()).hexdigest() + "\n")
    code, err = _run(capsys, "reimage", command, str(image), "--device", CARD, *YES[command])
    assert code == 2, err
    assert f"{image}: not a readable .gz file" in err and asked == []
