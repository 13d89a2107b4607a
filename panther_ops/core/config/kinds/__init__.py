"""One validator per file kind that panther-ops writes or deploys to a robot.

Every path that writes a file of a kind (``config push``, ``lights deploy``, ``shutdown
hosts add/remove``, ``apply``, ``manager deploy``...) checks the new content through
`check_file` (registry in `registry.py`), so the same content gets the same verdict and the
same message whatever command carries it: the message of the kind's dedicated validator
(``bt validate``, ``lights validate``, ``shutdown hosts validate``, the controller limits of
``config set``).
"""

from __future__ import annotations

from panther_ops.core.config.kinds.registry import PUSHABLE, FileKind, FileKindError, Target, check_file

__all__ = ["PUSHABLE", "FileKind", "FileKindError", "Target", "check_file"]
