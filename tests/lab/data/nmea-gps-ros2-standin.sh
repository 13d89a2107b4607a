#!/bin/sh
# `ros2` of the panther-ops lab's nmea-gps stand-in image (tests/lab/nmea_image.py). NOT ROS 2.
# Accepts the two forms the real husarion/nmea-gps image runs:
#   ros2 launch /husarion_utils/nmea_navsat.launch.py robot_namespace:=NS     (port 5000)
#   ros2 run nmea_navsat_driver nmea_socket_driver --ros-args -p port:=N ... (port N)
# and listens on that UDP port like the driver (nmea-listen), ending at once on SIGTERM. The
# fix topic and frame, as the real node gets them:
#   launch form: the node is named <device_namespace> (default gps) in <robot_namespace>
#     (default $ROBOT_NAMESPACE, else none), `fix` remapped to ~/fix: /NS/gps/fix; frame_id
#     <device_namespace> with tf_prefix "NS/" (empty without a namespace): NS//gps
#     (husarion/nmea-gps-docker@1accbc32:husarion_utils/nmea_navsat.launch.py);
#   run form: the node's own relative `fix` in its namespace (-r __ns:=/NS): /NS/fix; frame_id
#     gps, tf_prefix '' (ros-drivers/nmea_navsat_driver@2.0.1:src/libnmea_navsat_driver/driver.py).
echo "[nmea-gps stand-in] ros2 $*"
port=5000
case "${1:-} ${2:-}" in
    "launch /husarion_utils/nmea_navsat.launch.py") form=launch ;;
    "run nmea_navsat_driver") [ "${3:-}" = nmea_socket_driver ] || { echo "no executable ${3:-}" >&2; exit 1; }; form=run ;;
    *) echo "[nmea-gps stand-in] unknown command: ros2 $*" >&2; exit 1 ;;
esac
ns=${ROBOT_NAMESPACE:-} dev=gps rns=
for a in "$@"; do
    case "$a" in
        port:=*) port=${a#port:=} ;;
        robot_namespace:=*) ns=${a#robot_namespace:=} ;;
        device_namespace:=*) dev=${a#device_namespace:=} ;;
        __ns:=*) rns=${a#__ns:=} ;;
    esac
done
if [ "$form" = launch ]; then
    ns=${ns#/}; ns=${ns%/}
    topic=${ns:+/$ns}/$dev/fix frame=${ns:+$ns/}${ns:+/}$dev
else
    rns=${rns#/}; rns=${rns%/}
    topic=${rns:+/$rns}/fix frame=gps
fi
exec /usr/bin/nmea-listen "$port" "$topic" "$frame"
