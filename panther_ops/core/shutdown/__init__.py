"""Shutting user computers down with the robot: the hosts file, setup, check and the shutdown.

* `hostsfile`: the shutdown hosts file (read, validate, edit keeping comments).
* `robotfile`: the robot's own hosts file (where it is per stack version) and the pipeline
  plans that change it.
* `remote`: the robot as the way to its LAN (ping, SSH with the robot's key, HTTP) and the
  executor backends "from here" or "via the robot".
* `run`: running the shared executor (`panther_ops.manager.shutdown_executor`) and
  `shutdown robot`.
* `check`, `setup`: per-host checks and the manual's setup procedure, through the robot.
"""

from __future__ import annotations
