"""The parsed YAML of inventory files, kept between commands (``~/.cache/panther-ops/inventory/``).

Every fleet command reads the inventory before it can reach any robot, and reading YAML
begins with importing PyYAML (~10 ms here, most of it compiling its regular expressions),
all before the first connection. An inventory file that did not change since an earlier
command is read back from JSON instead (~0.3 ms). An entry is named by the file's real
path, inode, size and change times (ns) and this release of panther-ops: any change to the
file makes a new entry. Only the YAML document is kept, with the line of every key and
item; the inventory is validated from it every time, exactly as from the file. Documents
holding values JSON cannot carry (dates, binary, sets) are not kept.

The directory must belong to the user and be writable by nobody else (it is created so),
else it is not used; ``PANTHER_OPS_CACHE_DIR`` moves it and an empty value turns it off.
At most :data:`KEEP` entries are kept (the oldest go first).
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

from panther_ops import __version__
from panther_ops.core.yaml.located import LineDict, LineList

FORMAT = 1
KEEP = 32


class _Unsupported(Exception):
    """A value JSON cannot carry exactly."""


def cache_dir() -> Path | None:
    """Where entries live (created private when missing); None when off or not private."""
    configured = os.environ.get("PANTHER_OPS_CACHE_DIR")
    if configured is not None and not configured.strip():
        return None
    if configured:
        base = Path(configured).expanduser()
    else:
        base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "panther-ops" / "inventory"
    try:
        base.mkdir(mode=0o700, parents=True, exist_ok=True)
        st = base.stat()
    except OSError:
        return None
    if st.st_uid != os.getuid() or st.st_mode & 0o022:
        return None
    return base


def _key(path: Path) -> str | None:
    try:
        real = path.resolve()
        st = real.stat()
    except OSError:
        return None
    ident = f"{FORMAT}\0{__version__}\0{real}\0{st.st_ino}\0{st.st_size}\0{st.st_mtime_ns}\0{st.st_ctime_ns}"
    return hashlib.sha256(ident.encode()).hexdigest()


def _encode(value: Any) -> Any:
    if isinstance(value, LineDict):
        return {"d": [[k, value.key_lines.get(k, value.line), _encode(v)] for k, v in value.items()],
                "l": value.line}
    if isinstance(value, LineList):
        return {"a": [_encode(v) for v in value], "l": value.line, "i": list(value.item_lines)}
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    raise _Unsupported(type(value).__name__)


def _decode(value: Any) -> Any:
    if isinstance(value, dict):
        if "d" in value:
            out = LineDict()
            out.line = value["l"]
            out.key_lines = {}
            for k, line, v in value["d"]:
                out[k] = _decode(v)
                out.key_lines[k] = line
            return out
        seq = LineList(_decode(v) for v in value["a"])
        seq.line = value["l"]
        seq.item_lines = list(value["i"])
        return seq
    return value


def load(path: Path, parse: Callable[[Path], Any]) -> Any:
    """The YAML document of ``path``: from the cache when the file is unchanged, else
    ``parse(path)`` (its errors pass through; nothing is kept for a file that fails)."""
    where = cache_dir()
    key = _key(path) if where is not None else None
    if where is None or key is None:
        return parse(path)
    entry = where / f"{key}.json"
    try:
        if entry.stat().st_uid == os.getuid():
            return _decode(json.loads(entry.read_text(encoding="utf-8")))
    except (OSError, ValueError, KeyError, TypeError):
        pass  # missing or unreadable: parse and keep a new one
    doc = parse(path)
    try:
        text = json.dumps(_encode(doc), separators=(",", ":"))
    except _Unsupported:
        return doc
    _keep(where, entry, text)
    return doc


def _keep(where: Path, entry: Path, text: str) -> None:
    """Write an entry atomically; drop the oldest beyond :data:`KEEP`. Failures are ignored
    (the cache only saves time)."""
    import tempfile

    try:
        fd, tmp = tempfile.mkstemp(dir=where, prefix=".entry.", suffix=".tmp")
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
        os.replace(tmp, entry)
        entries = sorted(where.glob("*.json"), key=lambda p: p.stat().st_mtime_ns)
        for old in entries[:-KEEP]:
            old.unlink(missing_ok=True)
    except OSError:
        return
