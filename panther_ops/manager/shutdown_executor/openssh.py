"""SSH shutdowns through the OpenSSH client (``ssh``) when paramiko is not importable.

The robots' driver images (panther_ros 2.0 - husarion_ugv 2.2.0) have no paramiko: the stock
C++ manager links libssh. A deployed manager that needed paramiko would silently stop shutting
the User Computers down with the robot. This backend does what the stock node does with the
image's own ``ssh`` client:

* public-key authentication only, in batch mode (never a prompt): ``-o BatchMode=yes``,
  password and keyboard-interactive authentication off;
* strict host keys from ONE known_hosts file (``-o StrictHostKeyChecking=yes``,
  ``UserKnownHostsFile``; the global file is not read): an unknown or changed host key fails,
  nothing is ever added (the same rule as `ParamikoShutdown` with ``RejectPolicy``);
* the robot's key (``-i``, ``IdentitiesOnly``) when one is given, else ssh's defaults
  (``~/.ssh/id_rsa`` ...); no ssh_config files (``-F /dev/null``): nothing outside this call
  changes what it does;
* the command of the hosts file as ONE argument after ``--`` and the destination (no local
  shell is involved: an argv list); like libssh's and paramiko's ``exec`` request, the remote
  login shell runs it, so ``sudo shutdown now`` means what it means in the stock manager;
* bounded by the host's ``timeout`` (connect timeout and a hard limit on the process).

The host name, user and port come from a parsed `ShutdownHost`; values that ssh would read as
an option (leading ``-``) or that hold whitespace or control characters are refused here as
well, whatever validated the file before.
"""

from __future__ import annotations

import math
import re
import shutil
import subprocess
from pathlib import Path

from panther_ops.manager.shutdown_executor.backends import CommandOutcome
from panther_ops.manager.shutdown_executor.hosts import ShutdownHost

#: ssh's own error exit status (connection, authentication, host key); anything else is the command's
SSH_ERROR = 255
_SAFE = re.compile(r"^[A-Za-z0-9_.:%\[\]-]+$")


def ssh_client() -> str | None:
    """The ``ssh`` client on PATH, or None."""
    return shutil.which("ssh")


def _checked(value: str, what: str) -> str:
    if not value or value.startswith("-") or not _SAFE.match(value):
        raise ValueError(f"{what} {value!r} is not a plain host or user name")
    return value


class OpenSshShutdown:
    """Run the host's command with the OpenSSH client; host keys must already be in `known_hosts`."""

    def __init__(self, known_hosts: str | Path | None = None, key_filename: str | Path | None = None,
                 ssh: str | None = None) -> None:
        self.known_hosts = Path(known_hosts) if known_hosts else Path.home() / ".ssh" / "known_hosts"
        self.key_filename = str(key_filename) if key_filename else None
        self.ssh = ssh or ssh_client() or "ssh"

    def argv(self, host: ShutdownHost) -> list[str]:
        """The exact ssh command line for `host` (no shell)."""
        user = _checked(host.username or "", "user")
        ip = _checked(host.ip, "host")
        connect = max(1, math.ceil(host.timeout))
        argv = [self.ssh, "-F", "/dev/null", "-T", "-n",
                "-o", "BatchMode=yes",
                "-o", "StrictHostKeyChecking=yes",
                "-o", f"UserKnownHostsFile={self.known_hosts}",
                "-o", "GlobalKnownHostsFile=/dev/null",
                "-o", "PasswordAuthentication=no",
                "-o", "KbdInteractiveAuthentication=no",
                "-o", "PreferredAuthentications=publickey",
                "-o", f"ConnectTimeout={connect}",
                "-o", "LogLevel=ERROR",
                "-p", str(int(host.port)), "-l", user]
        if self.key_filename:
            argv += ["-o", "IdentitiesOnly=yes", "-i", self.key_filename]
        return [*argv, "--", ip, host.command]

    def request(self, host: ShutdownHost) -> CommandOutcome:
        if not self.known_hosts.is_file():
            return CommandOutcome(False, error=f"no known_hosts file at {self.known_hosts}: "
                                  f"add the host key of {host.ip} first (ssh-copy-id)")
        try:
            argv = self.argv(host)
        except ValueError as exc:
            return CommandOutcome(False, error=str(exc))
        try:
            done = subprocess.run(argv, stdin=subprocess.DEVNULL, capture_output=True, timeout=host.timeout,
                                  check=False)
        except subprocess.TimeoutExpired:
            return CommandOutcome(False, error=f"Timeout exceeded: no answer from {host.describe()} "
                                  f"in {host.timeout} s")
        except OSError as exc:
            return CommandOutcome(False, error=f"cannot run {self.ssh}: {exc.strerror or exc}")
        output = done.stdout.decode(errors="replace")
        error = done.stderr.decode(errors="replace").strip()
        if done.returncode == SSH_ERROR:
            return CommandOutcome(False, output, f"SSH error: {error or 'ssh exited with 255'}")
        if done.returncode != 0:
            return CommandOutcome(False, output, f"command exited with {done.returncode}: {error}")
        return CommandOutcome(True, output)
