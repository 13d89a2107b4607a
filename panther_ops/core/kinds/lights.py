"""LED configuration and user animations: the manager's `validate_animations`, as `lights validate`."""

from __future__ import annotations

import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from panther_ops.core.kinds.common import load_mapping
from panther_ops.core.kinds.registry import FileKindError, Target


def finding_line(f: Any) -> str:
    """A finding as `lights validate` / `bt validate` print it."""
    where = f" {f.where}" if f.where else ""
    return f"{f.severity.value} {f.message} ({f.code}){where}"


def split(findings: Sequence[Any]) -> tuple[list[str], list[str]]:
    errors = [finding_line(f) for f in findings if f.severity.value == "error"]
    warnings = [finding_line(f) for f in findings if f.severity.value != "error"]
    return errors, warnings


def on_disk(source: str, data: bytes, local: Path | None, check: Callable[[Path], list[str]]) -> list[str]:
    """Run a path-based validator on ``local``, or on a private copy of ``data``."""
    if local is not None and local.is_file() and local.read_bytes() == data:
        return check(local)
    with tempfile.TemporaryDirectory(prefix="panther-ops-check-") as tmp:
        path = Path(tmp) / (Path(source).name or "file")
        path.write_bytes(data)
        return check(path)


def _animations(source: str, data: bytes, local: Path | None, target: Target, what: str, key: str,
                hint: str) -> list[str]:
    """The manager's `validate_animations` with the lights rules of the robot's release (of the
    release the file's types name while no robot is known)."""
    from panther_ops.manager.lights.releases import release_for
    from panther_ops.manager.lights.validate import validate_animations

    doc = load_mapping(source, data, what)
    if key not in doc:
        raise FileKindError(source, what, [f"error no '{key}' list (anim-list-missing) {source}"], hint=hint)
    release = release_for(target.stack.version) if target.stack is not None else None

    def check(path: Path) -> list[str]:
        errors, warnings = split(validate_animations(path, release=release))
        if errors:
            raise FileKindError(source, what, errors, hint=f"panther-ops lights validate {source}")
        return warnings

    return on_disk(source, data, local, check)


def check_user_animations(source: str, data: bytes, local: Path | None, target: Target, force: bool) -> list[str]:
    return _animations(source, data, local, target, "animations", "user_animations",
                       "a user animations file lists its animations under user_animations:")


def check_led(source: str, data: bytes, local: Path | None, target: Target, force: bool) -> list[str]:
    return _animations(source, data, local, target, "animations", "led_animations",
                       "a led config has panels, segments, segments_map and led_animations "
                       "(user animations: --as user-animations)")
