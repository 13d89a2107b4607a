"""panther-ops: the typer application and the error funnel.

Only typer is imported at start-up; each command imports the core when it runs, so
``panther-ops --help`` stays instant.
"""

from __future__ import annotations

import logging
import os
import sys
from typing import TYPE_CHECKING, Annotated, Any, Optional

import typer
from typer.core import TyperGroup

from panther_ops import __version__
from panther_ops.cli.context import Settings
from panther_ops.cli.output import ColorMode

if TYPE_CHECKING:
    from typer.models import CommandInfo, TyperInfo

HELP = """Fleet operations and configuration for Husarion Panther robots (ROS 2 Humble and Jazzy).

Works on one robot or a whole fleet from an inventory (-i FILE|DIR, else
$PANTHER_OPS_INVENTORY, else ./inventory/). Choose robots with --robot/-r (globs),
--group/-g or --all; a one-robot inventory needs none.

Exit codes: 0 ok, 1 unexpected error, 2 bad input (nothing done), 3 some robots failed,
rolled back or were unreachable, 4 every robot unreachable, 5 declined at the confirmation,
6 config diff --exit-code found drift, 130 interrupted, 141 stdout closed (| head).

\b
Try the demo fleet (no robot needed):
  panther-ops demo init
  panther-ops -i demo-fleet status --all

\b
Shell completion (bash, zsh, fish, docs/getting-started.md):
  panther-ops --install-completion
"""

class _Root(TyperGroup):
    """The root command. Completing a line (click parses it resiliently), its options are read
    where a run reads them (cli/argv_order.py): ``status -i demo -r <TAB>`` completes the robots
    of ``demo``, as ``-i demo status -r <TAB>`` does."""

    def parse_args(self, ctx: Any, args: list[str]) -> list[str]:  # typer's own click Context
        if ctx.resilient_parsing:
            from panther_ops.cli.argv_order import in_place

            args = in_place(args, self)
        return super().parse_args(ctx, args)


app = typer.Typer(
    name="panther-ops",
    cls=_Root,
    help=HELP,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
    add_completion=True,
    context_settings={"help_option_names": ["-h", "--help"]},
)


def _version(value: bool) -> None:
    if value:
        typer.echo(f"panther-ops {__version__}")
        raise typer.Exit()


@app.callback()
def root(
    ctx: typer.Context,
    inventory: Annotated[
        Optional[str],  # noqa: UP045
        typer.Option("--inventory", "-i", help="Inventory file or directory.", envvar=None),
    ] = None,
    verbose: Annotated[int, typer.Option("--verbose", "-v", count=True, help="More detail on stderr.")] = 0,
    debug: Annotated[bool, typer.Option("--debug", help="Show tracebacks of unexpected errors.")] = False,
    color: Annotated[
        ColorMode, typer.Option("--color", help="Colour: auto (a terminal, unless NO_COLOR is set), always, never.")
    ] = ColorMode.AUTO,
    quiet: Annotated[
        bool, typer.Option("--quiet", "-q", help="No live progress and no recap on stderr.")
    ] = False,
    wide: Annotated[
        bool, typer.Option("--wide", help="Tables with every column at full width (past the terminal's edge).")
    ] = False,
    version: Annotated[
        bool, typer.Option("--version", callback=_version, is_eager=True, help="Print the version.")
    ] = False,
) -> None:
    """Global options go before or after the command: panther-ops -i fleet.yaml status --all."""
    from panther_ops.cli.output import configure, set_wide

    configure(color, quiet)
    set_wide(wide)
    ctx.obj = Settings(inventory=inventory, verbose=verbose, debug=debug)
    level = logging.DEBUG if debug else (logging.INFO if verbose else logging.WARNING)
    logging.basicConfig(level=level, format="%(levelname)s %(name)s: %(message)s", stream=sys.stderr)
    if not debug:
        logging.getLogger("paramiko").setLevel(logging.CRITICAL)


_ORDER = ("fleet", "config", "driver", "trust", "shutdown", "inventory", "demo", "bt", "lights", "manager",
          "gps", "sim", "estop", "webui", "teleop", "reimage")
"""Command modules in the order --help lists them."""
_NEEDS = {
    "status": ("fleet",), "doctor": ("fleet",), "config": ("config", "driver"), "apply": ("config",),
    "driver": ("driver",), "trust": ("trust",), "shutdown": ("shutdown",), "inventory": ("inventory",),
    "demo": ("demo",), "bt": ("bt",), "lights": ("lights",), "manager": ("manager",),
    "gps": ("gps",), "sim": ("sim",), "estop": ("estop",), "webui": ("webui",), "teleop": ("teleop",),
    "reimage": ("reimage",), "describe": ("fleet",),
}
"""Top-level command word -> the modules that register it (config gains restore-defaults from driver)."""
_registered: dict[str, tuple[list[CommandInfo], list[TyperInfo]]] = {}


def _register_module(name: str) -> None:
    import importlib

    if name in _registered:
        return
    mod = importlib.import_module(f"panther_ops.cli.commands.{name}")
    commands, groups = len(app.registered_commands), len(app.registered_groups)
    if hasattr(mod, "register"):
        mod.register(app)
    else:
        app.add_typer(mod.app, name=name)
    _registered[name] = (app.registered_commands[commands:], app.registered_groups[groups:])


def _register(command: str | None = None, sub: str | None = None) -> None:
    """Register the commands a run needs: those of a known command word, else all of them.

    typer builds every registered command (parameters, converters, their annotations) on
    each run, so a fleet command registers only its own word, and of a group only the
    subcommand named (``sub``) when the group has it; --help, an unknown word or no word
    gets them all.
    """
    for name in _NEEDS.get(command or "", _ORDER):
        _register_module(name)
    commands = [c for n in _ORDER if n in _registered for c in _registered[n][0]]
    groups = [g for n in _ORDER if n in _registered for g in _registered[n][1]]
    if command is not None and (any(_name(c) == command for c in commands) or any(g.name == command for g in groups)):
        commands = [c for c in commands if _name(c) == command]
        groups = [_only(g, sub) for g in groups if g.name == command]
    app.registered_commands[:] = commands
    app.registered_groups[:] = groups


def full_command() -> Any:
    """The click command of the whole application with every command registered (tests walk
    it to reach every command and subcommand)."""
    from typer.main import get_command

    _register()
    return get_command(app)


def _name(info: CommandInfo) -> str:
    """The word a registered command answers to (typer's rule when none was given)."""
    from typer.main import get_command_name

    return info.name or get_command_name(getattr(info.callback, "__name__", ""))


def _only(group: TyperInfo, sub: str | None) -> TyperInfo:
    """``group`` with only its command ``sub`` (when it has one by that name), else as it is."""
    import copy

    inner = group.typer_instance
    if sub is None or inner is None or not any(_name(c) == sub for c in inner.registered_commands):
        return group
    narrowed = copy.copy(inner)
    narrowed.registered_commands = [c for c in inner.registered_commands if _name(c) == sub]
    narrowed.registered_groups = []
    only = copy.copy(group)
    only.typer_instance = narrowed
    return only


def _command_words(argv: list[str]) -> tuple[str | None, str | None]:
    """The command word after the global options and the word after it (a group's
    subcommand) when it is one; None with --help/--version or none given."""
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in ("-h", "--help", "--version"):
            return None, None
        if a in ("--inventory", "--color"):
            i += 2
        elif a.startswith("--"):
            i += 1
        elif a.startswith("-") and len(a) > 1:
            flags = a[1:]
            i += 2 if flags.endswith("i") else 1  # -i PATH, -vi PATH; -iPATH carries its value
        else:
            sub = argv[i + 1] if i + 1 < len(argv) and not argv[i + 1].startswith("-") else None
            return a, sub
    return None, None


def main(argv: list[str] | None = None) -> int:
    """Entry point: runs the app and turns every outcome into the documented exit code; with
    --json, stdout gets the run's one document, an error's included (cli/envelope.py)."""
    from panther_ops.cli import envelope
    from panther_ops.errors import ExitCode

    args = list(sys.argv[1:] if argv is None else argv)
    _register(*_command_words(args))
    args = _in_place(args)
    envelope.start()
    try:
        rv = app(args=args, standalone_mode=False, prog_name="panther-ops")
        code, error = (int(rv) if isinstance(rv, int) else 0), None
    except BaseException as exc:  # each kind is one exit code (docs/results.md), in _ended
        ended = _ended(exc, "--debug" in args)
        if ended is None:
            raise
        code, error = ended
    if code == ExitCode.CLOSED_PIPE or not envelope.wanted(args):
        envelope.drop()
        return code
    try:
        envelope.write(_command_name(args), code, error)
    except BrokenPipeError:
        if not _reader_gone():
            raise
        return int(ExitCode.CLOSED_PIPE)
    return code


def _ended(exc: BaseException, debug: bool) -> tuple[int, dict[str, Any] | None] | None:
    """How a run that raised ``exc`` ends: its exit code and the JSON ``error`` object, after the
    message on stderr; None: raise it again (--debug, or an exit that is not ours)."""
    try:  # typer >= 0.2x vendors click
        from typer._click.exceptions import ClickException
    except ImportError:  # pragma: no cover - older typer on plain click
        from click.exceptions import ClickException  # type: ignore[assignment,unused-ignore]

    from panther_ops.cli.envelope import error_of
    from panther_ops.cli.render import error
    from panther_ops.errors import Declined, ExitCode, OpsError
    from panther_ops.manager.errors import ManagerError

    if isinstance(exc, Declined):  # the operator said no: not an error (exit 5, docs/results.md)
        sys.stderr.write(f"{exc}\n")
        return int(exc.exit_code), error_of(exc, exc.exit_code)
    if isinstance(exc, (OpsError, ManagerError)):  # a file the manager reads is bad input too
        code = int(exc.exit_code) if isinstance(exc, OpsError) else int(ExitCode.USAGE)
        error(str(exc))
        return code, error_of(exc, code)
    if isinstance(exc, typer.Exit):
        return int(getattr(exc, "exit_code", 0)), None
    if isinstance(exc, (typer.Abort, KeyboardInterrupt)):
        said = "aborted" if isinstance(exc, typer.Abort) else "interrupted"
        sys.stderr.write(f"{said}\n")
        return int(ExitCode.INTERRUPTED), error_of(exc, ExitCode.INTERRUPTED, said)
    if isinstance(exc, ClickException):
        exc.show()
        return int(ExitCode.USAGE), error_of(exc, ExitCode.USAGE, exc.format_message())
    closed = exc if isinstance(exc, BrokenPipeError) else exc.__context__ if isinstance(exc, SystemExit) else None
    if isinstance(closed, BrokenPipeError) and _reader_gone():  # rich and click: SystemExit(1) on EPIPE
        return int(ExitCode.CLOSED_PIPE), None
    if isinstance(exc, Exception) and not debug:
        log = _internal_error()
        said = f"internal error (a bug): traceback written to {log}; please report it"
        return int(ExitCode.ERROR), error_of(exc, ExitCode.ERROR, said)
    return None


def _in_place(args: list[str]) -> list[str]:
    """Global options after the command, and a command's options before it, moved to where
    click reads them (cli/argv_order.py)."""
    from typer.main import get_command

    from panther_ops.cli.argv_order import in_place

    return in_place(args, get_command(app))


def _command_name(args: list[str]) -> str:
    """The command's words (``shutdown hosts list``) as the command line gives them."""
    from typer.main import get_command

    first, _ = _command_words(args)
    if first is None:
        return ""
    words: list[str] = []
    cmd: Any = get_command(app)
    for word in args[args.index(first):]:
        sub = getattr(cmd, "commands", {}).get(word)
        if sub is None:
            break
        words.append(word)
        cmd = sub
    return " ".join(words)


def _reader_gone() -> bool:
    """``... | head``: the reader of the output has what it wanted and went away; the rest is
    dropped without a message (docs/results.md, exit 141)."""
    from panther_ops.cli.output import reader_gone

    return reader_gone()


def _internal_error() -> str:
    """An unexpected error (a bug): its traceback written to a debug log (--debug shows it
    instead), said on stderr; the log's path."""
    import tempfile
    import traceback

    with tempfile.NamedTemporaryFile("w", prefix="panther-ops-debug-", suffix=".log", delete=False) as fh:
        traceback.print_exc(file=fh)
    sys.stderr.write(f"internal error (a bug): traceback written to {fh.name}; please report it\n")
    return fh.name


def run() -> None:
    """Console entry point: ``main()``, then leave without the interpreter's slow teardown.

    After a fleet command, dozens of SSH transports and their threads are being torn down;
    the results are already printed, so the process exits at once once output is flushed.
    """
    code = main()
    logging.shutdown()
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except BrokenPipeError:
        from panther_ops.errors import ExitCode

        if _reader_gone():
            code = int(ExitCode.CLOSED_PIPE)
    os._exit(code)


if __name__ == "__main__":
    run()
