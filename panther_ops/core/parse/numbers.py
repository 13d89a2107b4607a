"""Whole numbers, ports and ids as an operator writes them: ASCII digits only.

Python's ``int()``, ``str.isdigit()`` and ``re``'s ``\\d`` all take any Unicode decimal
digit (``"８０８１"`` is 8081 to them), but ``snap set``, docker compose, the RUTX11's API
and ROS parameters do not. Every file kind and command option parses its numbers here.
"""

from __future__ import annotations

import re

_INT = re.compile(r"[+-]?[0-9]+", re.ASCII)
_UINT = re.compile(r"[0-9]+", re.ASCII)


class NumberError(ValueError):
    """A text that is not the number asked for; ``str()`` says what is allowed."""


def ascii_int(text: str, *, signed: bool = False) -> int:
    """``text`` as an integer written in ASCII digits (a sign only when ``signed``); no
    spaces, underscores or other scripts' digits. Raises NumberError."""
    if not isinstance(text, str) or not (_INT if signed else _UINT).fullmatch(text):
        shown = "a whole number" + ("" if signed else " >= 0")
        raise NumberError(f"{shown} written in ASCII digits 0-9")
    return int(text)


def int_in_range(text: str, low: int, high: int) -> int:
    """``text`` as a whole number from ``low`` to ``high`` (ASCII digits). Raises NumberError."""
    try:
        value = ascii_int(text, signed=low < 0)
    except NumberError:
        raise NumberError(f"a whole number from {low} to {high} (ASCII digits 0-9)") from None
    if not low <= value <= high:
        raise NumberError(f"a whole number from {low} to {high}")
    return value


def port(value: object) -> int:
    """A TCP/UDP port, 1-65535: an int (not a bool) or its text in ASCII digits. Raises NumberError."""
    if isinstance(value, bool):
        raise NumberError("a port: a whole number from 1 to 65535")
    if isinstance(value, int):
        number = value
    elif isinstance(value, str) and _UINT.fullmatch(value):
        number = int(value)
    else:
        raise NumberError("a port: a whole number from 1 to 65535 (ASCII digits 0-9)")
    if not 1 <= number <= 65535:
        raise NumberError("a port: a whole number from 1 to 65535")
    return number


_MODE = re.compile(r"[0-7]{3,4}", re.ASCII)


def file_mode(value: object) -> int:
    """A file's permission bits as ``chmod`` writes them: the text of 3 or 4 ASCII octal
    digits (``"0644"``, ``"755"``). Raises NumberError."""
    if not isinstance(value, str) or not _MODE.fullmatch(value):
        raise NumberError("a file mode: 3 or 4 octal digits 0-7, e.g. '0644'")
    return int(value, 8)


def whole(value: object, low: int, high: int) -> int:
    """An integer setting from YAML or a command line: an int (not a bool) or its ASCII text,
    from ``low`` to ``high``. Raises NumberError."""
    if isinstance(value, bool):
        raise NumberError(f"a whole number from {low} to {high}")
    if isinstance(value, int):
        if not low <= value <= high:
            raise NumberError(f"a whole number from {low} to {high}")
        return value
    if isinstance(value, str):
        return int_in_range(value, low, high)
    raise NumberError(f"a whole number from {low} to {high}")
