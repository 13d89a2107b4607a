"""Shutdown hosts: the plain description of a computer to power off, and the hosts file.

File format (``hosts:`` list), as shipped by the Panther stack (panther-stack.md §1.8):

* SSH (2.0.0 – 2.2.0): ``ip`` and ``username`` required; ``port`` 22, ``command``
  "sudo shutdown now", ``timeout`` 5.0, ``ping_for_success`` true.
* HTTP (2.2.1+, husarion-shutdown): ``ip`` required; ``port`` 3003, ``secret`` "husarion",
  ``timeout`` 5.0. An entry without ``username`` is taken as HTTP; ``method: ssh|http``
  may say it explicitly.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path
from typing import Any

from panther_ops.manager.errors import ShutdownHostsError
from panther_ops.manager.yaml_io import read_yaml

DEFAULT_COMMAND = "sudo shutdown now"
DEFAULT_TIMEOUT = 5.0
DEFAULT_SSH_PORT = 22
DEFAULT_HTTP_PORT = 3003
DEFAULT_SECRET = "husarion"


class Method(str, Enum):
    """How a host is asked to shut down."""

    SSH = "ssh"
    HTTP = "http"


@dataclass(frozen=True)
class ShutdownHost:
    """One computer to shut down. SSH unless a `secret` is given (then HTTP).

    Attributes:
        ip: address or host name.
        username: SSH user (required for SSH).
        port: SSH port (22) or husarion-shutdown HTTP port (3003).
        command: command run over SSH.
        timeout: seconds to wait for the response and for the host to disappear.
        ping_for_success: ping until the host no longer answers (else success on response).
        secret: shared HMAC secret of the HTTP shutdown service.
    """

    ip: str
    username: str | None = None
    port: int = DEFAULT_SSH_PORT
    command: str = DEFAULT_COMMAND
    timeout: float = DEFAULT_TIMEOUT
    ping_for_success: bool = True
    secret: str | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        if not self.ip:
            raise ValueError("a shutdown host needs an ip")
        if self.secret is None and not self.username:
            raise ValueError(f"{self.ip}: an SSH shutdown host needs a username")
        if not 0 < self.port < 65536:
            raise ValueError(f"{self.ip}: port {self.port} is not a TCP port")
        if self.timeout <= 0:
            raise ValueError(f"{self.ip}: timeout must be positive, got {self.timeout}")

    @property
    def method(self) -> Method:
        """SSH or HTTP."""
        return Method.HTTP if self.secret is not None else Method.SSH

    @property
    def key(self) -> tuple[str, str, int]:
        """Identity used to drop duplicates (ip, user, port), as the C++ node hashes them."""
        return (self.ip, self.username or "", self.port)

    def describe(self) -> str:
        """``user@ip:port`` for SSH, ``http://ip:port`` for HTTP."""
        if self.method is Method.HTTP:
            return f"http://{self.ip}:{self.port}"
        return f"{self.username}@{self.ip}:{self.port}"


@dataclass(frozen=True)
class ShutdownHostsFile:
    """A parsed hosts file: usable hosts, and entries that were skipped with the reason."""

    source: str
    hosts: tuple[ShutdownHost, ...]
    problems: tuple[str, ...] = ()


def _as_bool(value: Any) -> bool:
    if isinstance(value, bool):
        return value
    if isinstance(value, str) and value.lower() in {"true", "false"}:
        return value.lower() == "true"
    raise ValueError(f"expected true or false, got {value!r}")


def host_from_entry(entry: Mapping[str, Any]) -> ShutdownHost:
    """Build a host from one ``hosts:`` entry; raise ValueError naming the bad key."""
    unknown = set(entry) - {"ip", "username", "port", "command", "timeout", "ping_for_success",
                            "secret", "method"}
    if unknown:
        raise ValueError(f"unknown keys: {', '.join(sorted(unknown))}")
    if "ip" not in entry or not entry["ip"]:
        raise ValueError("no ip")
    method = str(entry.get("method") or ("ssh" if entry.get("username") else "http")).lower()
    if method not in {"ssh", "http"}:
        raise ValueError(f"method must be ssh or http, got {method!r}")
    http = method == "http"
    try:
        port = int(entry.get("port", DEFAULT_HTTP_PORT if http else DEFAULT_SSH_PORT))
        timeout = float(entry.get("timeout", DEFAULT_TIMEOUT))
    except (TypeError, ValueError):
        raise ValueError("port and timeout must be numbers") from None
    return ShutdownHost(
        ip=str(entry["ip"]),
        username=str(entry["username"]) if entry.get("username") else None,
        port=port,
        command=str(entry.get("command", DEFAULT_COMMAND)),
        timeout=timeout,
        ping_for_success=_as_bool(entry.get("ping_for_success", True)),
        secret=str(entry.get("secret", DEFAULT_SECRET)) if http else None,
    )


def parse_shutdown_hosts(document: Any, source: str = "<hosts>") -> ShutdownHostsFile:
    """Parse a loaded hosts document. Bad entries are skipped and reported, like the C++ node.

    Raises:
        ShutdownHostsError: the document is not a mapping with a ``hosts`` list.
    """
    if document is None:
        document = {}
    if not isinstance(document, Mapping):
        raise ShutdownHostsError(f"{source}: expected a mapping with a 'hosts' list")
    entries = document.get("hosts") or []
    if not isinstance(entries, list):
        raise ShutdownHostsError(f"{source}: 'hosts' must be a list")
    hosts: list[ShutdownHost] = []
    problems: list[str] = []
    seen: set[tuple[str, str, int]] = set()
    for index, entry in enumerate(entries):
        where = f"{source}: hosts[{index}]"
        if not isinstance(entry, Mapping):
            problems.append(f"{where}: not a mapping, skipped")
            continue
        try:
            host = host_from_entry(entry)
        except ValueError as exc:
            problems.append(f"{where}: {exc}, skipped")
            continue
        if host.key in seen:
            problems.append(f"{where}: duplicate of {host.describe()}, skipped")
            continue
        seen.add(host.key)
        hosts.append(host)
    return ShutdownHostsFile(source, tuple(hosts), tuple(problems))


def load_shutdown_hosts(path: str | Path) -> ShutdownHostsFile:
    """Read a shutdown hosts YAML file (see the module docstring for its format)."""
    return parse_shutdown_hosts(read_yaml(path, ShutdownHostsError), str(path))
