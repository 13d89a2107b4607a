"""The options fleet commands share, declared once, and :func:`shared`, which gives a command
the ones it takes.

A command names the shared options it takes (``@shared(*READ)``, ``@shared(*GATED)``...) and
declares only its own; it receives the shared ones as one :class:`~panther_ops.cli.context.Fleet`
(its first parameter), which selects the robots, runs the task, renders and returns the exit
code. --help lists a command's arguments, then the robot selection, then its own options, then
the shared ones in the order of ``_SHARED``.
"""

from __future__ import annotations

import copy
import inspect
import typing
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Optional, TypeVar

import typer
from typer.models import ArgumentInfo

from panther_ops.cli import complete
from panther_ops.cli.context import Fleet

if TYPE_CHECKING:
    from panther_ops.secret import Secret


def _number_parser(name: str, parse: Callable[[Any], Any]) -> Callable[[Any], Any]:
    """An option's ``parser=`` around a `core.parse.numbers` helper: its refusal as click's
    "Invalid value for '--opt'" (exit 2). ``name`` is click's type name (the metavar)."""

    def convert(value: Any) -> Any:
        from panther_ops.core.parse.numbers import NumberError

        try:
            return parse(value)
        except NumberError as exc:
            raise typer.BadParameter(f"{value!r} is not {exc}") from None

    convert.__name__ = name
    return convert


def whole_number(low: int, high: int | None = None) -> Callable[[Any], int]:
    """``parser=`` of an integer option or argument (a count, an id): ASCII digits, from
    ``low`` to ``high`` (click's ``int`` takes any script's digits and ``1_000``)."""
    from panther_ops.core.parse.numbers import whole

    return _number_parser("integer", lambda value: whole(value, low, high))


def port_number() -> Callable[[Any], int]:
    """``parser=`` of a TCP/UDP port option: 1-65535 in ASCII digits."""
    from panther_ops.core.parse.numbers import port

    return _number_parser("integer", port)


def real_number(low: float | None = None, high: float | None = None) -> Callable[[Any], float]:
    """``parser=`` of a decimal option (seconds, Hz, degrees): ASCII digits, finite, from
    ``low`` to ``high`` when given (click's ``float`` takes ``nan``, ``inf``, ``1_0`` and any
    script's digits)."""
    from panther_ops.core.parse.numbers import decimal

    return _number_parser("float", lambda value: decimal(value, low, high))


OptStr = Optional[str]  # noqa: UP045 - typer needs Optional on Python 3.10
OptInt = Optional[int]  # noqa: UP045
OptFloat = Optional[float]  # noqa: UP045
OptBool = Optional[bool]  # noqa: UP045
OptPath = Optional[Path]  # noqa: UP045
"""An option's type when it may be left out (typer needs Optional on Python 3.10)."""

Robots = Annotated[
    Optional[list[str]],  # noqa: UP045 - typer needs Optional on Python 3.10
    typer.Option("--robot", "-r", help="Robot name or glob (repeatable), e.g. -r 'panther-0*'.",
                 autocompletion=complete.robots),
]
Groups = Annotated[
    Optional[list[str]],  # noqa: UP045
    typer.Option("--group", "-g", help="Inventory group (repeatable).", autocompletion=complete.groups),
]
All = Annotated[bool, typer.Option("--all", help="Every robot of the inventory.")]
Json = Annotated[bool, typer.Option("--json", help="One versioned JSON document on stdout (docs/json.md).")]
Forks = Annotated[
    Optional[int],  # noqa: UP045
    typer.Option("--forks", "-f", parser=whole_number(1, 500),
                 help="Robots worked on at once, 1-500 (default: the inventory's settings.forks, else 100)."),
]
Canary = Annotated[
    int, typer.Option("--canary", parser=whole_number(0), help="Run N robots first; stop if one of them fails.")
]
MaxFail = Annotated[
    Optional[float],  # noqa: UP045
    typer.Option("--max-fail", parser=real_number(0, 100),
                 help="Stop starting robots once more than PCT % failed (0-100)."),
]
Yes = Annotated[bool, typer.Option("--yes", "-y", help="Apply without asking.")]
DryRun = Annotated[bool, typer.Option("--dry-run", help="Show the exact diffs; write nothing anywhere.")]
NoRestart = Annotated[bool, typer.Option("--no-restart", help="Write the files but do not recreate containers.")]
Settle = Annotated[
    float, typer.Option("--settle", parser=real_number(0),
                        help="Upper bound in seconds on the wait for a recreated container to be ready "
                             "(up and unrestarted for 2 s); a crash within it rolls back.")
]
Force = Annotated[bool, typer.Option("--force", help="Accept unknown keys and values beyond limits (with a warning).")]
Lines = Annotated[
    Optional[int],  # noqa: UP045
    typer.Option("--lines", "-n", parser=whole_number(0),
                 help="Last N lines of each robot (default 100; 0 with -f: only new)."),
]
Follow = Annotated[bool, typer.Option("--follow", "-f", help="Keep printing new lines (one robot; Ctrl-C ends).")]
Timestamps = Annotated[bool, typer.Option("--timestamps", "-t", help="Docker's timestamp on each line.")]
"""The options of a container's logs (`driver logs`, `manager logs`)."""

LocalFile = Annotated[
    OptPath,
    typer.Option("--file", help="A local hosts file (`shutdown hosts add|remove FILE`): its backups, kept "
                 "beside it, instead of robots'.", show_default=False),
]
"""`config history|rollback --file`: a local hosts file instead of the robots."""

PASSWORD_ENV = "PANTHER_OPS_SUDO_PASSWORD"
AskPassword = Annotated[bool, typer.Option(
    "--ask-sudo-password", help=f"Ask once for the User Computers' sudo password (else ${PASSWORD_ENV}, else "
    "sudo must not ask).")]


def sudo_password(ask: bool) -> Secret | None:
    """The User Computers' sudo password: asked once (``--ask-sudo-password``), else the
    environment's, else None (sudo must not ask). Never stored or printed."""
    import os

    from panther_ops.secret import Secret

    if ask:
        import getpass

        return Secret(getpass.getpass("sudo password of the User Computers: "))
    value = os.environ.get(PASSWORD_ENV)
    return Secret(value) if value else None


_SHARED: dict[str, tuple[Any, Any]] = {
    "robot": (Robots, None), "group": (Groups, None), "all_": (All, False),
    "yes": (Yes, False), "dry_run": (DryRun, False), "no_restart": (NoRestart, False), "settle": (Settle, 5.0),
    "json_out": (Json, False), "forks": (Forks, None), "canary": (Canary, 0), "max_fail": (MaxFail, None),
}
"""Each shared option: the parameter's name (a field of Fleet), its declaration and default."""

TARGETS = ("robot", "group", "all_")
READ = (*TARGETS, "json_out", "forks")
"""A command that reads the robots."""
WRITE = (*TARGETS, "yes", "dry_run", "no_restart", "settle", "json_out", "forks")
"""A change through the pipeline."""
GATED = (*WRITE, "canary", "max_fail")
"""A change through the pipeline, rolled out with --canary and --max-fail."""
RECREATE = tuple(n for n in WRITE if n != "no_restart")
"""A change whose point is to recreate containers (no --no-restart)."""


R = TypeVar("R")


def shared(*names: str, helps: dict[str, str] | None = None) -> Callable[[Callable[..., R]], Callable[..., R]]:
    """Give a command the shared options ``names`` (``helps``: another help text for some).

    The command's first parameter receives them as a :class:`Fleet` (with the context); its
    other parameters are its own options and arguments, declared as usual.
    """
    unknown = set(names) - set(_SHARED) or set(helps or {}) - set(names)
    if unknown:
        raise ValueError(f"not shared options of this command: {sorted(unknown)}")

    def decorate(fn: Callable[..., R]) -> Callable[..., R]:
        sig = inspect.signature(fn, eval_str=True)
        own = list(sig.parameters.values())[1:]

        def command(ctx: typer.Context, **given: Any) -> R:
            return fn(Fleet(ctx, **{n: given.pop(n) for n in names}), **given)

        params = [inspect.Parameter("ctx", inspect.Parameter.KEYWORD_ONLY, annotation=typer.Context)]
        params += [p for p in own if _is_argument(p)]
        params += [_parameter(n, helps) for n in names if n in TARGETS]
        params += [p for p in own if not _is_argument(p)]
        params += [_parameter(n, helps) for n in _SHARED if n in names and n not in TARGETS]
        command.__signature__ = inspect.Signature(  # type: ignore[attr-defined]
            [p.replace(kind=inspect.Parameter.KEYWORD_ONLY) for p in params], return_annotation=sig.return_annotation)
        command.__annotations__ = {p.name: p.annotation for p in params} | {"return": sig.return_annotation}
        command.__name__, command.__qualname__ = fn.__name__, fn.__qualname__
        command.__doc__, command.__module__ = fn.__doc__, fn.__module__
        return command

    return decorate


def _is_argument(p: inspect.Parameter) -> bool:
    return any(isinstance(m, ArgumentInfo) for m in getattr(p.annotation, "__metadata__", ()))


def _parameter(name: str, helps: dict[str, str] | None) -> inspect.Parameter:
    declared, default = _SHARED[name]
    if helps and name in helps:
        kind, info = typing.get_args(declared)
        info = copy.copy(info)
        info.help = helps[name]
        declared = Annotated[kind, info]
    return inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=default, annotation=declared)
