"""Import paramiko without what it loads but a fleet command does not use.

Every fleet command waits for paramiko before its first connection, so the CLI imports it
through :func:`import_paramiko`, which keeps two imports off that path:

- ``paramiko.config`` imports invoke (fabric's task runner: ~50 ms, unittest.mock and asyncio
  included) only to run ``Match exec`` lines of an ssh_config: invoke is kept out while
  paramiko loads and reached lazily, the first time such a line needs it;
- paramiko 5 reads its own version through ``importlib.metadata`` (~20 ms: the email package
  and a scan of site-packages): while it loads, a stand-in answers ``version("paramiko")``
  from the name of paramiko's ``.dist-info`` directory and hands everything else to the real
  module.

Once loaded, two per-packet helpers written in Python are replaced by C ones, and the
timer thread of each key exchange by a deadline (see :func:`_quicker`).
"""

from __future__ import annotations

import importlib
import importlib.util
import os
import sys
import threading
import time
from types import ModuleType
from typing import Any

_lock = threading.Lock()


class _LazyInvoke:
    """Stands in for the invoke module in ``paramiko.config``; imports it on first use."""

    def __getattr__(self, name: str) -> Any:
        return getattr(importlib.import_module("invoke"), name)


class _QuickMetadata(ModuleType):
    """Stands in for ``importlib.metadata`` while paramiko loads (see the module's text)."""

    def __init__(self, dists: dict[str, str]) -> None:
        super().__init__("importlib.metadata")
        self._dists = dists

    def version(self, name: str) -> str:
        found = self._dists.get(name.lower().replace("-", "_"))
        return found if found is not None else str(_real_metadata().version(name))

    def __getattr__(self, name: str) -> Any:
        return getattr(_real_metadata(), name)


def _real_metadata() -> ModuleType:
    """The real ``importlib.metadata``, imported now if need be (the stand-in steps aside)."""
    current = sys.modules.get("importlib.metadata")
    if isinstance(current, _QuickMetadata):
        sys.modules.pop("importlib.metadata", None)
    return importlib.import_module("importlib.metadata")


def _dist_versions(package: str) -> dict[str, str]:
    """``{name: version}`` of the ``*.dist-info`` directories beside ``package`` (names normalised)."""
    spec = importlib.util.find_spec(package)
    if spec is None or not spec.origin:
        return {}
    site = os.path.dirname(os.path.dirname(spec.origin))
    out: dict[str, str] = {}
    with os.scandir(site) as entries:
        for e in entries:
            if e.name.endswith(".dist-info") and "-" in e.name:
                name, _, version = e.name[: -len(".dist-info")].partition("-")
                out[name.lower().replace("-", "_").replace(".", "_")] = version
    return out


def import_paramiko() -> ModuleType:
    """``import paramiko``, without importing invoke until an ssh_config needs it.

    The stand-ins are in ``sys.modules`` while paramiko loads, for every thread: panther-ops
    imports paramiko only through this function (a lock orders the threads), so no other
    thread is half-way through importing paramiko meanwhile (which once made a task that
    imported it directly find the stand-in in the middle of loading the real module).
    """
    with _lock:
        if "paramiko" in sys.modules:
            _quicker(sys.modules["paramiko"])
            return sys.modules["paramiko"]
        # Stand-ins only where nothing is (setdefault: never over a module another thread is
        # importing); every import of paramiko in panther-ops comes through here, serialized.
        keep_out = "invoke" not in sys.modules and sys.modules.setdefault("invoke", None) is None  # type: ignore[arg-type]
        quick: _QuickMetadata | None = None
        if "importlib.metadata" not in sys.modules:
            quick = _QuickMetadata(_dist_versions("paramiko"))
            if sys.modules.setdefault("importlib.metadata", quick) is not quick:
                quick = None
        try:
            import paramiko
        finally:
            if keep_out and sys.modules.get("invoke", ...) is None:
                del sys.modules["invoke"]
            if quick is not None and sys.modules.get("importlib.metadata") is quick:
                del sys.modules["importlib.metadata"]
        if keep_out and getattr(paramiko.config, "invoke", None) is None:
            paramiko.config.invoke = _LazyInvoke()  # type: ignore[attr-defined]
        _quicker(paramiko)
        return paramiko


REPLACED: dict[str, Any] = {}
"""paramiko's own helpers that :func:`_quicker` replaced, by name (the tests compare them)."""


def _quicker(paramiko: ModuleType) -> None:
    """Three of paramiko's helpers done without their cost, with the same results.

    - ``util.constant_time_bytes_eq`` checks the MAC of every packet received in a Python
      loop over its bytes (~15 µs a packet, ~25 packets per robot); ``hmac.compare_digest``
      is the standard library's constant-time comparison of the same.
    - ``util.safe_string`` escapes the debug messages sshd sends (one per login, listing the
      key's options) byte by byte even when nothing is logged; a table does the same.
    - ``Packetizer.start_handshake`` starts a timer thread per key exchange: a deadline
      (:class:`_HandshakeDeadline`) answers ``handshake_timed_out`` the same way.
    """
    import hmac

    if REPLACED:
        return
    util = paramiko.util
    slow_eq, slow_safe = util.constant_time_bytes_eq, util.safe_string
    REPLACED.update(constant_time_bytes_eq=slow_eq, safe_string=slow_safe)

    def constant_time_bytes_eq(a: Any, b: Any) -> bool:
        try:
            return hmac.compare_digest(a, b)
        except TypeError:  # other than bytes, or str that is not ASCII: paramiko's own
            return bool(slow_eq(a, b))

    table = [bytes([i]) if 32 <= i <= 127 else b"%%%02X" % i for i in range(256)]

    def safe_string(s: Any) -> bytes:
        if isinstance(s, (bytes, bytearray)):
            return b"".join([table[c] for c in s])
        return bytes(slow_safe(s))

    util.constant_time_bytes_eq = constant_time_bytes_eq
    util.safe_string = safe_string
    paramiko.hostkeys.constant_time_bytes_eq = constant_time_bytes_eq

    packetizer = paramiko.packet.Packetizer
    REPLACED.update(start_handshake=packetizer.start_handshake, handshake_timed_out=packetizer.handshake_timed_out)

    def start_handshake(self: Any, timeout: float) -> None:
        if not self._Packetizer__timer:
            self._Packetizer__timer = _HandshakeDeadline(float(timeout))

    def handshake_timed_out(self: Any) -> bool:
        timer = self._Packetizer__timer
        if not timer or self._Packetizer__handshake_complete:
            return False
        return timer.expired() if isinstance(timer, _HandshakeDeadline) else bool(self._Packetizer__timer_expired)

    packetizer.start_handshake = start_handshake
    packetizer.handshake_timed_out = handshake_timed_out


class _HandshakeDeadline:
    """Stands in for the ``threading.Timer`` paramiko starts for every connection's key
    exchange (a thread each, started and cancelled within milliseconds, 30 for 30 robots):
    its deadline is read where paramiko asks whether the time is up."""

    def __init__(self, timeout: float) -> None:
        self.at = time.monotonic() + timeout

    def expired(self) -> bool:
        return time.monotonic() >= self.at

    def cancel(self) -> None:
        return None
