#!/bin/sh
# `ros2` of the panther-ops lab's nmea-gps stand-in image (tests/lab/nmea_image.py). NOT ROS 2.
# Accepts the two forms the real husarion/nmea-gps image runs:
#   ros2 launch /husarion_utils/nmea_navsat.launch.py robot_namespace:=NS     (port 5000)
#   ros2 run nmea_navsat_driver nmea_socket_driver --ros-args -p port:=N ... (port N)
# and listens on that UDP port like the driver (nmea-listen), ending at once on SIGTERM.
echo "[nmea-gps stand-in] ros2 $*"
port=5000
case "${1:-} ${2:-}" in
    "launch /husarion_utils/nmea_navsat.launch.py") ;;
    "run nmea_navsat_driver") [ "${3:-}" = nmea_socket_driver ] || { echo "no executable ${3:-}" >&2; exit 1; } ;;
    *) echo "[nmea-gps stand-in] unknown command: ros2 $*" >&2; exit 1 ;;
esac
for a in "$@"; do
    case "$a" in
        port:=*) port=${a#port:=} ;;
    esac
done
exec /usr/bin/nmea-listen "$port"
