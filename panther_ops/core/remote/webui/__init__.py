"""The husarion-webui snap on a robot's User Computer.

* `remote`: its state on a User Computer, install and settings. The settings' keys and their
  one validator (the rules of the snap's configure hook) are `core.kinds.webui_settings`,
  used by every path that writes WebUI settings (and by the inventory's ``desired.webui``).
"""

from __future__ import annotations
