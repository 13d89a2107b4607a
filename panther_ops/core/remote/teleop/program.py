"""The keyboard teleoperation program `teleop` runs in the driver container (``python3 -c``).

The manual drives the robot with ``teleop_twist_keyboard`` in the driver container, but the
images do not have it: they are built ``FROM husarnet/ros:humble-ros-core`` with only what
rosdep installs for the bringup's dependencies, and no package.xml of panther_ros 2.0.4 /
2.1.1 or husarion_ugv_ros 2.2.0 / 2.2.2 depends on teleop_twist_keyboard
(husarion/husarion_ugv_ros@2.2.2:docker/Dockerfile.hardware,
husarion/panther-docker@2.1.2:Dockerfile.hardware). What they do have, being ROS 2 images,
is python3 with rclpy and geometry_msgs (REP 2001's ros_core). So this small program does
what the manual's command does, with only those:

* keys as teleop_twist_keyboard's: ``u i o / j k l / m , .`` move (forward, turn, both),
  ``k`` or any other key stops; ``q``/``z`` raise/lower both speeds by 10 %, ``w``/``x`` the
  linear, ``e``/``c`` the angular one; speeds start at 0.5 m/s and 1.0 rad/s;
* the current ``geometry_msgs/Twist`` is published every ``1/rate`` s on schedule (the
  manual's ``repeat_rate``: the robot stops when no command arrived for 1 s), a key changes
  it at once;
* Ctrl-C (or the end of input) ends it, after one zero Twist (the robot stops), as
  teleop_twist_keyboard does.

Arguments: the absolute cmd_vel topic, the rate in Hz, and ``stamped`` (husarion_ugv 2.3.2: its twist
mux takes ``geometry_msgs/TwistStamped``, husarion_ugv_ros@2.3.2:ROS_API.md; the stamp is left zero,
which the mux replaces by the time of arrival: husarion/husarion_controllers@f4f78b7:twist_mux_controller/
include/twist_mux_controller/twist_msg_subscriber.hpp, the mux's merge (#14); husarion_ugv_ros@2.3.2:
husarion_ugv/hardware_deps.repos pins 2b2b37a, a later commit not in the mirror read here)
or ``plain`` (a ``Twist``, up to 2.3.1).
`keyboard.prepare` checks first, in the same round trip as the E-stop, that the container's python3
imports rclpy and geometry_msgs.
"""

from __future__ import annotations

NODE_NAME = "panther_ops_teleop"
BANNER = "Reading from the keyboard and publishing on"
"""The program's first line: ``<BANNER> <topic> at <rate> Hz``."""

PROGRAM = r'''
import os, select, sys, termios, time, tty
import rclpy
from geometry_msgs.msg import Twist

topic, rate = sys.argv[1], float(sys.argv[2])
stamped = sys.argv[3:4] == ["stamped"]
if stamped:
    from geometry_msgs.msg import TwistStamped
MOVES = {"u": (1, 1), "i": (1, 0), "o": (1, -1), "j": (0, 1), "l": (0, -1),
         "m": (-1, -1), ",": (-1, 0), ".": (-1, 1)}
SCALE = {"q": (1.1, 1.1), "z": (0.9, 0.9), "w": (1.1, 1.0), "x": (0.9, 1.0), "e": (1.0, 1.1), "c": (1.0, 0.9)}
speed, turn = 0.5, 1.0
move = (0, 0)
rclpy.init()
node = rclpy.create_node("NODE_NAME")
pub = node.create_publisher(TwistStamped if stamped else Twist, topic, 10)
fd = sys.stdin.fileno()
saved = termios.tcgetattr(fd) if os.isatty(fd) else None


def send(x, z):
    msg = TwistStamped() if stamped else Twist()
    twist = msg.twist if stamped else msg
    twist.linear.x, twist.angular.z = float(x), float(z)
    pub.publish(msg)


try:
    if saved is not None:
        tty.setcbreak(fd)  # keys one by one, Ctrl-C still a signal
    print(f"BANNER {topic} at {rate:g} Hz (panther-ops teleop)")
    print("u i o / j k l / m , . move, k stops; q/z w/x e/c speeds; Ctrl-C ends", flush=True)
    period = 1.0 / rate
    due = time.monotonic() + period
    while True:
        left = due - time.monotonic()
        if left > 0 and select.select([fd], [], [], left)[0]:
            key = os.read(fd, 1).decode(errors="replace")
            if key in ("", "\x03", "\x04"):
                break
            if key in SCALE:
                speed, turn = speed * SCALE[key][0], turn * SCALE[key][1]
                print(f"speed {speed:.2f} m/s, turn {turn:.2f} rad/s", flush=True)
            else:
                move = MOVES.get(key, (0, 0))
            continue
        send(move[0] * speed, move[1] * turn)
        due += period
        if due < time.monotonic():  # fell behind: start the schedule again from now
            due = time.monotonic() + period
except KeyboardInterrupt:
    pass
finally:
    send(0.0, 0.0)
    if saved is not None:
        termios.tcsetattr(fd, termios.TCSADRAIN, saved)
    node.destroy_node()
    rclpy.shutdown()
'''.replace("NODE_NAME", NODE_NAME).replace("BANNER", BANNER)

CHECK = "import rclpy, geometry_msgs.msg, termios"
"""What the program imports beyond the standard library: checked in the container before it starts."""
