"""docker SDK clients: over a robot's existing SSH connection, or a local socket; the SDK's errors
as panther-ops' own.

The SSH variant opens a channel of the connection the transport already holds and runs
``docker system dial-stdio`` on it (what docker's own ssh helper runs), so docker traffic
goes through jump hosts and opens no second SSH connection.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING, Any

from panther_ops.errors import OpsError

if TYPE_CHECKING:
    import paramiko
    from docker import DockerClient


class EngineError(OpsError):
    """A docker engine request failed (the SDK's ``DockerException``)."""


class EngineRefused(EngineError):
    """The engine answered with an HTTP error (the SDK's ``APIError``)."""


class NotInEngine(EngineRefused):
    """The engine has no such container or image (the SDK's ``NotFound`` and ``ImageNotFound``)."""


@contextmanager
def engine_errors() -> Iterator[None]:
    """The docker SDK's errors raised inside, as panther-ops' own (the cause kept): core
    catches these and never imports docker."""
    import docker.errors

    try:
        yield
    except docker.errors.NotFound as exc:
        raise NotInEngine(str(exc)) from exc
    except docker.errors.APIError as exc:
        raise EngineRefused(str(exc)) from exc
    except docker.errors.DockerException as exc:
        raise EngineError(str(exc)) from exc

# The SDK's own default; lowered to what the engine speaks when it is older.
_MAX_API = (1, 45)


def _negotiate(server_api: str) -> str:
    try:
        major, minor = (int(x) for x in server_api.split(".")[:2])
    except ValueError:
        return "1.41"
    return f"{major}.{minor}" if (major, minor) <= _MAX_API else "{}.{}".format(*_MAX_API)


def client_over_ssh(ssh: paramiko.SSHClient, server_api: str, timeout: int = 60) -> DockerClient:
    """A DockerClient whose HTTP connections are dial-stdio channels of ``ssh``."""
    import docker
    from docker.transport.basehttpadapter import BaseHTTPAdapter
    from docker.transport.sshconn import SSHConnectionPool, SSHHTTPAdapter
    from urllib3._collections import RecentlyUsedContainer

    class ChannelAdapter(SSHHTTPAdapter):  # type: ignore[misc]
        """SSHHTTPAdapter bound to a connection we own (it neither opens nor closes it)."""

        def __init__(self) -> None:
            self.ssh_client = ssh
            self.ssh_host = "robot"
            self.ssh_params: dict[str, Any] = {}
            self.timeout = timeout
            self.max_pool_size = 4
            self.pools: Any = RecentlyUsedContainer(2, dispose_func=lambda p: p.close())
            BaseHTTPAdapter.__init__(self)

        def _connect(self) -> None:  # the transport owns the connection
            return None

        def get_connection(self, url: Any, proxies: Any = None) -> Any:
            with self.pools.lock:
                pool = self.pools.get(url)
                if pool is None:
                    pool = SSHConnectionPool(
                        ssh_client=ssh, timeout=self.timeout, maxsize=self.max_pool_size, host="robot"
                    )
                    self.pools[url] = pool
            return pool

        def get_connection_with_tls_context(
            self, request: Any, verify: Any, proxies: Any = None, cert: Any = None
        ) -> Any:
            return self.get_connection(request.url, proxies)

        def close(self) -> None:
            BaseHTTPAdapter.close(self)

    api = docker.APIClient(base_url="http://127.0.0.1:9", version=_negotiate(server_api), timeout=timeout)
    adapter = ChannelAdapter()
    api._custom_adapter = adapter
    api.mount("http+docker://ssh", adapter)
    api._unmount("http://", "https://")
    api.base_url = "http+docker://ssh"
    client = docker.DockerClient.__new__(docker.DockerClient)
    client.api = api
    return client


def local_client(socket_path: str = "/var/run/docker.sock") -> DockerClient:
    import docker

    return docker.DockerClient(base_url=f"unix://{socket_path}")
