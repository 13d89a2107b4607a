"""battery_plugin_config.yaml (simulation only, panther_gazebo): `sim battery check`.

The file kind's one validator is `core/kinds` (the same that `config push --as battery`
uses); here it is asked about a local file, whose stack is not known: 0-100 (percent,
panther_ros 2.0.0) is accepted and a 0-1 value is reported as the fraction that panther_ros
2.0.1+ reads. Pushed to a robot, the file is checked for that robot's stack (a fraction and
every key its URDF reads, from 2.0.1).
"""

from __future__ import annotations

from panther_ops.core.kinds import FileKind, check_file


def validate_battery(data: bytes, path: str) -> list[str]:
    """Notes about a valid file; `FileKindError` (exit 2, naming the key) for a bad one."""
    return check_file(FileKind.BATTERY, path, data)
