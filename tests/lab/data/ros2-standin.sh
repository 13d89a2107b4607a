#!/bin/sh
# `ros2` stand-in of the panther-ops test lab image (tests/lab). NOT ROS 2.
#
# Records its arguments (stdout, so `docker logs` shows them, and /var/log/ros2-standin.log
# in the container). `ros2 launch` / `ros2 run` keep running like the driver and end at once
# on SIGINT/SIGTERM. Like the real launch, it fails (exit 1) when an argument `*_path:=` or
# `*_file:=` names an absolute path that does not exist in the container; values such as
# `$(find pkg)/...` or empty ones are accepted.
#
# The driver's E-stop API (panther_ros ROS_API.md), answered in the driver's namespace (the
# launch's `namespace:=` argument of PID 1, else $ROBOT_NAMESPACE) with the state in a file
# of the container (/var/lib/ros2-standin/e_stop; the driver starts with the E-stop
# triggered, as the real one does):
#   ros2 topic echo --once <ns>/hardware/e_stop            -> `data: true|false` then `---`
#   ros2 service call <ns>/hardware/e_stop_trigger std_srvs/srv/Trigger
#   ros2 service call <ns>/hardware/e_stop_reset std_srvs/srv/Trigger
#       (refused, like the real driver, while something publishes on <ns>/cmd_vel)
#   ros2 topic info -v <ns>/cmd_vel                         -> its publishers and subscriber
#   ros2 topic pub [--rate R] <ns>/cmd_vel geometry_msgs/msg/Twist '{...}'
#       a publisher (node `_ros2cli_<pid>`) registered while it runs (tests start it with
#       `docker exec -d` and stop it with a signal); a killed one no longer counts.
#   ros2 run teleop_twist_keyboard teleop_twist_keyboard --ros-args -p repeat_rate:=R
#       -r cmd_vel:=<ns>/cmd_vel
#       the keyboard teleoperation on its terminal: publisher `teleop_twist_keyboard` while it
#       runs; i , j l u o m . move, k (any other key) stops; the current Twist "published"
#       every 1/R s on schedule (a key press changes it at once) as a line `<uptime> <linear.x> <angular.z>`
#       appended to /var/lib/ros2-standin/cmd_vel.log; Ctrl-C ends it.
# An E-stop topic or service of another namespace is never answered: like the real CLI, the
# command waits (`waiting for service to become available...`) until it is killed.
#
# The GPS fix (sensor_msgs/msg/NavSatFix), published by the lab's NMEA driver stand-in
# (nmea-listen: in the nmea-gps service's container, or started by this driver's launch):
#   ros2 topic echo --once <topic> sensor_msgs/msg/NavSatFix
#       -> the next fix published on <topic>, as the real CLI prints it, then `---`; a topic
#       nobody publishes (no listener, another namespace, no NMEA arriving) waits until killed.
#   The stand-in's stand-in for DDS discovery: nmea-listen serves each fix it publishes, with
#   its topic, to the clients waiting on 127.0.0.1:11811 (both containers run with
#   network_mode host: the robot's network namespace); this script waits there with busybox nc.
# `ros2 launch ... launch_nmea_gps:=True` (panther_ros 2.1.1, husarion_ugv 2.2) also runs the
# NMEA driver as the real bringup does (localization.launch.py includes nmea_navsat.launch.py):
# nmea-listen on the parameters file's port (nmea_params_path:= (2.2) or params_file:= (2.1.1),
# else the package's, port 5000), publishing <ns>/<device_namespace>/fix (device_namespace:=,
# 2.1.1 only, default gps) with frame_id <ns>/gps (tf_prefix = the namespace)
# (husarion_ugv_ros@2.1.1:panther_localization/launch/nmea_navsat.launch.py and
# config/nmea_navsat_params.yaml; @2.2.2:husarion_ugv_localization/launch/nmea_navsat.launch.py
# and config/nmea_navsat.yaml).
LOG=/var/log/ros2-standin.log
STATE=/var/lib/ros2-standin
echo "ros2 $*" >> "$LOG"

driver_ns() {  # few processes: the E-stop trigger of a whole fleet is timed in the lab
    ns=
    if [ -r /proc/1/cmdline ]; then
        while read -r w; do
            case $w in namespace:=*) ns=${w#namespace:=}; break ;; esac
        done <<EOF
$(tr '\000' '\n' < /proc/1/cmdline)
EOF
    fi
    [ -n "$ns" ] || ns=${ROBOT_NAMESPACE:-}
    ns=${ns#/}
    ns=${ns%/}
    P=${ns:+/$ns}
}

wait_forever() {
    trap 'exit 130' INT TERM
    while :; do sleep 1; done
}

echo_fix() {  # $1 the topic: the next NavSatFix nmea-listen publishes on it, else wait until killed
    f=/tmp/ros2-standin-fix.$$
    nc 127.0.0.1 11811 < /dev/null > "$f" 2>/dev/null &
    nc=$!
    trap 'kill "$nc" 2>/dev/null; rm -f "$f"; exit 130' INT TERM
    wait "$nc"
    if [ "$(head -n 1 "$f")" = "$1" ]; then
        tail -n +2 "$f"
        rm -f "$f"
        exit 0
    fi
    rm -f "$f"
    wait_forever
}

live_publishers() {
    [ -d "$STATE/cmd_vel" ] || return 0
    for f in "$STATE"/cmd_vel/*; do
        [ -f "$f" ] || continue
        pid=$(cat "$f")
        if kill -0 "$pid" 2>/dev/null; then
            basename "$f"
        else
            rm -f "$f"
        fi
    done
}

e_stop_state() {
    state=true
    [ -f "$STATE/e_stop" ] && read -r state < "$STATE/e_stop"
    echo "$state"
}

set_e_stop() {
    [ -d "$STATE" ] || mkdir -p "$STATE"
    echo "$1" > "$STATE/e_stop"
}

respond() {
    echo "requester: making request: std_srvs.srv.Trigger_Request()"
    echo
    echo "response:"
    echo "std_srvs.srv.Trigger_Response(success=$1, message='$2')"
    echo
}

driver_ns
case "${1:-}" in
    topic)
        topic=  # the first absolute name: the topic
        for a in "$@"; do
            case "$a" in /*) topic=$a; break ;; esac
        done
        case "${2:-}" in
            echo)
                case " $* " in *" sensor_msgs/msg/NavSatFix "*) echo_fix "$topic" ;; esac
                if [ "$topic" = "$P/hardware/e_stop" ]; then
                    echo "data: $(e_stop_state)"
                    echo "---"
                    exit 0
                fi
                case "$topic" in */hardware/e_stop) wait_forever ;; esac
                exit 0
                ;;
            info)
                if [ "$topic" != "$P/cmd_vel" ]; then
                    echo "Unknown topic '$topic'" >&2
                    exit 1
                fi
                pubs=$(live_publishers)
                n=0
                for p in $pubs; do n=$((n + 1)); done
                echo "Type: geometry_msgs/msg/Twist"
                echo
                echo "Publisher count: $n"
                echo
                for p in $pubs; do
                    printf 'Node name: %s\nNode namespace: /\nTopic type: geometry_msgs/msg/Twist\nEndpoint type: PUBLISHER\n' "$p"
                    printf 'GID: 01.0f.stand.in\nQoS profile:\n  Reliability: RELIABLE\n  History (Depth): UNKNOWN\n'
                    printf '  Durability: VOLATILE\n  Lifespan: Infinite\n  Deadline: Infinite\n  Liveliness: AUTOMATIC\n'
                    printf '  Liveliness lease duration: Infinite\n\n'
                done
                echo "Subscription count: 1"
                echo
                printf 'Node name: drive_controller\nNode namespace: %s\nTopic type: geometry_msgs/msg/Twist\n' "${P:-/}"
                printf 'Endpoint type: SUBSCRIPTION\nGID: 01.0f.stand.in\n\n'
                exit 0
                ;;
            pub)
                if [ "$topic" = "$P/cmd_vel" ]; then
                    mkdir -p "$STATE/cmd_vel"
                    node="_ros2cli_$$"
                    echo "$$" > "$STATE/cmd_vel/$node"
                    trap 'rm -f "$STATE/cmd_vel/$node"; exit 0' INT TERM
                    echo "publisher: beginning loop"
                    while :; do sleep 1; done
                fi
                exit 0
                ;;
        esac
        exit 0
        ;;
    service)
        if [ "${2:-}" = call ]; then
            echo "waiting for service to become available..." >&2
            case "${3:-}" in
                "$P/hardware/e_stop_trigger")
                    set_e_stop true
                    respond True "E-stop triggered successfully"
                    exit 0
                    ;;
                "$P/hardware/e_stop_reset")
                    if [ "$(e_stop_state)" = false ]; then
                        respond True "E-stop is not active, reset is not needed"
                    elif [ -n "$(live_publishers)" ]; then
                        respond False "E-stop reset failed, some messages are published on the cmd_vel topic"
                    else
                        set_e_stop false
                        respond True "E-stop reset successful"
                    fi
                    exit 0
                    ;;
                */hardware/e_stop_trigger | */hardware/e_stop_reset) wait_forever ;;
            esac
        fi
        exit 0
        ;;
esac
if [ "${1:-}" = run ] && [ "${2:-}" = teleop_twist_keyboard ]; then
    rate=0 topic=/cmd_vel
    for a in "$@"; do
        case $a in
            repeat_rate:=*) rate=${a#repeat_rate:=} ;;
            cmd_vel:=*) topic=${a#cmd_vel:=} ;;
        esac
    done
    if [ "$topic" = "$P/cmd_vel" ]; then
        mkdir -p "$STATE/cmd_vel"
        echo "$$" > "$STATE/cmd_vel/teleop_twist_keyboard"
    fi
    old=$(stty -g 2>/dev/null || true)
    stty -icanon -echo 2>/dev/null || true
    trap 'rm -f "$STATE/cmd_vel/teleop_twist_keyboard"; [ -n "$old" ] && stty "$old" 2>/dev/null; exit 0' INT TERM HUP
    echo "Reading from the keyboard and Publishing to Twist! (lab stand-in; repeat_rate $rate)"
    echo "i , j l u o m . move, k stops; CTRL-C to quit"
    # publish every period (centiseconds, from /proc/uptime), keeping to the schedule: a key
    # press does not delay the next message
    period=$(awk "BEGIN { if ($rate > 0) printf \"%d\", 100 / $rate; else print 360000 }")
    [ "$period" -gt 0 ] || period=1
    read -r up _ < /proc/uptime
    now=$(( ${up%.*} * 100 + 10#${up#*.} ))
    next=$((now + period))
    x=0 z=0
    while :; do
        read -r up _ < /proc/uptime
        now=$(( ${up%.*} * 100 + 10#${up#*.} ))
        left=$((next - now))
        key=
        if [ "$left" -gt 0 ]; then
            read -t "$(printf '%d.%02d' $((left / 100)) $((left % 100)))" -n 1 key
        fi
        case $key in
            i) x=0.5 z=0 ;; ,) x=-0.5 z=0 ;; j) x=0 z=1.0 ;; l) x=0 z=-1.0 ;;
            u) x=0.5 z=1.0 ;; o) x=0.5 z=-1.0 ;; m) x=-0.5 z=-1.0 ;; .) x=-0.5 z=1.0 ;;
            "") ;;
            *) x=0 z=0 ;;
        esac
        [ -n "$key" ] && continue  # a key: applied now, published on schedule
        next=$((next + period))
        if [ "$topic" = "$P/cmd_vel" ]; then
            read -r up _ < /proc/uptime
            echo "$up $x $z" >> "$STATE/cmd_vel.log"
        fi
    done
fi
echo "[ros2-standin] ros2 $*"
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
gps= params= dev=gps nmea=
for a in "$@"; do
    case "$a" in
        launch_nmea_gps:=*) gps=$(echo "${a#*:=}" | tr 'A-Z' 'a-z') ;;
        nmea_params_path:=* | params_file:=*) params=${a#*:=} ;;
        device_namespace:=*) dev=${a#*:=} ;;
    esac
done
case " $* " in *" husarion_ugv_bringup "*) dev=gps ;; esac  # 2.2 fixes it: no argument
if [ "$gps" = true ] || [ "$gps" = 1 ]; then
    port=
    [ -f "$params" ] && port=$(sed -n 's/^ *port: *\([0-9][0-9]*\).*/\1/p' "$params" | head -n 1)
    /usr/bin/nmea-listen "${port:-5000}" "$P/$dev/fix" "${P#/}${P:+/}gps" &
    nmea=$!
fi
child=
stop() {
    echo "[ros2-standin] signal received, shutting down"
    [ -n "$child" ] && kill "$child" 2>/dev/null
    [ -n "$nmea" ] && kill "$nmea" 2>/dev/null
    exit 0
}
trap stop INT TERM
while :; do
    sleep 3600 &
    child=$!
    wait "$child"
done
