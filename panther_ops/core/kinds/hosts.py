"""The shutdown hosts file: `core.shutdown.hostsfile.parse_hosts`, as `shutdown hosts validate`."""

from __future__ import annotations

from pathlib import Path

from panther_ops.core.kinds.common import text_of
from panther_ops.core.kinds.registry import FileKindError, Target

WHAT = "shutdown hosts file"


def check_shutdown_hosts(source: str, data: bytes, local: Path | None, target: Target, force: bool) -> list[str]:
    from panther_ops.core.kinds.hostsfile import Mode, parse_hosts

    text = text_of(source, data, WHAT)
    mode = None
    if target.stack is not None:
        mode = Mode.HTTP if target.stack.shutdown_over_http else Mode.SSH
    # a file for a robot holds the secret itself: {env:}/{file:} references are for local files
    parsed = parse_hosts(text, source, mode=mode, allow_refs=target.stack is None,
                         base=local.parent if local else None)
    if parsed.errors:
        raise FileKindError(source, WHAT, [str(f) for f in parsed.errors],
                            hint=f"panther-ops shutdown hosts validate {source}")
    return [str(f) for f in parsed.warnings]
