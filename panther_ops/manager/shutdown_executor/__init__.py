"""Shutting hosts down without blocking: used by the Shutdown tree and by the CLI.

`ShutdownExecutor.step()` does bounded work (network I/O runs in worker threads);
`run_all(hosts, clock)` is the blocking convenience for the CLI.
"""

from __future__ import annotations

from panther_ops.manager.shutdown_executor.backends import (
    CommandOutcome,
    HttpShutdown,
    InlineDispatcher,
    ParamikoShutdown,
    ShutdownBackends,
    SubprocessPinger,
    SubprocessRunner,
    ThreadDispatcher,
    shutdown_path,
    sign_shutdown_request,
    ssh_backend,
    ssh_method,
)
from panther_ops.manager.shutdown_executor.hosts import (
    Method,
    ShutdownHost,
    ShutdownHostsFile,
    load_shutdown_hosts,
    parse_shutdown_hosts,
)
from panther_ops.manager.shutdown_executor.machine import (
    HostResult,
    HostShutdown,
    HostState,
    ShutdownExecutor,
    run_all,
)
from panther_ops.manager.shutdown_executor.openssh import OpenSshShutdown

__all__ = [
    "CommandOutcome",
    "HostResult",
    "HostShutdown",
    "HostState",
    "HttpShutdown",
    "InlineDispatcher",
    "Method",
    "OpenSshShutdown",
    "ParamikoShutdown",
    "ShutdownBackends",
    "ShutdownExecutor",
    "ShutdownHost",
    "ShutdownHostsFile",
    "SubprocessPinger",
    "SubprocessRunner",
    "ThreadDispatcher",
    "load_shutdown_hosts",
    "parse_shutdown_hosts",
    "run_all",
    "shutdown_path",
    "sign_shutdown_request",
    "ssh_backend",
    "ssh_method",
]
