"""Import paramiko without invoke.

``paramiko.config`` imports invoke (fabric's task runner: ~50 ms, unittest.mock and asyncio
included) at import time, only to run ``Match exec`` lines of an ssh_config. Every fleet
command waits for paramiko before its first connection, so the CLI imports it through
:func:`import_paramiko`: invoke is kept out while paramiko loads and then reached lazily,
the first time an ssh_config's ``Match exec`` needs it.
"""

from __future__ import annotations

import importlib
import sys
import threading
from types import ModuleType
from typing import Any

_lock = threading.Lock()


class _LazyInvoke:
    """Stands in for the invoke module in ``paramiko.config``; imports it on first use."""

    def __getattr__(self, name: str) -> Any:
        return getattr(importlib.import_module("invoke"), name)


def import_paramiko() -> ModuleType:
    """``import paramiko``, without importing invoke until an ssh_config needs it."""
    with _lock:
        if "paramiko" in sys.modules:
            return sys.modules["paramiko"]
        keep_out = "invoke" not in sys.modules
        if keep_out:
            sys.modules["invoke"] = None  # type: ignore[assignment]  # `import invoke` raises ImportError
        try:
            import paramiko
        finally:
            if keep_out and sys.modules.get("invoke", ...) is None:
                del sys.modules["invoke"]
        if keep_out and getattr(paramiko.config, "invoke", None) is None:
            paramiko.config.invoke = _LazyInvoke()  # type: ignore[attr-defined]
        return paramiko
