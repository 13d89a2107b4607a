"""Why an SSH connection to a robot failed, in words, with the next command filled in.

Each failure of connecting (nothing listens, the host never answers, a key the robot refuses,
no key at all, a key file that is missing or needs a passphrase, a host key unknown or
changed) becomes an :class:`~panther_ops.errors.UnreachableError` whose hint is the command
to run next with the robot's own values: its name, user, address, port and key file.
"""

from __future__ import annotations

import errno
import os
import shlex
import socket
from typing import TYPE_CHECKING, Any

from panther_ops.errors import HostKeyError, UnreachableError

if TYPE_CHECKING:
    from panther_ops.transport.ssh_config import Hop

DEFAULT_KEYS = ("id_rsa", "id_ecdsa", "id_ed25519", "id_dsa")
"""The key files an SSH client tries in ~/.ssh when none is configured (paramiko as OpenSSH)."""
NEW_KEY = "~/.ssh/id_ed25519"


class UnknownHostKey(Exception):
    """Raised by the missing-host-key policy: the host offered a key known_hosts does not hold."""

    def __init__(self, key_type: str, offered: str) -> None:
        super().__init__(f"host key {key_type} {offered} is not in known_hosts: refused")
        self.key_type = key_type
        self.offered = offered


def address(hop: Hop) -> str:
    return f"{hop.hostname}:{hop.port}"


def login(hop: Hop) -> str:
    """``-p PORT user@host`` as ssh and ssh-copy-id take them."""
    return f"-p {hop.port} {shlex.quote(f'{hop.user}@{hop.hostname}')}"


def path_arg(path: str) -> str:
    """``path`` as a shell word (a leading ``~/`` left for the shell to expand)."""
    return "~/" + shlex.quote(path[2:]) if path.startswith("~/") else shlex.quote(path)


def copy_id(key: str, hop: Hop) -> str:
    """The command that installs ``key`` (a private key's path) on the robot."""
    return f"ssh-copy-id -i {path_arg(key + '.pub')} {login(hop)}"


def _trust_command(hop: Hop) -> str:
    """``panther-ops trust NAME`` for a hop that is a robot of the inventory; for a jump host
    that is not one (ProxyJump, or ``jump: user@host``), how to record its key by hand."""
    if " (jump " in hop.label:
        kh = hop.known_hosts[0] if hop.known_hosts else "~/.ssh/known_hosts"
        return f"ssh-keyscan -p {hop.port} {shlex.quote(hop.hostname)} >> {shlex.quote(kh)}"
    return f"panther-ops trust {shlex.quote(hop.label)}"


def unknown_host_key(robot: str, hop: Hop, exc: UnknownHostKey) -> HostKeyError:
    return HostKeyError(
        robot, f"{address(hop)} offers host key {exc.key_type} {exc.offered}, which is not in known_hosts "
        f"({', '.join(hop.known_hosts)}): refused", offered=exc.offered,
        hint="compare it with the robot's own (on the robot: ssh-keygen -lf /etc/ssh/ssh_host_ed25519_key.pub), "
        f"then: {_trust_command(hop)}")


def changed_host_key(robot: str, hop: Hop, got: str, want: str) -> HostKeyError:
    from panther_ops.transport.hostkeys import known_hosts_name

    fix = (f"{_trust_command(hop)} --replace" if " (jump " not in hop.label else
           f"ssh-keygen -R {shlex.quote(known_hosts_name(hop.hostname, hop.port))}, then {_trust_command(hop)}")
    return HostKeyError(
        robot, f"HOST KEY CHANGED for {known_hosts_name(hop.hostname, hop.port)}: offered {got}, "
        f"known_hosts has {want}. Refused: this may be a reinstalled robot or an attack.",
        offered=got, expected=want,
        hint=f"if the robot was reinstalled, check the new key on it (ssh-keygen -lf "
        f"/etc/ssh/ssh_host_ed25519_key.pub), then: {fix}")


def _default_keys() -> list[str]:
    ssh_dir = os.path.expanduser("~/.ssh")
    return [os.path.join(ssh_dir, k) for k in DEFAULT_KEYS if os.path.isfile(os.path.join(ssh_dir, k))]


AUTH_TIMEOUT = "Authentication timeout."
"""paramiko's AuthenticationException when its auth_timeout ran out (paramiko/auth_handler.py)."""


def auth_failed(robot: str, hop: Hop, exc: Exception) -> UnreachableError:
    """The robot answered but did not let us in (paramiko's AuthenticationException), or there
    was no key to offer (paramiko: "No authentication methods available")."""
    import paramiko

    who = f"{hop.user}@{hop.hostname}"
    if str(exc) == AUTH_TIMEOUT:  # no answer yet, not a refusal: a robot or a machine too busy
        return UnreachableError(
            robot, f"{who} did not finish logging in within {hop.connect_timeout:g} s (the key was not refused)",
            hint="the robot or this machine is too busy to log in in time (many logins at once?): run again "
            "with fewer robots at once (--forks), or allow more time (connect_timeout: in the inventory, "
            "ConnectTimeout in ssh_config)")
    if isinstance(exc, paramiko.BadAuthenticationType) and "publickey" not in exc.allowed_types:
        return UnreachableError(
            robot, f"{who} does not take keys (the robot's sshd allows: {', '.join(exc.allowed_types) or 'nothing'})",
            hint="on the robot: PubkeyAuthentication yes in /etc/ssh/sshd_config, then sudo systemctl restart ssh")
    if isinstance(exc, paramiko.PasswordRequiredException):
        key = hop.key_files[0] if hop.key_files else NEW_KEY
        return UnreachableError(robot, f"the key {key} is protected by a passphrase (panther-ops asks none)",
                                hint=f"load it into ssh-agent, then run again: ssh-add {path_arg(key)}")
    agent = bool(os.environ.get("SSH_AUTH_SOCK"))
    if hop.key_files:
        keys = ", ".join(hop.key_files)
        return UnreachableError(
            robot, f"{who} refused the key {keys}{' and the ssh-agent keys' if agent else ''}",
            hint=f"install the key on the robot (asks its password once): {copy_id(hop.key_files[0], hop)} "
            f"(if {hop.user} is not the robot's user, set user: in the inventory)")
    found = _default_keys()
    if not found and not agent:
        return UnreachableError(
            robot, f"no key to log in as {who} with: no identity_file (inventory or ssh_config), no key in "
            "~/.ssh and no ssh-agent",
            hint=f"make a key and install it on the robot: ssh-keygen -t ed25519 -f {NEW_KEY} && "
            f"{copy_id(NEW_KEY, hop)}; then set identity_file: {NEW_KEY} in the inventory")
    offered = ", ".join([*found, *(["the ssh-agent keys"] if agent else [])])
    first = found[0] if found else NEW_KEY
    return UnreachableError(
        robot, f"{who} refused every key offered ({offered}); no identity_file is set",
        hint=f"install your key on the robot (asks its password once): {copy_id(first, hop)}; "
        "or set identity_file: in the inventory to the key the robot has")


def missing_key(robot: str, hop: Hop, path: str) -> UnreachableError:
    return UnreachableError(
        robot, f"identity file {path} does not exist (from ssh_config or the inventory)",
        hint=f"give the path of your private key, or make one and install it: ssh-keygen -t ed25519 -f "
        f"{path_arg(path)} && {copy_id(path, hop)}")


def no_answer(robot: str, hop: Hop, *, accepted: bool) -> UnreachableError:
    """The host did not answer within the connect timeout: before TCP was up, or after (a port
    that accepts and never says a word of SSH)."""
    seconds = f"{hop.connect_timeout:g} s"
    if accepted:
        return UnreachableError(
            robot, f"{address(hop)} accepted the connection but did not answer in {seconds} (no SSH greeting)",
            hint=f"is port {hop.port} the robot's sshd (port: in the inventory), and is sshd up? "
            f"try: ssh {login(hop)}")
    return UnreachableError(
        robot, f"{address(hop)} did not answer in {seconds}",
        hint=f"is the robot on and on this network (host: in the inventory)? try: {_ping(hop)}")


def cannot_connect(robot: str, hop: Hop, exc: BaseException, transport: Any) -> UnreachableError:
    """Any other failure while connecting; ``transport``: paramiko's Transport when the TCP
    connection was up (None: it never was), to ask whether the SSH session had begun."""
    greeted = transport is not None and getattr(transport, "initial_kex_done", False)
    if isinstance(exc, (socket.timeout, TimeoutError)) or (not greeted and _silence(exc)):
        timed_out = isinstance(exc, (socket.timeout, TimeoutError))
        return no_answer(robot, hop, accepted=transport is not None or not timed_out)
    if isinstance(exc, FileNotFoundError) and exc.filename in hop.key_files:
        return missing_key(robot, hop, str(exc.filename))
    if isinstance(exc, socket.gaierror):
        return UnreachableError(robot, f"cannot resolve {hop.hostname}: {exc.strerror or exc}",
                                hint="check host: in the inventory (an address, or a name this machine resolves)")
    if isinstance(exc, ConnectionRefusedError):
        return UnreachableError(robot, f"{address(hop)} refused the connection (no sshd listens on port {hop.port})",
                                hint=f"check port: in the inventory and that sshd runs on the robot; "
                                f"try: ssh {login(hop)}")
    if isinstance(exc, OSError) and exc.errno in (errno.EHOSTUNREACH, errno.ENETUNREACH):
        return UnreachableError(robot, f"cannot reach {address(hop)}: {exc.strerror}",
                                hint=f"is this machine on the robot's network? try: {_ping(hop)}")
    text = str(exc) or type(exc).__name__
    return UnreachableError(robot, f"cannot connect to {address(hop)}: {text}",
                            hint=f"try the connection by hand: ssh -v {login(hop)}")


def _ping(hop: Hop) -> str:
    return f"ping -c 3 {shlex.quote(hop.hostname)}"


def _silence(exc: BaseException) -> bool:
    """paramiko's words for a peer that never spoke SSH: it gave up waiting for the greeting or
    the key exchange ("No existing session" is what authenticating says after that); a peer
    that closed at once is not silence."""
    text = str(exc)
    waited = isinstance(exc.__context__, (socket.timeout, TimeoutError)) or text.endswith(("banner", "timed out"))
    return "No existing session" in text or ("protocol banner" in text and waited)
