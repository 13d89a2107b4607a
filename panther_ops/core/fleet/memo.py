"""Results of pure computations, shared by the robots of one command.

Robots of one release usually carry byte-identical files (compose.yaml as the image's
setup wrote it), so a fleet command plans each distinct file once: the robots of a
30-robot fleet with three releases cost three YAML round trips, not thirty. Keys hold the
whole input (file bytes included), never a hash alone; values must be immutable (or copied
by the caller) since every robot with that input gets the same object.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Hashable
from typing import Generic, TypeVar

V = TypeVar("V")


class Memo(Generic[V]):
    """A bounded, thread-safe memo: concurrent callers with one key compute it once.

    A computation that raises is not remembered: each caller gets its own error.
    """

    def __init__(self, size: int = 64) -> None:
        self.size = size
        self._values: dict[Hashable, V] = {}
        self._locks: dict[Hashable, threading.Lock] = {}
        self._guard = threading.Lock()
        self.computed = 0
        """How many times a value was computed (the rest were shared)."""

    def get(self, key: Hashable, compute: Callable[[], V]) -> V:
        with self._guard:
            if key in self._values:
                return self._values[key]
            lock = self._locks.setdefault(key, threading.Lock())
        with lock:
            with self._guard:
                if key in self._values:
                    return self._values[key]
            try:
                value = compute()
            except BaseException:
                with self._guard:
                    self._locks.pop(key, None)
                raise
            with self._guard:
                self.computed += 1
                if len(self._values) >= self.size:
                    self._values.clear()
                self._values[key] = value
                self._locks.pop(key, None)
            return value
