"""The husarion-webui snap on a robot's User Computer.

* The settings' keys and their one validator (the rules of the snap's configure hook) are
  `core.kinds.webui_settings`, used by every path that writes WebUI settings (and by the
  inventory's ``desired.webui``).
* `plan.py` (pure planners): the inventory's ``desired.webui`` for `apply` and `config diff`;
  `state.py` (pure): the snap's state as read and the plan of `webui set`; `defaults.py`
  (pure): ``ros.namespace`` defaults to the robot's namespace.
* `read.py`: the snap's state read on the User Computer (or a demo robot's recording), the
  robot's namespace, `webui status|url`, the plan of `webui set`, the fact ``desired.webui``
  plans from.
* `apply.py`: `apply_settings`, the one path that changes keys (`webui set` and `apply`),
  `webui start|stop`.
* `install.py`: `webui install` (clocks checked first).
"""

from __future__ import annotations
