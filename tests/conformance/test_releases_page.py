"""docs/releases.md is what scripts/releases.py writes from the catalogue today, and says what
the catalogue says (a few facts read back from the page, per release)."""

from __future__ import annotations

import re
from pathlib import Path

from panther_ops.conformance.releases import RELEASES, render
from panther_ops.core.stack import LINES, parse_version

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "releases.md"


def _section(text: str, release: str) -> str:
    """The section whose release table lists ``release``."""
    for part in text.split("\n## ")[1:]:
        if re.search(rf"^\| {re.escape(release)} \|", part, re.M):
            return part
    raise AssertionError(f"no section lists {release}")


def test_page_is_current() -> None:
    assert PAGE.read_text(encoding="utf-8") == render(), "docs/releases.md is stale: python scripts/releases.py"


def test_every_supported_release_has_a_section() -> None:
    text = render()
    assert all(any(ln.holds(parse_version(r)) for ln in LINES) for r in RELEASES)
    for release in RELEASES:
        _section(text, release)


def test_sections_say_where_each_release_reads_its_files() -> None:
    text = render()
    s222, s232, s211 = _section(text, "2.2.2"), _section(text, "2.3.2"), _section(text, "2.1.1")
    assert "`husarion/husarion-ugv:humble-2.2.2-20250702` | `templates/compose/husarion-ugv-2.2.2.yaml`" in s222
    assert "`/config/husarion_ugv_bringup/config/joy2twist_panther.yaml` (tree)" in s222
    assert "`/config/husarion_ugv_teleop/config/joy2twist_panther.yaml` (tree)" in s232
    assert "| `use_madgwick_filter` |" in s232 and "| `use_madgwick_filter` |" not in s222
    assert "| `publish_robot_state` |" in s222 and "| `publish_robot_state` |" not in s232
    assert "(image)" in s211 and "(tree)" not in s211  # panther_ros: every default is the image's
    assert "`/ros2_ws/install/husarion_ugv_manager/share/husarion_ugv_manager/config/safety_manager.yaml` (image)" \
        in s232
    assert "2.1.1, 2.1.2" not in s211 and "| 2.1.2 |" in s211  # 2.1.1 and 2.1.2 read alike: one section
