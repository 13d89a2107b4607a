"""Every translated file through the one validator of its file kind, for the target release.

The same `check_file` every write path uses (config push, shutdown hosts, the manager...):
a translation is planned only once the 2.3 validator of its kind accepts it, for the robot
it is meant for (target stack, wheel type, namespace); what it refuses is a
:class:`MigrationRefused` (exit 2, nothing written anywhere) naming the file, each error
(key and value) and the fix. The EKF files have no file kind of their own (panther-ops does
not push them): their translator is their only check.
"""

from __future__ import annotations

import re
import tempfile
from dataclasses import dataclass, replace
from pathlib import Path

from panther_ops.core.driver.migrate.translated import MigrationRefused, version_label
from panther_ops.core.kinds import FileKind, FileKindError, Target, check_file

_WHEEL_FILE = re.compile(r"(WH0[1245])_controller\.yaml$")


@dataclass(frozen=True)
class Checker:
    """The robot the translated files are meant for (stack: the target release)."""

    target: Target

    def wheel_for(self, path: str) -> Target:
        """A stock tree controller file is for its own wheel type (the tree holds all four);
        any other controller file for the robot's."""
        m = _WHEEL_FILE.search(path)
        return replace(self.target, wheel_type=m.group(1)) if m else self.target

    def check(self, kind: FileKind, path: str, data: bytes, *, project: tuple[str, bytes] | None = None) -> list[str]:
        """``data`` (the translation of ``path``) through ``kind``'s validator: its warnings.

        ``project``: for a behaviour tree file, (name, content) of the BT project that includes
        it; the project is checked with the translated tree next to it.

        Raises:
            MigrationRefused: the validator refuses the translation.
        """
        target = self.wheel_for(path) if kind is FileKind.CONTROLLER else self.target
        try:
            if project is None:
                return check_file(kind, path, data, target=target)
            with tempfile.TemporaryDirectory(prefix="panther-ops-migrate-") as tmp:
                name, content = project
                (Path(tmp) / path.rsplit("/", 1)[-1]).write_bytes(data)
                (Path(tmp) / name).write_bytes(content)
                return check_file(kind, path, content, local=Path(tmp) / name, target=target)
        except FileKindError as exc:
            release = version_label(target.stack.version) if target.stack is not None else "2.3"
            raise MigrationRefused(
                f"its husarion_ugv {release} form is refused by the {kind.value} check, so the migration would "
                "write a file the new driver cannot use:\n" + "\n".join(f"  {e}" for e in exc.errors),
                path=path,
                hint="fix the named key in the 2.2 file (or `panther-ops config restore-defaults` for the stock file), "
                     "then migrate again: nothing was changed") from exc
