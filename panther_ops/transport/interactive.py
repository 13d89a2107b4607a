"""An interactive command on a robot: a pseudo-terminal over the robot's SSH connection,
wired to this terminal (raw mode while it runs) until the command ends."""

from __future__ import annotations

import os
import select
import sys
from typing import TYPE_CHECKING, Any

from panther_ops.errors import TransportError
from panther_ops.transport.base import Command

if TYPE_CHECKING:
    import paramiko


def run_interactive(client: paramiko.SSHClient, robot: str, command: Command,
                    stdin_fd: int | None = None, stdout_fd: int | None = None) -> int:
    """Run ``command`` with a pty on the robot; this terminal's keys go to it, its output
    comes here. Returns its exit status."""
    import termios
    import tty

    fd_in = sys.stdin.fileno() if stdin_fd is None else stdin_fd
    fd_out = sys.stdout.fileno() if stdout_fd is None else stdout_fd
    transport = client.get_transport()
    if transport is None or not transport.is_active():
        raise TransportError(robot, "the connection to the robot was lost")
    try:
        cols, rows = os.get_terminal_size(fd_out)
    except OSError:
        cols, rows = 80, 24
    chan = transport.open_session()
    chan.get_pty(term=os.environ.get("TERM", "xterm"), width=cols, height=rows)
    chan.exec_command(command.render(reveal=True))
    saved = termios.tcgetattr(fd_in) if os.isatty(fd_in) else None
    try:
        if saved is not None:
            tty.setraw(fd_in)
        stdin_open = True
        while True:
            watch: list[Any] = [chan, fd_in] if stdin_open else [chan]
            ready, _, _ = select.select(watch, [], [], 0.5)
            if chan in ready:
                data = chan.recv(4096)
                if not data:
                    break
                os.write(fd_out, data)
            if fd_in in ready:
                data = os.read(fd_in, 1024)
                if data:
                    chan.sendall(data)
                else:
                    stdin_open = False
                    chan.shutdown_write()
            if chan.exit_status_ready() and not chan.recv_ready():
                break
        return chan.recv_exit_status()
    finally:
        if saved is not None:
            termios.tcsetattr(fd_in, termios.TCSADRAIN, saved)
        chan.close()
