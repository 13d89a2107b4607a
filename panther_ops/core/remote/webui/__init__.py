"""The husarion-webui snap on a robot's User Computer.

* `settings`: its configuration keys and the one validator of them (the rules of the
  snap's configure hook), used by every path that writes WebUI settings.
"""

from __future__ import annotations
