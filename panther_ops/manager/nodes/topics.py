"""Conditions on a topic's last message: CheckStringMsg (husarion_ugv 2.3.2).

As husarion_ugv_ros@2.3.2:husarion_ugv_manager/src/plugins/condition/check_string_msg.cpp (a
BehaviorTree.ROS2 RosTopicSubNode<std_msgs/String> that latches the last message): SUCCESS
when the last message received on ``topic_name`` has ``data`` equal to the port ``data``,
FAILURE otherwise, also before any message arrived. The stock Lights tree of 2.3.2 checks
``twist_mux_controller/source`` for ``manual`` and ``autonomous``
(husarion_ugv_ros@2.3.2:husarion_ugv_manager/behavior_trees/lights.xml).
"""

from __future__ import annotations

from typing import ClassVar

from py_trees.common import Status

from panther_ops.manager.nodes.base import PortedLeaf, PortSpec


class CheckStringMsg(PortedLeaf):
    """SUCCESS when the last std_msgs/String on ``topic_name`` says ``data`` (ports: topic_name, data)."""

    PORTS: ClassVar[dict[str, PortSpec]] = {
        "topic_name": PortSpec("str", description="Topic name"),
        "data": PortSpec("str", description="Specifies the expected state of the data field"),
    }

    def update(self) -> Status:
        topic, expected = self.port("topic_name"), self.port("data")
        last = self.ctx.topics.last(topic)
        self.feedback_message = f"{topic}: {'no message' if last is None else repr(last)}, expected {expected!r}"
        return Status.SUCCESS if last == expected else Status.FAILURE
