"""One private py_trees blackboard namespace per tree instance.

py_trees keeps a single process-wide storage. Giving every tree instance its own namespace
(``/panther/lights0``, ``/panther/safety1`` ...) keeps the Lights, Safety and Shutdown trees
apart, as BT.CPP gives each tree its own blackboard, and lets tests build the same tree twice.
Behaviours still declare what they read and write through their own py_trees clients.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Mapping
from typing import Any

import py_trees
from py_trees.common import Access

_ids = itertools.count()


class TreeBlackboard:
    """A tree's blackboard: a namespace plus a writer client for inputs and constants."""

    def __init__(self, tree: str) -> None:
        self.tree = tree
        self.namespace = f"/panther/{tree.lower()}{next(_ids)}"
        self._writer = py_trees.blackboard.Client(name=f"{tree}Inputs", namespace=self.namespace)
        self._written: set[str] = set()

    def absolute(self, key: str) -> str:
        """The storage key of a tree-relative key."""
        return f"{self.namespace}/{key.lstrip('/')}"

    def client(self, behaviour: py_trees.behaviour.Behaviour, reads: Iterable[str] = (),
               writes: Iterable[str] = ()) -> py_trees.blackboard.Client:
        """Attach a client to `behaviour`, registering the keys it reads and writes."""
        client = behaviour.attach_blackboard_client(name=behaviour.name, namespace=self.namespace)
        writes = set(writes)
        for key in writes:
            client.register_key(key=key, access=Access.WRITE)
        for key in set(reads) - writes:
            client.register_key(key=key, access=Access.READ)
        return client

    def set(self, key: str, value: Any) -> None:
        """Write an entry as the tree's owner (inputs, constants, initial state)."""
        if key not in self._written:
            self._writer.register_key(key=key, access=Access.WRITE)
            self._written.add(key)
        if py_trees.blackboard.Blackboard.activity_stream is None:
            # the registered key's storage slot, without the client's per-call bookkeeping
            py_trees.blackboard.Blackboard.storage[self.absolute(key)] = value
        else:
            self._writer.set(key, value)

    def update(self, values: Mapping[str, Any]) -> None:
        """Write several entries."""
        for key, value in values.items():
            self.set(key, value)

    def get(self, key: str, default: Any = None) -> Any:
        """Read an entry for introspection (snapshots, tests); `default` when absent."""
        absolute = self.absolute(key)
        return py_trees.blackboard.Blackboard.storage.get(absolute, default)

    def exists(self, key: str) -> bool:
        """True when the entry has been written."""
        return self.absolute(key) in py_trees.blackboard.Blackboard.storage

    def entries(self) -> dict[str, Any]:
        """All entries of this tree, by tree-relative key."""
        prefix = self.namespace + "/"
        storage = py_trees.blackboard.Blackboard.storage
        return {k[len(prefix):]: v for k, v in storage.items() if k.startswith(prefix)}

    def clear(self) -> None:
        """Remove every entry of this tree from the process-wide storage."""
        prefix = self.namespace + "/"
        storage = py_trees.blackboard.Blackboard.storage
        for key in [k for k in storage if k.startswith(prefix)]:
            del storage[key]
