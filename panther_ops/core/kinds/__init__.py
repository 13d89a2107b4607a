"""One validator per file kind that panther-ops writes or deploys to a robot.

Every path that writes a file of a kind (``config push``, ``lights deploy``, ``shutdown
hosts add/remove``, ``apply``, ``manager deploy``...) checks the new content through
`check_file` (registry in `registry.py`), so the same content gets the same verdict and the
same message whatever command carries it: the message of the kind's dedicated validator
(``bt validate``, ``lights validate``, ``shutdown hosts validate``, the controller limits of
``config set``).

The shared engine, below `fleet` (whose change pipeline checks every compose file a plan
writes, and whose inventory checks its ``desired:`` blocks with these rules) and above `stack`
and `yaml`: the kinds' models and rules live here, not in a feature, so every feature and the
engine use the same one. Besides the registry: `arg_catalogue` (the driver's launch
arguments per stack version, shared with ``config set`` and ``desired.launch_args``),
`controller_limits` (the wheel types' limits, shared with ``config set`` and
``desired.controller``), `hostsfile` (the shutdown hosts file: both formats, validation and
edits), `webui_settings` (the husarion-webui snap's keys and its configure hook's rules).
"""

from __future__ import annotations

from panther_ops.core.kinds.registry import CHECKED, PUSHABLE, FileKind, FileKindError, Target, check_file

__all__ = ["CHECKED", "PUSHABLE", "FileKind", "FileKindError", "Target", "check_file"]
