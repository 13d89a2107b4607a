#!/bin/sh
# `ros2` stand-in of the panther-ops test lab image (tests/lab). NOT ROS 2.
#
# Records its arguments (stdout, so `docker logs` shows them, and /var/log/ros2-standin.log
# in the container). `ros2 launch` / `ros2 run` keep running like the driver and end at once
# on SIGINT/SIGTERM. Like the real launch, it fails (exit 1) when an argument `*_path:=` or
# `*_file:=` names an absolute path that does not exist in the container; values such as
# `$(find pkg)/...` or empty ones are accepted.
LOG=/var/log/ros2-standin.log
echo "[ros2-standin] ros2 $*"
echo "$(date +%s) ros2 $*" >> "$LOG"
case "${1:-}" in
    launch | run) ;;
    pkg)
        if [ "${2:-}" = prefix ] && [ -n "${3:-}" ]; then
            echo "/opt/ros/humble"
        fi
        exit 0
        ;;
    *) exit 0 ;;
esac
missing=0
for a in "$@"; do
    case "$a" in
        *:=*) ;;
        *) continue ;;
    esac
    key=${a%%:=*}
    val=${a#*:=}
    case "$key" in
        *_path | *_file) ;;
        *) continue ;;
    esac
    case "$val" in
        /*)
            if [ ! -e "$val" ]; then
                echo "[ERROR] [launch]: Caught exception in launch (see debug for traceback): file not found: '$val' (launch argument '$key')" >&2
                missing=1
            fi
            ;;
    esac
done
if [ "$missing" != 0 ]; then
    echo "$(date +%s) exit 1: missing file" >> "$LOG"
    exit 1
fi
echo "[INFO] [launch]: All log files can be found below /root/.ros/log"
echo "[ros2-standin] running (stand-in of the driver)"
child=
stop() {
    echo "[ros2-standin] signal received, shutting down"
    [ -n "$child" ] && kill "$child" 2>/dev/null
    exit 0
}
trap stop INT TERM
while :; do
    sleep 3600 &
    child=$!
    wait "$child"
done
