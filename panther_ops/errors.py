"""One error hierarchy for panther-ops, and the documented exit codes.

Every error carries what an operator needs: which robot, which file, line and key,
what is allowed and what to do next. The CLI funnel renders them; nothing else exits.
"""

from __future__ import annotations

from enum import IntEnum


class ExitCode(IntEnum):
    """Exit codes of every panther-ops command (docs/results.md)."""

    OK = 0
    """Every targeted robot ended ok, changed or skipped."""
    ERROR = 1
    """An unexpected error (a bug): the traceback is in the debug log."""
    USAGE = 2
    """Bad input or usage; nothing was done anywhere."""
    PARTIAL = 3
    """At least one robot failed, was rolled back or was unreachable while others were reached."""
    UNREACHABLE = 4
    """Every targeted robot was unreachable."""
    DECLINED = 5
    """The operator answered no to the confirmation: nothing was done."""
    DRIFT = 6
    """``config diff --exit-code``: every robot was read and at least one differs."""
    INTERRUPTED = 130
    """Interrupted by the operator (Ctrl-C)."""
    CLOSED_PIPE = 141
    """The reader of stdout went away (``... | head``): the rest of the output is dropped
    without a message, as a tool killed by SIGPIPE (128 + 13) exits in a shell."""


class OpsError(Exception):
    """Root of every error panther-ops raises on purpose."""

    exit_code: ExitCode = ExitCode.ERROR

    def __init__(self, message: str, *, hint: str | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.hint = hint

    def __str__(self) -> str:
        return self.message if not self.hint else f"{self.message}\n  hint: {self.hint}"


class UsageError(OpsError):
    """Bad input: a value, file, key or option that is not allowed. Exit code 2."""

    exit_code = ExitCode.USAGE


class InputError(UsageError):
    """Bad content in a file: names the file, line and key, and what is allowed."""

    def __init__(
        self,
        message: str,
        *,
        path: str | None = None,
        line: int | None = None,
        key: str | None = None,
        hint: str | None = None,
    ) -> None:
        where = ""
        if path:
            where = path + (f":{line}" if line else "")
        if key:
            where = f"{where} [{key}]" if where else f"[{key}]"
        super().__init__(f"{where}: {message}" if where else message, hint=hint)
        self.path = path
        self.line = line
        self.key = key


class InventoryError(InputError):
    """The inventory is missing, malformed or names something that does not exist."""


class Declined(OpsError):
    """The operator answered no to the confirmation question: nothing was done. Exit code 5
    (not bad input: a decision; docs/results.md)."""

    exit_code = ExitCode.DECLINED


class Interrupted(OpsError):
    """The operator pressed Ctrl-C where nothing had been started (the confirmation question):
    nothing was done. Exit code 130."""

    exit_code = ExitCode.INTERRUPTED


class TransportError(OpsError):
    """A robot could not be reached or a transport step failed."""

    def __init__(self, robot: str, message: str, *, hint: str | None = None) -> None:
        super().__init__(f"{robot}: {message}", hint=hint)
        self.robot = robot


class UnreachableError(TransportError):
    """The robot did not answer (network, DNS, refused, timeout, authentication). Exit code 4
    when it ends a one-robot command (``trust``, ``teleop``): the robot was not reached."""

    exit_code = ExitCode.UNREACHABLE


class HostKeyError(UnreachableError):
    """The robot's host key is unknown or changed: it is refused, never added silently."""

    def __init__(
        self,
        robot: str,
        message: str,
        *,
        offered: str | None = None,
        expected: str | None = None,
        hint: str | None = None,
    ) -> None:
        super().__init__(robot, message, hint=hint)
        self.offered = offered
        self.expected = expected


class CommandFailed(TransportError):
    """A remote command exited with a non-zero status."""

    def __init__(self, robot: str, command: str, exit_status: int, stderr: str) -> None:
        tail = "\n".join(stderr.strip().splitlines()[-5:])
        super().__init__(robot, f"`{command}` exited {exit_status}" + (f": {tail}" if tail else ""))
        self.command = command
        self.exit_status = exit_status
        self.stderr = stderr


class RemoteStateError(OpsError):
    """The robot is in a state the command cannot work with (e.g. no compose.yaml)."""
