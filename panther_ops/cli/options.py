"""Options shared by fleet commands (targets, output, parallelism)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Optional

import typer

if TYPE_CHECKING:
    from panther_ops.secret import Secret


def finite(value: float | None) -> float | None:
    """Option callback: a number of seconds or a percentage must be finite (click's float
    ranges let ``nan`` through, and ``inf`` means "forever")."""
    import math

    if value is not None and not math.isfinite(value):
        raise typer.BadParameter(f"{value} is not a finite number")
    return value


Robots = Annotated[
    Optional[list[str]],  # noqa: UP045 - typer needs Optional on Python 3.10
    typer.Option("--robot", "-r", help="Robot name or glob (repeatable), e.g. -r 'panther-0*'."),
]
Groups = Annotated[
    Optional[list[str]],  # noqa: UP045
    typer.Option("--group", "-g", help="Inventory group (repeatable)."),
]
All = Annotated[bool, typer.Option("--all", help="Every robot of the inventory.")]
Json = Annotated[bool, typer.Option("--json", help="One versioned JSON document on stdout (docs/json.md).")]
Forks = Annotated[
    Optional[int],  # noqa: UP045
    typer.Option("--forks", "-f", min=1, max=500,
                 help="Robots worked on at once (default: the inventory's settings.forks, else 32)."),
]
Canary = Annotated[
    int, typer.Option("--canary", min=0, help="Run N robots first; stop if one of them fails.")
]
MaxFail = Annotated[
    Optional[float],  # noqa: UP045
    typer.Option("--max-fail", min=0, max=100, callback=finite,
                 help="Stop starting robots once more than PCT % failed."),
]

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
