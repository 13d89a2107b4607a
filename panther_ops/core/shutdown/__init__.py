"""Shutting user computers down with the robot: the hosts file, setup, check and the shutdown.

* `core/kinds/hostsfile`: the shutdown hosts file (read, validate, edit keeping comments).
* `plan`: the robot's own hosts file (where it is per stack version) and the pure plans that
  change it (edits, ``desired.shutdown_hosts``); `read`: the file in use, read, and the
  pipeline plan of an edit; `localfile`: a local hosts file as a target of the same edits.
* `links`: what a shutdown runs to reach a LAN host and how each answer is judged (the
  robot as the way to its LAN: `transport/lan.py`).
* `run`: running the shared executor (`panther_ops.manager.shutdown_executor`) and
  `shutdown robot`.
* `check`, `setup`: per-host checks and the manual's setup procedure, through the robot.
"""

from __future__ import annotations
