#!/bin/sh
# Power-off stand-in of the panther-ops test lab (tests/lab). NOT the real program.
#
# Bind-mounted over /sbin/shutdown, /sbin/poweroff, /sbin/reboot (and so over systemctl)
# inside one simulated robot's mount namespace. It records the call in
# /var/log/power-standin.log (one JSON object per line) and then takes the robot's network
# interfaces down, which is what "powered off" looks like from the network: the robot answers
# neither ping nor ssh any more. It never calls reboot(2) or a real power-off. `reboot`
# brings the interfaces back after $LAB_REBOOT_SECONDS (default 5) seconds.
LOG=/var/log/power-standin.log
me=${0##*/}
action=
case "$me" in
    shutdown)
        action=poweroff
        for a in "$@"; do
            case "$a" in
                -r | --reboot) action=reboot ;;
                -H | --halt) action=halt ;;
                -c) action=cancel ;;
                -k) action=wall ;;
            esac
        done
        ;;
    poweroff | halt | reboot) action=$me ;;
    *)
        for a in "$@"; do
            case "$a" in
                poweroff | halt | reboot | kexec) action=$a ;;
            esac
        done
        if [ -z "$action" ]; then
            echo "System has not been booted with systemd as init system (PID 1). Can't operate." >&2
            echo "Failed to connect to bus: Host is down" >&2
            exit 1
        fi
        ;;
esac
esc() { printf '%s' "$1" | sed 's/\\/\\\\/g; s/"/\\"/g'; }
uid=$(id -u)
printf '{"time": %s, "user": "%s", "uid": %s, "sudo_user": "%s", "argv0": "%s", "args": "%s", "action": "%s"}\n' \
    "$(date +%s.%N)" "$(id -un)" "$uid" "${SUDO_USER:-}" "$(esc "$0")" "$(esc "$*")" "$action" >> "$LOG" 2>/dev/null
if [ "$uid" != 0 ]; then
    echo "Failed to $action system via logind: Interactive authentication required." >&2
    exit 1
fi
case "$action" in
    cancel | wall) exit 0 ;;
esac
# Answer first (as a real shutdown does), then drop off the network.
links_down='for l in /sys/class/net/*; do n=${l##*/}; [ "$n" = lo ] || ip link set "$n" down; done'
links_up='for l in /sys/class/net/*; do n=${l##*/}; ip link set "$n" up; done'
if [ "$action" = reboot ]; then
    setsid sh -c "sleep 0.3; $links_down; sleep ${LAB_REBOOT_SECONDS:-5}; $links_up" </dev/null >/dev/null 2>&1 &
else
    setsid sh -c "sleep 0.3; $links_down" </dev/null >/dev/null 2>&1 &
fi
exit 0
