"""The one shape of ``--json`` output (docs/json.md): every run prints exactly one document,
with ``schema``, ``command`` and ``exit_code`` first, errors included.

A command hands its document to :func:`hold` (through ``render.emit_json``); ``app.main``
writes it once the run's exit code is known (:func:`write`), or, when the run ended in an
error, the error's document instead: ``{"schema": 1, "command": ..., "exit_code": 2,
"error": {"type", "code", "message", "hint", ...}}``.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from panther_ops.errors import ExitCode

_held: dict[str, Any] = {}
"""The run's document while it is held (``doc``), and whether holding is on (``on``)."""


def start() -> None:
    """Hold the documents of this run until :func:`write` (``app.main`` calls it)."""
    _held.clear()
    _held["on"] = True


def hold(doc: dict[str, Any]) -> None:
    """The run's document: held while a run is on, else written at once."""
    from panther_ops.cli.output import write_json

    if not _held.get("on"):
        write_json(doc)
        return
    if "doc" in _held and _held.get("under") and _held["under"] not in _held["doc"]:
        _held["doc"][_held["under"]] = doc
        return
    if "doc" in _held:
        raise RuntimeError("a second JSON document in one run (docs/json.md: exactly one)")
    _held["doc"] = doc


@contextmanager
def under(key: str) -> Iterator[None]:
    """A command of several steps (``reimage restore``: the restore, then ``apply`` and ``doctor``):
    the document a later step gives goes into the run's document, under ``key``."""
    _held["under"] = key
    try:
        yield
    finally:
        _held.pop("under", None)


def hold_error(error: dict[str, Any]) -> None:
    """The run ends in this error (a command that says it on stderr and returns its exit code)."""
    if "doc" in _held:
        raise RuntimeError("an error after the run's JSON document (docs/json.md: exactly one)")
    _held["error"] = error


def write(command: str, code: int, error: dict[str, Any] | None = None) -> None:
    """The run's one document on stdout: the error's when ``error`` (or one held), else the
    command's (or, when it gave none, the envelope alone), with ``command`` and the run's real
    ``exit_code``."""
    from panther_ops.cli.output import write_json

    error = error if error is not None else _held.get("error")
    doc = {} if error is not None else _held.get("doc", {})
    _held.clear()
    head = {"schema": doc.get("schema", 1), "command": doc.get("command") or command, "exit_code": int(code)}
    write_json({**head, **{k: v for k, v in doc.items() if k not in head},
                **({"error": error} if error is not None else {})})


def drop() -> None:
    """Nothing is written for this run (stdout is gone)."""
    _held.clear()


def error_of(exc: BaseException, code: int, message: str | None = None) -> dict[str, Any]:
    """The ``error`` object of a document: what failed and what to do, as the message on stderr."""
    err: dict[str, Any] = {"type": type(exc).__name__, "code": ExitCode(code).name,
                           "message": message if message is not None else getattr(exc, "message", str(exc))}
    hint = getattr(exc, "hint", None)
    if hint:
        err["hint"] = hint
    for key in ("path", "line", "key", "robot"):
        value = getattr(exc, key, None)
        if value is not None:
            err[key] = value
    details = getattr(exc, "details", None)
    if details:
        err["details"] = details
    return err


def wanted(args: list[str]) -> bool:
    """Whether the command line asks for JSON (``--json`` before any ``--``)."""
    return "--json" in (args[:args.index("--")] if "--" in args else args)
