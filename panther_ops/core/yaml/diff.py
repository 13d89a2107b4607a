"""Unified diffs of configuration files, as shown to the operator before a change."""

from __future__ import annotations

import difflib

NO_NEWLINE = "\\ No newline at end of file"


def _header_path(path: str) -> str:
    """``/home/husarion/compose.yaml`` -> ``home/husarion/compose.yaml`` (so ``a/`` + it reads well)."""
    return path.lstrip("/")


def unified_diff(before: str | None, after: str | None, path: str, *, context: int = 3) -> str:
    """A unified diff from ``before`` to ``after`` with ``a/`` and ``b/`` headers.

    ``path`` is the file's path on the robot; a leading ``/`` is dropped, so
    ``/home/husarion/compose.yaml`` gives ``--- a/home/husarion/compose.yaml`` and
    ``+++ b/home/husarion/compose.yaml`` (``patch -p1`` applies it from ``/``). A file that
    does not exist (``None``: one the change creates, or removes) is ``/dev/null`` in its
    header, as diff(1) -N and git write it, so ``patch`` creates or deletes it.
    Identical texts give ``""``. A last line without a newline is marked with
    ``\\ No newline at end of file`` as diff(1) and git do. The result ends with a newline.
    """
    if before == after:
        return ""
    name = _header_path(path)
    a = (before or "").splitlines(keepends=True)
    b = (after or "").splitlines(keepends=True)
    old = "/dev/null" if before is None else f"a/{name}"
    new = "/dev/null" if after is None else f"b/{name}"
    out: list[str] = []
    for line in difflib.unified_diff(a, b, old, new, n=context):
        if line.endswith("\n"):
            out.append(line)
        else:
            out.append(line + "\n")
            out.append(NO_NEWLINE + "\n")
    return "".join(out)


def changed_lines(diff: str) -> list[str]:
    """The ``-``/``+`` lines of a unified diff (without the ``---``/``+++`` headers)."""
    return [
        line
        for line in diff.splitlines()
        if line[:1] in "+-" and not line.startswith(("--- ", "+++ "))
    ]


def under_directory(diff: str, directory: str) -> str:
    """The same diff for a tree one level up: its file headers gain ``directory/``.

    ``--- a/home/husarion/compose.yaml`` becomes ``--- a/panther-01/home/husarion/compose.yaml``
    (and ``+++ b/...`` alike), so the diffs of several robots make one patch that applies with
    ``patch -p1`` in the directory that holds one directory per robot. Only the headers before the
    first hunk are touched: a removed line that reads ``-- a/x`` stays what it is.
    """
    lines = diff.splitlines(keepends=True)
    for i, line in enumerate(lines):
        if line.startswith("@@"):
            break
        for marker in ("--- a/", "+++ b/"):
            if line.startswith(marker):
                lines[i] = f"{marker}{directory}/{line[len(marker):]}"
    return "".join(lines)
