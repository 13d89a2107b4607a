"""How output looks, decided in one place for every command.

- Terminal or pipe: each stream (stdout for data, stderr for messages and progress) is
  looked at on its own, so ``panther-ops ... | less`` still shows colour on stderr.
- Colour: ``--color auto|always|never`` (a global option); ``auto`` colours a terminal
  unless ``NO_COLOR`` is set to anything non-empty (https://no-color.org); ``always``
  colours even a pipe; ``never`` never does.
- Width: the terminal's on a terminal, 160 columns in a pipe (tables are not squeezed
  to 80 columns in a log file). Tables fit that width (``cli/tables.py``); ``--wide``
  shows them whole, past the edge.
- Progress: live per-robot phases on stderr only when stderr is a terminal, never with
  ``--json`` or ``--quiet`` (``cli/progress.py``).
- A closed pipe (``panther-ops ... | head``): once the reader of stdout has gone, the rest of
  the output is dropped without a message and the exit code is 141, as a tool killed by
  SIGPIPE exits in a shell (``git log | head``). SIGPIPE itself stays ignored (Python's
  default): the SSH connections to robots are sockets, and a signal on writing to a closed
  one would kill the whole fleet run; the error a write raises instead (EPIPE) ends the run
  through :func:`reader_gone` in ``app.main``.
- Wrapping: table cells wrap to the width, and messages on a terminal (in a pipe a
  message stays one line); diffs and JSON never do (a diff
  line is written whole, running past the edge of a narrow terminal, so what is shown
  and copied is the exact patch, each line with its ``+``/``-``/space marker).
"""

from __future__ import annotations

import errno
import json
import os
import sys
from enum import Enum
from functools import cache
from typing import IO, Any

PIPE_WIDTH = 160
"""Columns of tables and wrapped text when the stream is not a terminal."""


class ColorMode(str, Enum):
    AUTO = "auto"
    ALWAYS = "always"
    NEVER = "never"


_state: dict[str, ColorMode] = {"color": ColorMode.AUTO}
_quiet: dict[str, bool] = {"quiet": False}
_wide: dict[str, bool] = {"wide": False}


def configure(color: ColorMode | str = ColorMode.AUTO, quiet: bool = False) -> None:
    """Set the run's colour mode and quietness (the root callback does, from ``--color``, ``--quiet``)."""
    _state["color"] = ColorMode(color)
    _quiet["quiet"] = quiet


def set_wide(on: bool) -> None:
    """``--wide``: tables show every column at its full width (``cli/tables.py``)."""
    _wide["wide"] = on


def wide() -> bool:
    return _wide["wide"]


def color_mode() -> ColorMode:
    return _state["color"]


def quiet() -> bool:
    """``--quiet``: no live progress and no recap."""
    return _quiet["quiet"]


def stream(stderr: bool = False) -> IO[str]:
    return sys.stderr if stderr else sys.stdout


def is_terminal(stderr: bool = False) -> bool:
    """Whether the stream is a terminal (a pseudo-terminal counts)."""
    s = stream(stderr)
    try:
        return bool(s.isatty())
    except (AttributeError, ValueError):  # closed or replaced streams
        return False


def use_color(stderr: bool = False) -> bool:
    mode = color_mode()
    if mode is ColorMode.ALWAYS:
        return True
    if mode is ColorMode.NEVER or os.environ.get("NO_COLOR", ""):
        return False
    return is_terminal(stderr)


def reader_gone() -> bool:
    """Whether stdout's or stderr's reader has gone (a closed pipe); each that has is pointed at
    /dev/null, so that nothing written or flushed later fails again."""
    import select

    gone = False
    for s in (sys.__stdout__, sys.__stderr__):
        try:
            fd = s.fileno() if s is not None else -1
            poll = select.poll()
            poll.register(fd, select.POLLOUT)
            closed = any(ev & (select.POLLERR | select.POLLHUP) for _, ev in poll.poll(0))
        except (AttributeError, OSError, ValueError):  # no file descriptor (a test's capture)
            continue
        if closed:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, fd)
            os.close(devnull)
            gone = True
    return gone


@cache
def _console_class() -> Any:
    """rich's Console, except on a closed pipe: rich's own answer (``SystemExit(1)``, "a bug"
    here) becomes the ``BrokenPipeError`` that ``app.main`` turns into the quiet exit 141."""
    from rich.console import Console

    class PipeConsole(Console):
        def on_broken_pipe(self) -> None:
            self.quiet = True
            raise BrokenPipeError(errno.EPIPE, "the reader of the output has gone")

    return PipeConsole


def console(stderr: bool = False) -> Any:
    """A rich console for the stream, set up by the rules above."""
    Console = _console_class()

    terminal = is_terminal(stderr)
    colour = use_color(stderr)
    return Console(
        file=stream(stderr),
        highlight=False,
        emoji=False,  # text from robots and files is shown as it is: ":x:" stays ":x:"
        soft_wrap=False,
        width=None if terminal else PIPE_WIDTH,
        force_terminal=True if colour and not terminal else None,  # --color always in a pipe
        no_color=not colour,
        color_system="auto" if colour else None,
    )


def print_exact(text: Any, stderr: bool = False) -> None:
    """Print rich Text (or a plain string) line for line: no wrapping, no cropping."""
    console(stderr).print(text, soft_wrap=True, crop=False, overflow="ignore", no_wrap=True)


def print_message(markup: str, stderr: bool = True) -> None:
    """A one-line message (rich markup): wrapped to a terminal's width, whole in a pipe (a log
    line stays one line for grep)."""
    console(stderr).print(markup, soft_wrap=not is_terminal(stderr))


def write_json(doc: Any) -> None:
    """One JSON document on stdout, never wrapped nor styled."""
    out = stream()
    out.write(json.dumps(doc, indent=2, default=str) + "\n")
    out.flush()


def write_bytes(data: bytes) -> None:
    """Bytes on stdout as they are (a file fetched from a robot)."""
    sys.stdout.buffer.write(data)
    sys.stdout.flush()
