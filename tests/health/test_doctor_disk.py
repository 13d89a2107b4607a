"""The doctor's disk rule: an absolute amount of free space, whatever the disk's size."""
from __future__ import annotations

from panther_ops.core.health.doctor import DISK_MIN_BYTES, _disk

GIB = 1024**3


def test_a_big_disk_with_tens_of_gib_free_is_ok_though_under_ten_percent() -> None:
    finding = _disk(20 * GIB, 252 * GIB)
    assert (finding.state, finding.detail) == ("ok", "20.0 GiB free (8%)")


def test_a_small_card_under_the_amount_warns_with_the_fix() -> None:
    finding = _disk(3 * GIB, 29 * GIB)
    assert finding.state == "warn"
    assert finding.detail == "3.0 GiB free (10%)"
    assert "docker image prune -a" in (finding.fix or "")


def test_the_amount_is_the_boundary() -> None:
    assert _disk(DISK_MIN_BYTES, 32 * GIB).state == "ok"
    assert _disk(DISK_MIN_BYTES - 1, 32 * GIB).state == "warn"


def test_an_unreadable_disk_is_a_warning_naming_how_to_look() -> None:
    finding = _disk(None, None)
    assert finding.state == "warn" and "df -h /" in (finding.fix or "")
