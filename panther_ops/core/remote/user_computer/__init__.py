"""The robot's User Computer (inventory ``user_computer:``), reached through the robot.

* `access`: where it is (inventory, defaults) and a fabric session to it over the robot's
  open connection, with strict host keys and sudo answered with a password given once.
"""

from __future__ import annotations
