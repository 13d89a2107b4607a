"""The husarion-webui snap on a robot's User Computer.

* The settings' keys and their one validator (the rules of the snap's configure hook) are
  `core.kinds.webui_settings`, used by every path that writes WebUI settings (and by the
  inventory's ``desired.webui``).
* `remote`: the snap's state read on the User Computer (or a demo robot's recording),
  `webui set|status|start|stop|url`, and `apply_settings`, the one path that changes keys.
* `install`: `webui install` (clocks checked first).
* `state`: the snap's state as read and the plan of `webui set` (pure).
* `defaults`: ``ros.namespace`` defaults to the robot's namespace (pure; `remote.robot_namespace`
  reads it).
* `plan` (pure) and `desired` (its reads, and the change): the inventory's
  ``desired.webui`` for `apply` and `config diff`.
"""

from __future__ import annotations
