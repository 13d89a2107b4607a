"""The RUTX11 router's NMEA forwarding (`gps router show|set`, and the router half of `gps
enable --router`): a room of its own inside `gps`, since the router is another device with
its own API (REST, through the robot's connection), its own reads and its own change.

* `plan.py`: the request, its checks, and the planner (pure: a function of the state read);
* `read.py`: the router reached and read (and `gps router show`);
* `apply.py`: the PUTs and the read back.
"""

from __future__ import annotations
