"""Where `config pull` puts the files it fetched on this machine: ``--output FILE`` (one
robot) or ``--dest DIR`` (``DIR/<robot>/<kind>.yaml``, kept inside DIR), each written
atomically (transport/localfile.py); else stdout (the CLI's)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from panther_ops.core.kinds import FileKind
from panther_ops.errors import UsageError


@dataclass(frozen=True)
class LocalWrite:
    """One file to write on this machine."""

    path: Path
    data: bytes


def check_output(output: Path | None) -> None:
    """--output names a file in an existing directory (exit 2 before the inventory is read)."""
    if output is not None and (output.is_dir() or not output.parent.is_dir()):
        raise UsageError(f"--output {output}: not a file path in an existing directory")


def check_dest(dest: Path | None, robots: int) -> None:
    """Several robots need --dest (exit 2 before anything is fetched)."""
    if robots > 1 and dest is None:
        raise UsageError(f"{robots} robots chosen: pass --dest DIR (files go to DIR/<robot>/)")


def plan_writes(got: dict[str, bytes], kind: FileKind, output: Path | None, dest: Path | None) -> list[LocalWrite]:
    """The files to write for what each robot sent (none: stdout); a robot's directory under
    --dest that resolves outside it (a link) is refused."""
    if dest is not None:
        root = dest.resolve()
        writes = []
        for name, data in got.items():
            where = dest / name
            if not where.resolve().is_relative_to(root):
                raise UsageError(f"--dest {dest}: {where} leads outside it ({where.resolve()})",
                                 hint="remove the link or choose another --dest")
            writes.append(LocalWrite(where / f"{kind.value}.yaml", data))
        return writes
    if output is not None:
        return [LocalWrite(output, data) for data in got.values()]
    return []


def write_files(writes: list[LocalWrite]) -> None:
    from panther_ops.transport.localfile import write_atomic

    for w in writes:
        write_atomic(w.path, w.data)
