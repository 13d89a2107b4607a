"""What the shutdown commands take besides the shared options: a local hosts file, the power
budget, the shared secret of HTTP hosts (docs/shutdown.md)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Optional

import typer

from panther_ops.cli.options import OptPath, OptStr, real_number

if TYPE_CHECKING:
    from panther_ops.secret import Secret

FileArg = Annotated[
    Optional[Path],  # noqa: UP045 - typer needs Optional on Python 3.10
    typer.Argument(help="A local hosts file (instead of -r ROBOT).", show_default=False),
]
PowerBudget = Annotated[
    float,
    typer.Option("--power-budget", parser=real_number(0.1),
                 help="Seconds the robot's hardware gives its computers before it cuts "
                 "the power (a timeout above it is warned)."),
]
SecretEnv = Annotated[OptStr, typer.Option("--secret-env", metavar="VAR",
                                           help="HTTP hosts: the shared secret from this environment variable.")]
SecretFile = Annotated[OptPath, typer.Option("--secret-file", metavar="PATH",
                                             help="HTTP hosts: the shared secret from this file.")]
AskSecret = Annotated[bool, typer.Option("--ask-secret", help="HTTP hosts: ask for the shared secret.")]


def usage_error(message: str, hint: str | None = None) -> Exception:
    from panther_ops.errors import UsageError

    return UsageError(message, hint=hint)


def ask_to_confirm(question: str, yes: bool, what: str) -> bool:
    from panther_ops.cli.mutate import confirm

    return confirm(question, yes, refusal(question, what))


def refusal(question: str, what: str) -> str:
    return f"{question} -- {what} needs confirmation: pass --yes when not interactive (or --dry-run to only look)"


def secret_from(env: str | None, file: Path | None, ask: bool) -> Secret | None:
    import getpass
    import os

    from panther_ops.secret import Secret

    given = [x for x in (env, file, ask or None) if x]
    if len(given) > 1:
        raise usage_error("give the secret one way: --secret-env, --secret-file or --ask-secret")
    if env:
        value = os.environ.get(env)
        if value is None:
            raise usage_error(f"--secret-env {env}: the variable is not set")
        return Secret(value)
    if file:
        try:
            return Secret(file.read_text().strip())
        except OSError as exc:
            raise usage_error(f"--secret-file {file}: {exc.strerror}") from None
    if ask:
        return Secret(getpass.getpass("shared secret of the husarion-shutdown service: "))
    return None
