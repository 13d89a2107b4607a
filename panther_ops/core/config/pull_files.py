"""Where `config pull` puts the files it fetched on this machine: ``--output FILE`` (one
robot) or ``--dest DIR`` (``DIR/<robot>/<kind>.yaml``, a BT project ``<kind>.btproj``, kept
inside DIR), each written atomically (transport/localfile.py); else stdout (the CLI's).

A BT project comes with the files it includes (`bt_pull`), written beside it at their relative
paths, so the project stays valid whatever it is renamed to. The file the user names is
replaced as before; an included file, which the user did not name, that exists with other
content is not replaced without ``--force`` (exit 2 before anything is written)."""

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
    robot: str = ""
    """the robot it came from"""
    included: bool = False
    """a file the pulled project includes (not named by the user)"""


def check_output(output: Path | None) -> None:
    """--output names a file in an existing directory (exit 2 before the inventory is read)."""
    if output is not None and (output.is_dir() or not output.parent.is_dir()):
        raise UsageError(f"--output {output}: not a file path in an existing directory")


def check_dest(dest: Path | None, robots: int) -> None:
    """Several robots need --dest (exit 2 before anything is fetched)."""
    if robots > 1 and dest is None:
        raise UsageError(f"{robots} robots chosen: pass --dest DIR (files go to DIR/<robot>/)")


def local_writes(got: dict[str, bytes], kind: FileKind, output: Path | None, dest: Path | None,
                includes: dict[str, dict[str, bytes]] | None = None) -> list[LocalWrite]:
    """The files to write for what each robot sent (none: stdout), with the files each robot's
    project includes (``includes``: robot -> relative name -> content) beside it; a robot's
    directory under --dest, or an included file, that resolves outside its directory (a link)
    is refused."""
    from panther_ops.core.robot.push import BT_ARGS

    mains: dict[str, Path] = {}
    if dest is not None:
        root = dest.resolve()
        suffix = "btproj" if kind in BT_ARGS else "yaml"
        for name in got:
            where = dest / name
            if not where.resolve().is_relative_to(root):
                raise UsageError(f"--dest {dest}: {where} leads outside it ({where.resolve()})",
                                 hint="remove the link or choose another --dest")
            mains[name] = where / f"{kind.value}.{suffix}"
    elif output is not None:
        mains = dict.fromkeys(got, output)
    writes = []
    for name, path in mains.items():
        writes.append(LocalWrite(path, got[name], name))
        base = path.parent
        for rel, data in (includes or {}).get(name, {}).items():
            where = base / rel
            if not where.resolve().is_relative_to(base.resolve()):
                raise UsageError(f"{where}: an included file of the project would be written outside {base} "
                                 f"({where.resolve()})", hint="remove the link or pull into another directory")
            if where.resolve() == path.resolve():
                raise UsageError(f"{path}: the project includes a file of that name ({rel})",
                                 hint="name the pulled project another way (a .btproj)")
            writes.append(LocalWrite(where, data, name, included=True))
    return writes


def settle(writes: list[LocalWrite], force: bool) -> tuple[list[LocalWrite], list[LocalWrite]]:
    """The writes to do and the included files already there with the same content; an
    included file there with other content is refused unless ``force``."""
    todo: list[LocalWrite] = []
    same: list[LocalWrite] = []
    differ: list[Path] = []
    for w in writes:
        if w.included and w.path.is_file():
            if w.path.read_bytes() == w.data:
                same.append(w)
                continue
            if not force:
                differ.append(w.path)
        todo.append(w)
    if differ:
        raise UsageError("the project includes files that exist here with other content: "
                         + ", ".join(str(p) for p in differ) + "; nothing was written",
                         hint="pull into another directory, or pass --force to replace them")
    return todo, same


def write_files(writes: list[LocalWrite]) -> None:
    from panther_ops.transport.localfile import write_atomic

    for w in writes:
        write_atomic(w.path, w.data)
