"""The husarion-webui snap on a robot's User Computer.

* `settings`: its configuration keys and the one validator of them (the rules of the
  snap's configure hook), used by every path that writes WebUI settings.
* `remote`: the snap's state read on the User Computer (or a demo robot's recording),
  `webui set|status|start|stop|url`, and `apply_settings`, the one path that changes keys.
* `install`: `webui install` (clocks checked first).
* `defaults`: ``ros.namespace`` defaults to the robot's namespace.
* `desired`: the inventory's ``desired.webui`` for `apply` and `config diff`.
"""

from __future__ import annotations
