#!/bin/sh
# `ros2` stand-in of the panther-ops test lab image (tests/lab). NOT ROS 2.
#
# Records its arguments (stdout, so `docker logs` shows them, and /var/log/ros2-standin.log
# in the container). `ros2 launch` / `ros2 run` keep running like the driver and end at once
# on SIGINT/SIGTERM. Like the real launch, it fails (exit 1) when an argument `*_path:=` or
# `*_file:=` names an absolute path that does not exist in the container, its error on stdout
# with the launch's other log lines; values such as `$(find pkg)/...` or empty ones are accepted.
#
# The driver's E-stop API (panther_ros ROS_API.md), answered in the driver's namespace (the
# launch's `namespace:=` argument of PID 1, else $ROBOT_NAMESPACE) with the state in a file
# of the container (/var/lib/ros2-standin/e_stop; the driver starts with the E-stop
# triggered, as the real one does):
#   ros2 topic echo --once <ns>/hardware/e_stop            -> `data: true|false` then `---`
#   ros2 service call <ns>/hardware/e_stop_trigger std_srvs/srv/Trigger
#   ros2 service call <ns>/hardware/e_stop_reset std_srvs/srv/Trigger
#       (refused, like the real driver, while the last velocity command is not zero: below)
#   ros2 topic info -v <ns>/cmd_vel                         -> its publishers and subscriber
#   ros2 topic pub [--rate R] <ns>/cmd_vel geometry_msgs/msg/Twist '{...}'
#       a publisher (node `_ros2cli_<pid>`) registered while it runs (tests start it with
#       `docker exec -d` and stop it with a signal); a killed one no longer counts.
#   ros2 run teleop_twist_keyboard ...  -> `Package 'teleop_twist_keyboard' not found`, exit 1:
#       the real images do not have it (FROM husarnet/ros:humble-ros-core plus what rosdep
#       installs for the bringup; no package.xml of panther_ros 2.0.4/2.1.1 or husarion_ugv_ros
#       2.2.0/2.2.2 depends on it). A publisher made with rclpy (the lab's Python image has an
#       rclpy stand-in, data/rclpy-standin) registers in and logs to the same state as
#       `ros2 topic pub` here: /var/lib/ros2-standin/cmd_vel/<node>, cmd_vel.log.
#
# The lights controller's SetLEDAnimation service of the image's release (/version.txt, as the
# real Dockerfiles write it: the panther / husarion_ugv package version), in the driver's
# namespace: 2.0.x `lights/controller/set/animation` with panther_msgs/srv/SetLEDAnimation
# (husarion/husarion_ugv_ros@2.0.4:panther_lights/src/controller_node.cpp), 2.1.x
# `lights/set_animation` with panther_msgs (@2.1.1:panther_lights/src/lights_controller_node.cpp),
# 2.2.x `lights/set_animation` with husarion_ugv_msgs (@2.2.2:husarion_ugv_lights/src/
# lights_controller_node.cpp), 2.3.x the same as 2.2 (@2.3.2:husarion_ugv_lights/src/lights_controller_node.cpp).
# The answer is the controller's: success=True for an animation it
# has -- the release's default IDs (2.0/2.1 led_config.yaml: 0-7, 9; 2.2, 2.3.0, 2.3.1 panther_animations.yaml:
# 0-15; 2.3.2: 0-17, with 16 GOAL_FAILED and 17 FLOOD_LIGHT) and the `id:`s of the user animations file the driver's launch arguments name
# (`user_led_animations_file:=` 2.0/2.1; `user_led_animations_path:=`, else
# <common_dir_path>/husarion_ugv_lights/config/user_animations.yaml, 2.2) -- else success=False,
# "No animation with ID: N".
# An E-stop or lights service of another namespace, name or type is never answered: like the
# real CLI, the command waits (`waiting for service to become available...`) until it is killed.
# `ros2 pkg prefix <pkg>` prints the install prefix and nothing else (ros2/ros2cli@9fce6a08381b:
# ros2pkg/ros2pkg/verb/prefix.py prints get_prefix_path): /ros2_ws/install/<pkg> for a package
# colcon installed in the image's workspace (isolated install: joy2twist, husarion/joy2twist@2f8ad45:
# Dockerfile), else /opt/ros/$ROS_DISTRO (humble; jazzy on husarion_ugv 2.3): the gamepad's
# `joy2twist_params_file:=$(ros2 pkg prefix joy2twist)/share/...` names a file of the image.
# On 2.3.2 <ns>/cmd_vel is the twist mux's input of priority 1 and carries geometry_msgs/msg/TwistStamped,
# subscribed by twist_mux_controller (husarion_ugv_ros@2.3.2:ROS_API.md, husarion_ugv_controller/config/
# WH01_controller.yaml); `ros2 topic info -v` says so.
# The mux's other inputs are <ns>/manual/cmd_vel (priority 100) and <ns>/autonomous/cmd_vel (10), each
# with a 0.2 s timeout (same file): `ros2 topic pub` registers on them too (/var/lib/ros2-standin/
# manual_cmd_vel/<node>, autonomous_cmd_vel/<node>), and `topic info -v` lists each input's publishers.
# The 2.3.2 E-stop reset rule: the driver refuses a reset while the last velocity commands are not zero
# (husarion_ugv_ros@2.3.2:husarion_ugv_hardware_interfaces/src/robot_system/system_e_stop.cpp
# EStop::ResetEStop, ZeroVelocityCheck = ugv_system.cpp AreVelocityCommandsNearZero), with that file's
# message; the last command is the mux's: the highest-priority input with a message within its timeout,
# else zero (husarion/husarion_controllers:twist_mux_controller/src/twist_mux_controller.cpp
# update_reference_from_subscribers). A running `ros2 topic pub --rate R` (R >= 5) never times out: the
# active input is the highest one with a live publisher, and its velocity is the one that publisher sends
# (its message's x/y/z, kept in velocity/<node>). Publishers of zero velocity do not block the reset. On
# success the real service answers success=True with an empty message (system_ros_interface.cpp
# CallbackWrapper), and it does not look at the E-stop's state first (ResetEStop resets the GPIO anyway).
# The E-stop reset rule up to 2.2 is the same check behind the diff drive controller: the driver refuses
# while the last velocity commands are not zero (panther_ros@2.1.1:panther_hardware_interfaces/src/
# panther_system/panther_system_e_stop.cpp, @2.0.4: src/panther_system_e_stop.cpp, EStopPTH12X::ResetEStop
# and EStopPTH10X::ResetEStop, the class by the driver's PANTHER_ROBOT_VERSION, default 1.0, PTH12X from 1.2:
# panther_system.cpp; @2.0.0: panther_system.cpp PantherSystem::ResetEStop, the PTH10X message;
# husarion_ugv_ros@2.2.2:husarion_ugv_hardware_interfaces/src/robot_system/system_e_stop.cpp EStop::ResetEStop,
# the PTH12X message), each with its file's message. The last command is the controller's: the last
# message on <ns>/cmd_vel if it came within cmd_vel_timeout, else zero (0.5 s: panther_ros@2.1.1 and
# @2.0.4:panther_controller/config/WH01_controller.yaml; 0.2 s: husarion_ugv_ros@2.2.2:husarion_ugv_controller/
# config/WH01_controller.yaml). A publisher started with `--rate R` (default 1, as ros2 topic pub's) sends
# at its start and every 1/R s after (its start time from /proc/uptime, the message's x/y/z zero or not,
# kept in velocity/<node> as `<0|1> <R> <start>`; the rclpy stand-in's publishers write `<0|1> 0 <time>` at
# each message): the newest message of the running publishers is the last command (a stopped
# one counts no more at once, where the real command lapses within the timeout). A publisher of
# zeros never blocks the reset. Success: success=True with an empty message (CallbackWrapper: only an
# exception sets it; the "E-stop is not active" line of GPIOControllerPTH12X::EStopReset goes to stdout).
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

live_publishers() {  # $1 the registry (default cmd_vel; 2.3.2 also manual_cmd_vel, autonomous_cmd_vel)
    d=$STATE/${1:-cmd_vel}
    [ -d "$d" ] || return 0
    for f in "$d"/*; do
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

mux_input() {  # 2.3.2: the registry of the twist mux input topic $1, else nothing
    [ "$(release)" = 2.3.2 ] || return 0
    case $1 in
        "$P/manual/cmd_vel") echo manual_cmd_vel ;;
        "$P/autonomous/cmd_vel") echo autonomous_cmd_vel ;;
        "$P/cmd_vel") echo cmd_vel ;;
    esac
}

nonzero() {  # 1 when a velocity (x, y or z) in the message $1 is not zero, else 0
    printf '%s\n' "$1" | grep -o '[xyz]: *[-+0-9.eE]*' | awk -F': *' '$2 + 0 != 0 { n = 1 } END { print n + 0 }'
}

mux_velocity_nonzero() {  # 2.3.2: whether the mux's last command is not zero (its highest live input's)
    for reg in manual_cmd_vel autonomous_cmd_vel cmd_vel; do
        pubs=$(live_publishers "$reg")
        [ -n "$pubs" ] || continue
        for p in $pubs; do
            v=0
            [ -f "$STATE/velocity/$p" ] && read -r v _ < "$STATE/velocity/$p"
            [ "$v" = 1 ] && return 0
        done
        return 1
    done
    return 1
}

cmd_vel_timeout() {  # up to 2.2: the diff drive controller's cmd_vel_timeout of the release (WH01_controller.yaml)
    case $(release) in
        2.0.* | 2.1.*) echo 0.5 ;;
        *) echo 0.2 ;;
    esac
}

last_velocity_nonzero() {  # up to 2.2: whether the controller's last command is not zero: the newest
    # message of the live publishers on cmd_vel, within cmd_vel_timeout, else zero
    now= _u=
    read -r now _u < /proc/uptime
    for p in $(live_publishers cmd_vel); do
        [ -f "$STATE/velocity/$p" ] && echo "$(cat "$STATE/velocity/$p")"
    done | awk -v now="$now" -v timeout="$(cmd_vel_timeout)" '
        NF >= 3 { age = now - $3; if (age < 0) age = 0
                  if ($2 > 0) { period = 1 / $2; age -= int(age / period) * period }  # since its last message
                  if (!seen || age < newest) { seen = 1; newest = age; v = $1 } }
        END { exit !(seen && newest <= timeout && v == 1) }'
}

reset_refusal() {  # the release's message of a reset refused for a non-zero velocity command
    case $(release) in
        2.0.0) pth10x=1 ;;
        2.0.* | 2.1.*)
            version=$(tr '\000' '\n' < /proc/1/environ 2>/dev/null | sed -n 's/^PANTHER_ROBOT_VERSION=//p' | head -n 1)
            pth10x=$(awk -v v="${version:-1.0}" 'BEGIN { print (v + 0 < 1.2) ? 1 : 0 }') ;;
        *) pth10x=0 ;;
    esac
    if [ "$pth10x" = 1 ]; then
        echo "Can't reset E-stop - last velocity commands are different than zero. Make sure that your controller sends zero commands before trying to reset E-stop."
    else
        echo "Cannot reset the E-stop: the last velocity commands are not zero. Ensure that the controller is sending zero velocity commands or not sending any velocity commands before attempting to reset the E-stop."
    fi
}

set_e_stop() {
    [ -d "$STATE" ] || mkdir -p "$STATE"
    echo "$1" > "$STATE/e_stop"
}

launch_arg() {  # the value of the driver's launch argument $1:= (PID 1's command line), else ""
    [ -r /proc/1/cmdline ] || return 0
    tr '\000' '\n' < /proc/1/cmdline | sed -n "s/^$1:=//p" | head -n 1
}

lights_service() {  # "<name> <msgs package>" of the image's release, or nothing
    v=
    [ -r /version.txt ] && read -r v < /version.txt
    case $v in
        2.0.*) echo "lights/controller/set/animation panther_msgs" ;;
        2.1.*) echo "lights/set_animation panther_msgs" ;;
        2.2.* | 2.3.*) echo "lights/set_animation husarion_ugv_msgs" ;;
    esac
}

release() {  # the image's release (/version.txt)
    v=
    [ -r /version.txt ] && read -r v < /version.txt
    echo "$v"
}

set_animation() {  # $1 msgs package, $2 the request (YAML)
    id=$(printf '%s' "$2" | sed -n 's/.*id: *\([0-9][0-9]*\).*/\1/p')
    rep=False
    case $2 in *"repeating: true"*) rep=True ;; esac
    known="0 1 2 3 4 5 6 7 9"
    user=$(launch_arg user_led_animations_file)
    if [ "$1" = husarion_ugv_msgs ]; then
        known="0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15"
        [ "$(release)" = 2.3.2 ] && known="$known 16 17"
        user=$(launch_arg user_led_animations_path)
        common=$(launch_arg common_dir_path)
        [ -z "$user" ] && [ -n "$common" ] && user=$common/husarion_ugv_lights/config/user_animations.yaml
    fi
    [ -n "$user" ] && [ -r "$user" ] && known="$known $(sed -n 's/^[ -]*id: *\([0-9][0-9]*\).*/\1/p' "$user")"
    echo "requester: making request: $1.srv.SetLEDAnimation_Request(animation=$1.msg.LEDAnimation(id=$id, param=''), repeating=$rep)"
    echo
    echo "response:"
    for k in $known; do
        if [ "$k" = "$id" ]; then
            echo "$1.srv.SetLEDAnimation_Response(success=True, message='')"
            echo
            return 0
        fi
    done
    echo "$1.srv.SetLEDAnimation_Response(success=False, message='No animation with ID: $id')"
    echo
}

respond() {
    echo "requester: making request: std_srvs.srv.Trigger_Request()"
    echo
    echo "response:"
    case $2 in  # as Python's repr prints the string (ros2 service call prints the response's repr)
        *\'*) echo "std_srvs.srv.Trigger_Response(success=$1, message=\"$2\")" ;;
        *) echo "std_srvs.srv.Trigger_Response(success=$1, message='$2')" ;;
    esac
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
                reg=$(mux_input "$topic")
                [ "$topic" = "$P/cmd_vel" ] && reg=cmd_vel
                if [ -z "$reg" ]; then
                    echo "Unknown topic '$topic'" >&2
                    exit 1
                fi
                pubs=$(live_publishers "$reg")
                n=0
                for p in $pubs; do n=$((n + 1)); done
                type=geometry_msgs/msg/Twist sub=drive_controller
                [ "$(release)" = 2.3.2 ] && type=geometry_msgs/msg/TwistStamped sub=twist_mux_controller
                echo "Type: $type"
                echo
                echo "Publisher count: $n"
                echo
                for p in $pubs; do
                    printf 'Node name: %s\nNode namespace: /\nTopic type: %s\nEndpoint type: PUBLISHER\n' "$p" "$type"
                    printf 'GID: 01.0f.stand.in\nQoS profile:\n  Reliability: RELIABLE\n  History (Depth): UNKNOWN\n'
                    printf '  Durability: VOLATILE\n  Lifespan: Infinite\n  Deadline: Infinite\n  Liveliness: AUTOMATIC\n'
                    printf '  Liveliness lease duration: Infinite\n\n'
                done
                echo "Subscription count: 1"
                echo
                printf 'Node name: %s\nNode namespace: %s\nTopic type: %s\n' "$sub" "${P:-/}" "$type"
                printf 'Endpoint type: SUBSCRIPTION\nGID: 01.0f.stand.in\n\n'
                exit 0
                ;;
            pub)
                reg=$(mux_input "$topic")
                [ "$topic" = "$P/cmd_vel" ] && reg=cmd_vel
                if [ -n "$reg" ]; then
                    mkdir -p "$STATE/$reg" "$STATE/velocity"
                    node="_ros2cli_$$"
                    eval "msg=\${$#}"  # the message: the last argument
                    rate=1 prev= start= _u=
                    for a in "$@"; do
                        case $prev in -r | --rate) rate=$a ;; esac
                        case $a in --rate=*) rate=${a#--rate=} ;; esac
                        prev=$a
                    done
                    read -r start _u < /proc/uptime
                    echo "$(nonzero "$msg") $rate $start" > "$STATE/velocity/$node"
                    echo "$$" > "$STATE/$reg/$node"
                    trap 'rm -f "$STATE/$reg/$node" "$STATE/velocity/$node"; exit 0' INT TERM
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
                    # success carries no message: husarion_ugv_ros@2.2.2:husarion_ugv_hardware_interfaces/
                    # src/robot_system/system_ros_interface.cpp (CallbackWrapper sets one only on an exception)
                    respond True ""
                    exit 0
                    ;;
                "$P/hardware/e_stop_reset")
                    if [ "$(release)" = 2.3.2 ]; then
                        if mux_velocity_nonzero; then
                            respond False "Cannot reset the E-stop: the last velocity commands are not zero. Ensure that the controller is sending zero velocity commands or not sending any velocity commands before attempting to reset the E-stop."
                        else
                            set_e_stop false
                            respond True ""
                        fi
                    elif last_velocity_nonzero; then
                        respond False "$(reset_refusal)"
                    else
                        set_e_stop false
                        respond True ""
                    fi
                    exit 0
                    ;;
                */hardware/e_stop_trigger | */hardware/e_stop_reset) wait_forever ;;
                */lights/set_animation | */lights/controller/set/animation)
                    set -- "$@" "" "" ""
                    lights=$(lights_service)
                    if [ -n "$lights" ] && [ "$3" = "$P/${lights%% *}" ] && [ "$4" = "${lights#* }/srv/SetLEDAnimation" ]; then
                        set_animation "${lights#* }" "$5"
                        exit 0
                    fi
                    wait_forever
                    ;;
            esac
        fi
        exit 0
        ;;
esac
if [ "${1:-}" = run ] && [ "${2:-}" = teleop_twist_keyboard ]; then
    echo "Package 'teleop_twist_keyboard' not found" >&2
    exit 1
fi
if [ "${1:-}" = pkg ]; then  # only the prefix on stdout: `$(ros2 pkg prefix joy2twist)/share/...` is a path
    if [ "${2:-}" = prefix ] && [ -n "${3:-}" ]; then
        if [ -d "/ros2_ws/install/$3" ]; then echo "/ros2_ws/install/$3"; else echo "/opt/ros/${ROS_DISTRO:-humble}"; fi
    fi
    exit 0
fi
echo "[ros2-standin] ros2 $*"
case "${1:-}" in
    launch | run) ;;
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
                # on stdout, as the real launch's own log lines (its screen handler is a StreamHandler on
                # sys.stdout: ros2/launch@1.0.7 (Humble) and @3.4.3 (Jazzy): launch/launch/logging/__init__.py, get_screen_handler)
                echo "[ERROR] [launch]: Caught exception in launch (see debug for traceback): file not found: '$val' (launch argument '$key')"
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
