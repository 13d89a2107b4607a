"""Resolve how to reach a robot from the inventory and ``~/.ssh/config``.

Inventory values win over ssh_config (as command-line options win in OpenSSH); ssh_config
gives HostName, User, Port, IdentityFile, ProxyJump, UserKnownHostsFile and ConnectTimeout.
"""

from __future__ import annotations

import functools
import os
from dataclasses import dataclass, replace
from typing import Any

from panther_ops.transport.base import Endpoint
from panther_ops.transport.filecache import parsed
from panther_ops.transport.ssh_config_read import QuickConfig, read_file

DEFAULT_KNOWN_HOSTS = "~/.ssh/known_hosts"


@dataclass(frozen=True)
class Hop:
    """One resolved SSH hop: where to connect and how to authenticate."""

    label: str
    hostname: str
    port: int
    user: str
    key_files: tuple[str, ...]
    known_hosts: tuple[str, ...]
    connect_timeout: float
    jump: Hop | None = None


_lookups: dict[tuple[int, str], dict[str, object]] = {}


@functools.cache
def _config_type() -> Any:
    """paramiko's SSHConfig, minus a cost that grows with the square of the fleet.

    A lookup visits every block of the file twice and, for each block whose ``Host`` does
    not match, asks the ``Match`` conditions, which begins with ``getpass.getuser()`` (a
    user-database lookup) even when the block has none. An inventory's ssh_config with a
    block per robot made that 60 lookups per robot on 30 robots. A block without ``Match``
    conditions matches nothing by them: answered here without asking.
    """
    import paramiko

    class Config(paramiko.SSHConfig):
        def _does_match(self, match_list: list[Any], *args: Any) -> Any:
            if not match_list:
                return []  # what paramiko returns for no conditions: nothing matched
            return super()._does_match(match_list, *args)  # type: ignore[misc]  # private, not in the stubs

    return Config


@dataclass(frozen=True)
class _Read:
    config: QuickConfig | None
    """None: the quick reader gave up on this file (paramiko reads it)."""


def _read(path: str) -> _Read:
    return _Read(read_file(path))


class _NeedsParamiko(Exception):
    """A quick-only lookup met an ssh_config only paramiko reads."""


def _lookup(config_path: str | None, alias: str, quick_only: bool = False) -> dict[str, object]:
    """ssh_config's answer for ``alias`` (the file parsed once per command, each alias looked up once).

    The quick reader (``ssh_config_read``) answers where it can, else paramiko's SSHConfig;
    ``quick_only`` raises :class:`_NeedsParamiko` instead of loading paramiko.
    """
    path = os.path.expanduser(config_path or "~/.ssh/config")
    read = parsed("ssh_config quick", path, _read)
    if read is None:
        return {}
    conf: Any = read.config
    if conf is None:
        if quick_only:
            raise _NeedsParamiko(path)
        conf = parsed("ssh_config", path, _config_type().from_path)
        if conf is None:
            return {}
    key = (id(conf), alias)
    if key not in _lookups:
        _lookups[key] = dict(conf.lookup(alias))
    return dict(_lookups[key])


def _parse_jump_spec(spec: str) -> tuple[str | None, str, int | None]:
    user: str | None = None
    hostport = spec
    if "@" in spec:
        user, hostport = spec.rsplit("@", 1)
    port: int | None = None
    if hostport.startswith("["):
        host, _, rest = hostport[1:].partition("]")
        if rest.startswith(":"):
            port = int(rest[1:])
    elif hostport.count(":") == 1:
        host, p = hostport.split(":")
        port = int(p)
    else:
        host = hostport
    return user, host, port


def resolve(endpoint: Endpoint) -> Hop:
    """Turn an inventory endpoint into a chain of hops, consulting ssh_config."""
    return _resolve(endpoint, quick_only=False)


def resolve_quick(endpoint: Endpoint) -> Hop | None:
    """:func:`resolve` where the quick reader knows every ssh_config involved, else None
    (it never loads paramiko)."""
    try:
        return _resolve(endpoint, quick_only=True)
    except _NeedsParamiko:
        return None


def _resolve(endpoint: Endpoint, quick_only: bool) -> Hop:
    cfg = _lookup(endpoint.ssh_config, endpoint.host, quick_only)
    hostname = str(cfg.get("hostname", endpoint.host))
    port = endpoint.port or int(str(cfg.get("port", 22)))
    user = endpoint.user or str(cfg.get("user", os.environ.get("USER", "husarion")))
    cfg_keys = cfg.get("identityfile", [])
    keys = endpoint.identity_files or tuple(
        os.path.expanduser(str(k)) for k in (cfg_keys if isinstance(cfg_keys, list) else [cfg_keys])
    )
    cfg_known = cfg.get("userknownhostsfile")
    known = list(endpoint.known_hosts)
    if isinstance(cfg_known, str):
        known.extend(os.path.expanduser(k) for k in cfg_known.split())
    if not known:
        known.append(os.path.expanduser(DEFAULT_KNOWN_HOSTS))
    timeout = endpoint.connect_timeout
    if "connecttimeout" in cfg and endpoint.connect_timeout == Endpoint.connect_timeout:
        timeout = float(str(cfg["connecttimeout"]))

    jump: Hop | None = None
    if endpoint.jump is not None:
        jump = _resolve(endpoint.jump, quick_only)
    elif "proxyjump" in cfg and str(cfg["proxyjump"]).lower() != "none":
        # A chain "a,b": connect to a, then through it to b, then to the target.
        for spec in str(cfg["proxyjump"]).split(","):
            juser, jhost, jport = _parse_jump_spec(spec.strip())
            hop_ep = Endpoint(
                name=f"{endpoint.name} (jump {jhost})",
                host=jhost,
                port=jport,
                user=juser,
                ssh_config=endpoint.ssh_config,
                known_hosts=endpoint.known_hosts,
                connect_timeout=endpoint.connect_timeout,
            )
            hop = _resolve(hop_ep, quick_only)
            jump = hop if jump is None else replace(hop, jump=jump)
    return Hop(
        label=endpoint.name,
        hostname=hostname,
        port=port,
        user=user,
        key_files=tuple(keys),
        known_hosts=tuple(dict.fromkeys(known)),
        connect_timeout=timeout,
        jump=jump,
    )

