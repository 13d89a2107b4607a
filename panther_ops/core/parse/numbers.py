"""Whole numbers, ports, ids and decimal numbers as an operator writes them: ASCII digits only.

Python's ``int()``, ``float()``, ``str.isdigit()`` and ``re``'s ``\\d`` all take any Unicode
decimal digit (``"８０８１"`` is 8081 to them; ``float`` also takes ``"1_0"``, ``"nan"`` and
``"inf"``), but ``snap set``, docker compose, the RUTX11's API, ROS parameters and Gazebo's SDF
reader do not. Every file kind and command option parses its numbers here.
"""

from __future__ import annotations

import math
import re

_INT = re.compile(r"[+-]?[0-9]+", re.ASCII)
_UINT = re.compile(r"[0-9]+", re.ASCII)
_DECIMAL = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?", re.ASCII)


class NumberError(ValueError):
    """A text that is not the number asked for; ``str()`` says what is allowed."""


def _shown(number: float) -> str:
    return str(number) if isinstance(number, int) else f"{number:g}"


def _span(low: float, high: float | None) -> str:
    return f"from {_shown(low)} to {_shown(high)}" if high is not None else f"of {_shown(low)} or more"


def ascii_int(text: str, *, signed: bool = False) -> int:
    """``text`` as an integer written in ASCII digits (a sign only when ``signed``); no
    spaces, underscores or other scripts' digits. Raises NumberError."""
    if not isinstance(text, str) or not (_INT if signed else _UINT).fullmatch(text):
        shown = "a whole number" + ("" if signed else " >= 0")
        raise NumberError(f"{shown} written in ASCII digits 0-9")
    return int(text)


def int_in_range(text: str, low: int, high: int | None = None) -> int:
    """``text`` as a whole number from ``low`` to ``high`` (no upper bound: None), ASCII
    digits. Raises NumberError."""
    try:
        value = ascii_int(text, signed=low < 0)
    except NumberError:
        raise NumberError(f"a whole number {_span(low, high)} (ASCII digits 0-9)") from None
    if value < low or (high is not None and value > high):
        raise NumberError(f"a whole number {_span(low, high)}")
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


def whole(value: object, low: int, high: int | None = None) -> int:
    """An integer setting from YAML or a command line: an int (not a bool) or its ASCII text,
    from ``low`` to ``high`` (no upper bound: None). Raises NumberError."""
    if isinstance(value, bool):
        raise NumberError(f"a whole number {_span(low, high)}")
    if isinstance(value, int):
        if value < low or (high is not None and value > high):
            raise NumberError(f"a whole number {_span(low, high)}")
        return value
    if isinstance(value, str):
        return int_in_range(value, low, high)
    raise NumberError(f"a whole number {_span(low, high)}")


def decimal(value: object, low: float | None = None, high: float | None = None) -> float:
    """A real number from YAML, XML text or a command line: an int or float (not a bool) or
    its text in ASCII digits (``53.1978``, ``-12``, ``.5``, ``1e-3``; not ``nan``, ``inf``,
    ``1_0`` or other scripts' digits), finite, from ``low`` to ``high`` when given (either
    may be None). Raises NumberError."""
    if low is not None:
        shown = f"a number {_span(low, high)}"
    else:
        shown = f"a number up to {_shown(high)}" if high is not None else "a finite number"
    if isinstance(value, bool):
        raise NumberError(shown)
    if not isinstance(value, (int, float)) and not (isinstance(value, str) and _DECIMAL.fullmatch(value)):
        raise NumberError(f"{shown} written in ASCII digits 0-9, e.g. 1.5")
    number = float(value)
    if not math.isfinite(number) or (low is not None and number < low) or (high is not None and number > high):
        raise NumberError(shown)
    return number
