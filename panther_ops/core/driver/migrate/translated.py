"""What a translator returns, and how it refuses.

A translation is the 2.3 text of one file plus notes: each mapping the plan must name (a
value that had no 2.3 key of its own, a default that changed, a customised value kept where
upstream now ships another). What cannot be carried over is a :class:`MigrationRefused`
(exit 2, nothing changed anywhere), naming the file, the key, why, and the fix.
"""

from __future__ import annotations

from dataclasses import dataclass

from panther_ops.errors import InputError

MUX_SINCE = (2, 3, 2)
"""husarion_ugv_ros 2.3.2 brought the twist mux (``manual/cmd_vel``), the teleop package and
the IMU covariance placeholder (husarion_ugv_ros@2.3.2:husarion_ugv_controller/config/*,
husarion_ugv_teleop/)."""


class MigrationRefused(InputError):
    """A value of a 2.2 file that has no 2.3 form: the migration stops before anything is written."""


@dataclass(frozen=True)
class Translated:
    """One file's 2.3 text and what the plan must say about it."""

    text: str
    notes: tuple[str, ...] = ()


def version_label(version: tuple[int, int, int]) -> str:
    return ".".join(str(p) for p in version)
