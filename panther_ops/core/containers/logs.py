"""A container's logs through the docker SDK (driver, manager): options, reading, prefixing."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from panther_ops.core.containers.times import engine_now


@dataclass(frozen=True)
class LogOptions:
    tail: int | None = 100
    since_s: float | None = None
    follow: bool = False
    timestamps: bool = False


def read_logs(client: Any, ctr: Any, opts: LogOptions) -> tuple[str, Any]:
    """(container name, logs): bytes, or an iterator of chunks when following."""
    kwargs: dict[str, Any] = {"stdout": True, "stderr": True, "timestamps": opts.timestamps,
                              "tail": "all" if opts.tail is None else opts.tail}
    if opts.since_s is not None:
        kwargs["since"] = int(engine_now(client).timestamp() - opts.since_s)
    if opts.follow:
        return ctr.name, ctr.logs(stream=True, follow=True, **kwargs)
    return ctr.name, ctr.logs(**kwargs)


def prefix_lines(name: str, data: bytes) -> bytes:
    """Every line of ``data`` as ``name | line``."""
    head = name.encode() + b" | "
    return b"".join(head + (ln if ln.endswith(b"\n") else ln + b"\n") for ln in data.splitlines(keepends=True))


def iter_chunks(stream: Any) -> Iterator[bytes]:
    """Chunks of a docker log stream (bytes; text is encoded)."""
    for chunk in stream:
        yield chunk if isinstance(chunk, bytes) else str(chunk).encode()
