"""Options where the user puts them: a global option after the command (``status -i demo``) and
a command's option before it (``--json status``) are moved to where click reads them.

click reads the root's options (``-i``, ``-v``, ``-q``, ``--debug``, ``--color``, ``--wide``)
only before the command word, and a command's only after it; without this, ``status -i demo``
said "No such option: -i" and ``--json status`` suggested ``--version``. An option the command
has itself stays where it is, and nothing after ``--`` is touched.
"""

from __future__ import annotations

from typing import Any


def _options(cmd: Any) -> dict[str, bool]:
    """Each option name of a click command -> whether it takes a value."""
    out: dict[str, bool] = {}
    for p in getattr(cmd, "params", []):
        if getattr(p, "param_type_name", "") != "option":
            continue
        takes = not (p.is_flag or p.count)
        for name in (*p.opts, *p.secondary_opts):
            out[name] = takes
    return out


def _split(token: str) -> tuple[str, bool]:
    """``--name=value`` -> (``--name``, True: the value is in the token)."""
    if token.startswith("--") and "=" in token:
        return token.split("=", 1)[0], True
    return token, False


def in_place(args: list[str], root: Any) -> list[str]:
    """``args`` with misplaced options moved (the same list when nothing is)."""
    globals_ = _options(root)
    front: list[str] = []
    moved_after: list[str] = []
    i = 0
    while i < len(args):  # before the command word: the root's options and the command's
        name, inline = _split(args[i])
        if not name.startswith("-") or name == "--":
            break
        if name in globals_:
            width = 1 if inline or not globals_[name] else 2
            front += args[i:i + width]
            i += width
        else:
            moved_after.append(args[i])  # not the root's: the command's (checked below)
            i += 1
    path: list[str] = []
    cmd = root
    while i < len(args) and args[i] in getattr(cmd, "commands", {}):
        cmd = cmd.commands[args[i]]
        path.append(args[i])
        i += 1
    if not path or hasattr(cmd, "commands"):
        return args  # no command, or a group without its subcommand: click says what is missing
    own = _options(cmd)
    if any(_split(a)[0] not in own for a in moved_after):
        return args  # not an option of the command either: click's own message names it
    rest: list[str] = []
    while i < len(args):
        token = args[i]
        name, inline = _split(token)
        if token == "--":
            rest += args[i:]
            break
        if name in own:
            width = 1 if inline or not own[name] else 2
            rest += args[i:i + width]
            i += width
        elif name in globals_ and name not in own:
            width = 1 if inline or not globals_[name] else 2
            front += args[i:i + width]
            i += width
        else:
            rest.append(token)
            i += 1
    moved = [*front, *path, *moved_after, *rest]
    return moved if moved != args else args
