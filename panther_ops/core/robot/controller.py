"""The drive controller file under edit (``config set controller.<key>``), and the stack's default.

The keys, the wheel types' limits and the checks are the controller file kind's rules
(`core.kinds.controller_limits`), shared with its validator. Edits go through `YamlDocument`:
only the edited line changes; values are written as floats (``2.0``, never ``2``: ROS
refuses an integer for a double parameter).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from panther_ops.core.kinds import FileKind
from panther_ops.core.kinds.controller_limits import (
    LimitKey,
    file_limits,
    limit_warnings,
    locate,
    parse_limit_key,
    validate_limit,
)
from panther_ops.core.robot.files import config_file
from panther_ops.core.stack import Stack

if TYPE_CHECKING:  # the YAML editor (ruamel) loads when a file is edited, not for validating values
    from panther_ops.core.yaml.document import YamlDocument


def default_controller_text(stack: Stack, wheel_type: str) -> str:
    """The stack's default ``<wheel_type>_controller.yaml`` (from ``templates/config``).

    Raises:
        UsageError: no template (custom wheels; WH05 before husarion_ugv 2.2).
    """
    return config_file(stack, FileKind.CONTROLLER, wheel_type=wheel_type).template_text()


@dataclass(frozen=True)
class LimitChange:
    changed: bool
    key: str
    value: bool | float | None
    warnings: tuple[str, ...] = ()


class ControllerConfig:
    """A controller file under edit, for a given stack and wheel type."""

    def __init__(self, doc: YamlDocument, stack: Stack, wheel_type: str, *, force: bool = False) -> None:
        from panther_ops.core.kinds.stock_wheels import controller_file_wheels, limits_wheel

        self.doc = doc
        self.stack = stack
        self.wheel_type = limits_wheel(controller_file_wheels(doc.to_plain(), stack), wheel_type)
        """the wheels whose limits apply: those the file's kinematics describe (`limits_wheel`)"""
        self.top, self.controller_key = locate(doc, stack, force=force)

    @classmethod
    def parse(
        cls, text: str, stack: Stack, wheel_type: str, *, path: str | None = None, force: bool = False
    ) -> ControllerConfig:
        from panther_ops.core.yaml.document import YamlDocument

        return cls(YamlDocument(text, path), stack, wheel_type, force=force)

    @classmethod
    def default(cls, stack: Stack, wheel_type: str) -> ControllerConfig:
        """The stack's default file for the wheel type, ready to edit."""
        cf = config_file(stack, FileKind.CONTROLLER, wheel_type=wheel_type)
        return cls.parse(cf.template_text(), stack, wheel_type, path=cf.container_path)

    def text(self) -> str:
        return self.doc.text

    def diff(self) -> str:
        return self.doc.diff()

    def _path(self, key: LimitKey) -> tuple[str, ...]:
        return key.path(self.controller_key, self.top)

    def get(self, key: str) -> Any:
        """Current value (None when the key is not in the file)."""
        return self.doc.get(self._path(parse_limit_key(key)), None)

    def limits(self) -> dict[str, Any]:
        """Every limit key present in the file."""
        return file_limits(self.doc, self.top, self.controller_key)

    def set(self, key: str, value: Any, *, force: bool = False) -> LimitChange:
        """Validate (`validate_limit`) and write one limit; only that line changes."""
        validated = validate_limit(self.stack, self.wheel_type, key, value, force=force)
        changed = self.doc.set(self._path(validated.key), validated.value)
        return LimitChange(changed, validated.key.dotted, validated.value, validated.warnings)

    def unset(self, key: str) -> bool:
        """Remove a limit key from the file (e.g. ``min_velocity`` back to its default)."""
        return self.doc.delete(self._path(parse_limit_key(key)))

    def check(self) -> list[str]:
        """Warnings about the file as it is: values above the wheel limits, enabled limits at 0."""
        return limit_warnings(self.limits(), self.wheel_type)
