"""Parsed local files (ssh_config, known_hosts) shared by every connection of a command.

A fleet command opens one SSH connection per robot; without this each connection would
parse the same ssh_config and known_hosts again (measured: over half of the client CPU of
connecting 30 lab robots). Entries are keyed by path, size and mtime, so a file that changes
(e.g. ``panther-ops trust`` recording a key) is parsed afresh.
"""

from __future__ import annotations

import os
import threading
from collections.abc import Callable
from typing import TypeVar

T = TypeVar("T")

_lock = threading.Lock()
_cache: dict[tuple[str, str, int, int], object] = {}
_parsing: dict[tuple[str, str, int, int], threading.Lock] = {}


def parsed(kind: str, path: str, parse: Callable[[str], T]) -> T | None:
    """``parse(path)``, once per version of the file; None when the file does not exist.

    Connections that ask together (a command's first ``--forks`` connections start at once)
    wait for one parse: each parsing it was measured at 300 robots as 32 parses of a 300-line
    known_hosts, whose paramiko load is quadratic in its lines (issue 29). A parse that
    raises is not remembered: the next caller parses again.
    """
    try:
        st = os.stat(path)
    except OSError:
        return None
    key = (kind, path, st.st_size, st.st_mtime_ns)
    with _lock:
        if key in _cache:
            return _cache[key]  # type: ignore[return-value]
        one_parse = _parsing.setdefault(key, threading.Lock())
    with one_parse:
        with _lock:
            if key in _cache:
                return _cache[key]  # type: ignore[return-value]
        try:
            value = parse(path)
        except BaseException:
            with _lock:  # nothing is left behind for a version that did not parse
                _parsing.pop(key, None)
            raise
        with _lock:
            _cache[key] = value
            _parsing.pop(key, None)
    return value
