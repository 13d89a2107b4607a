#!/bin/sh
# PID 1 of one simulated robot of the panther-ops test lab (tests/lab).
#
# Started by the lab as
#   ip netns exec NS unshare --mount --uts --pid --fork --propagation private robot-init.sh DIR NAME
# so it runs in the robot's own network, mount, UTS and PID namespaces. It builds the robot's
# view of the file system (per-robot /etc files, /home, /run, /var/log, ... bind-mounted from
# DIR), puts the power-off stand-ins in place, writes DIR/ready and then only reaps orphans.
# It ignores SIGTERM/SIGINT/SIGHUP: the lab ends a robot with SIGKILL from the root
# namespace, which ends every process of the robot's PID namespace with it.
set -eu
DIR=$1
NAME=$2
trap '' TERM INT HUP

mount -t proc proc /proc
hostname "$NAME"

# `ip netns exec` mounted a fresh /sys without the cgroup hierarchies: mount the host's
# hierarchies again (the lab wrote them to DIR/cgroups as "fstype options subdir").
# Only robots with a dockerd get them (the file is empty otherwise).
if [ -s "$DIR/cgroups" ]; then
    mount -t tmpfs -o mode=755 cgroup /sys/fs/cgroup
    (cd /sys/fs/cgroup && cut -d' ' -f3 "$DIR/cgroups" | xargs mkdir -p)
    while read -r fstype opts sub; do
        mount -t "$fstype" -o "$opts" cgroup "/sys/fs/cgroup/$sub"
    done < "$DIR/cgroups"
fi

# User computers with the snap stand-in (computers.py, `webui=True`): /usr/local and /var seen
# through overlays whose upper layers are in DIR/overlay (snap commands in /usr/local/bin,
# /var/snap and /var/lib/snapd-standin); the host's own directories are never written.
if [ -d "$DIR/overlay" ]; then
    for d in usr/local var; do
        mkdir -p "$DIR/overlay/$d/upper" "$DIR/overlay/$d/work"
        mount -t overlay overlay -o "lowerdir=/$d,upperdir=$DIR/overlay/$d/upper,workdir=$DIR/overlay/$d/work" "/$d"
    done
fi

# Per-robot files and directories. The host's own files are never written.
for f in passwd group shadow hostname hosts; do
    mount --bind "$DIR/etc/$f" "/etc/$f"
done
for d in etc/ssh etc/sudoers.d etc/docker var/log home run tmp; do
    mount --bind "$DIR/$d" "/$d"
done

# Power-off stand-ins. On Debian these are symlinks to systemctl; a bind mount over a
# symlink lands on its target, so the stand-in also covers systemctl in this robot only.
done_targets=" "
: > "$DIR/standin-targets"
for p in /sbin/shutdown /sbin/poweroff /sbin/reboot /sbin/halt; do
    [ -e "$p" ] || continue
    t=$(readlink -f "$p")
    case "$done_targets" in
        *" $t "*) ;;
        *)
            mount --bind "$DIR/poweroff-standin" "$t"
            done_targets="$done_targets$t "
            ;;
    esac
    echo "$p $t" >> "$DIR/standin-targets"
done

echo ready > "$DIR/ready"

# Reap orphans (processes the lab starts with nsenter are re-parented to us).
while :; do
    sleep 3600 &
    wait $! || :
done
