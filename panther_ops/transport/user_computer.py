"""A robot's User Computer, reached with fabric through the robot's open SSH connection.

The User Computer (a NUC at 10.15.20.3 on a real Panther) sits on the robot's LAN, which
the operator usually cannot reach. Its fabric ``Connection`` takes the robot as its
``gateway``: a fabric ``Connection`` bound to the robot's already open paramiko client, so
fabric sees it connected and opens the ``direct-tcpip`` channel on it (no second connection
to the robot). Host keys are strict: ``paramiko.RejectPolicy`` (fabric's default would add
an unknown key) against the known_hosts files given. ``sudo`` answers the sudo prompt with
fabric's password watcher; the password is a :class:`Secret` kept in memory only, never
echoed (fabric hides the watcher's answer) and never part of a command line.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from panther_ops.errors import TransportError, UnreachableError
from panther_ops.secret import Secret
from panther_ops.transport.base import Command, CommandResult

if TYPE_CHECKING:
    import paramiko


@dataclass(frozen=True)
class ComputerAddress:
    """Where the User Computer is and how to log in (behind robot ``robot``)."""

    robot: str
    host: str
    port: int = 22
    user: str = "husarion"
    key_file: str | None = None
    connect_timeout: float = 10.0
    known_hosts: tuple[str, ...] = ()

    @property
    def name(self) -> str:
        return f"{self.robot}'s User Computer {self.user}@{self.host}"


class UserComputerSession:
    """One fabric connection to the User Computer, through the robot's connection."""

    def __init__(self, robot_client: paramiko.SSHClient, address: ComputerAddress,
                 sudo_password: Secret | None = None) -> None:
        self.address = address
        self._robot_client = robot_client
        self._password = sudo_password
        self._conn: Any = None

    def connect(self) -> None:
        import paramiko

        fabric = _fabric()  # after paramiko: fabric imports it too

        robot_transport = self._robot_client.get_transport()
        if robot_transport is None or not robot_transport.is_active():
            raise UnreachableError(self.address.robot, "the connection to the robot was lost")
        config = fabric.Config(lazy=True)  # no ssh_config of this machine for a host on the robot's LAN
        gateway = fabric.Connection(self.address.robot, config=config)
        gateway.client = self._robot_client  # the robot's open connection: fabric's open() leaves it be
        gateway.transport = robot_transport
        kwargs: dict[str, Any] = {"look_for_keys": False, "allow_agent": False}
        if self.address.key_file:
            kwargs["key_filename"] = [self.address.key_file]
        conn = fabric.Connection(self.address.host, user=self.address.user, port=self.address.port,
                                 gateway=gateway, config=fabric.Config(lazy=True),
                                 connect_timeout=int(self.address.connect_timeout), connect_kwargs=kwargs)
        conn.client.set_missing_host_key_policy(paramiko.RejectPolicy())
        for path in self.address.known_hosts:
            try:
                conn.client.load_host_keys(path)
            except FileNotFoundError:
                continue
        try:
            conn.open()
        except paramiko.SSHException as exc:
            conn.close()
            text = str(exc)
            if "not found in known_hosts" in text:
                raise UnreachableError(self.address.name, f"host key not known ({text})",
                                       hint="add its key to the inventory's known_hosts "
                                       "(ssh-keyscan through the robot, then check the fingerprint)") from None
            raise UnreachableError(self.address.name, f"SSH failed: {text}") from None
        except (OSError, EOFError) as exc:
            conn.close()
            raise UnreachableError(self.address.name, f"not reachable through {self.address.robot}: "
                                   f"{exc or type(exc).__name__}") from None
        self._conn = conn

    def run(self, command: Command, *, timeout: float = 60.0) -> CommandResult:
        return self._do(command, timeout, sudo=False)

    def sudo(self, command: Command, *, timeout: float = 60.0) -> CommandResult:
        """The command as root: ``sudo`` on the User Computer, its password prompt answered
        by fabric's watcher when a password was given (else it must not ask)."""
        return self._do(command, timeout, sudo=True)

    def _do(self, command: Command, timeout: float, *, sudo: bool) -> CommandResult:
        if self._conn is None:
            self.connect()
        import invoke

        text = command.render(reveal=True)
        start = time.monotonic()
        kwargs: dict[str, Any] = {"hide": True, "warn": True, "in_stream": False, "timeout": timeout}
        try:
            if sudo:
                if self._password is not None:
                    kwargs["password"] = self._password.reveal()
                else:
                    text = f"sudo -n -- sh -c {_quote(text)}"
                res = self._conn.sudo(text, **kwargs) if self._password is not None else \
                    self._conn.run(text, **kwargs)
            else:
                res = self._conn.run(text, **kwargs)
        except invoke.exceptions.AuthFailure:
            raise TransportError(self.address.name, "sudo refused the password") from None
        except invoke.exceptions.CommandTimedOut:
            raise TransportError(self.address.name, f"`{command}` timed out after {timeout:.0f} s") from None
        out = str(res.stdout)
        return CommandResult(str(command), int(res.exited), out, str(res.stderr), time.monotonic() - start,
                             out.encode())

    def close(self) -> None:
        if self._conn is not None:
            self._conn.close()  # its own client only: the robot's connection stays open
            self._conn = None


def _quote(text: str) -> str:
    import shlex

    return shlex.quote(text)


def _fabric() -> Any:
    import fabric

    return fabric
