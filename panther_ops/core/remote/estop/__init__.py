"""The driver's E-stop, seen and changed through its ROS API inside the driver container.

* `answers`: what the ROS 2 CLI prints (topic echo, service call, topic info -v), parsed.
* `calls`: the one command per robot that asks the driver (namespace and container per
  stack version), the demo robots' recorded answers, and the robot tasks of
  `estop status|trigger|reset`.
"""

from __future__ import annotations
