"""A script run inside the robot's running driver container: one command per robot, one round trip.

Used by every feature that asks the driver's ROS 2 graph with the ROS 2 CLI of the driver's
image (`estop`, `teleop`, `gps status`): the robot runs :data:`ROBOT_SCRIPT`, which makes
an exec in the driver container with the docker engine's API on its socket (what
`docker exec` sends) and starts it; the container runs ``/ros_entrypoint.sh sh -c SCRIPT
sh ARGS...`` (the image's entrypoint sources ROS first). Nothing is read before: the
container is found by name (``husarion_ugv_ros`` from 2.2, ``panther_ros`` up to 2.1; the
name of the stack whose environment file the OS wrote is asked for first), else by its
compose service label.

The container script prints sections (:mod:`exec_output`): ``@@ns <namespace>``, then per
action ``@@<action>``, its output, ``@@exit <status>``. :data:`NAMESPACE_SH` is the part
every script starts with: the namespace it was given, else the driver's own (the launch
argument ``namespace:=`` of the container's main process (2.0), else its
``ROBOT_NAMESPACE``: compose.yaml's environment (2.1), the env_file (2.2)).
"""

from __future__ import annotations

import json
from collections.abc import Sequence

from panther_ops.core.containers.exec_output import Answers, container_of, docker_stream, split
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.stack import DRIVER_ENV_FILES, DRIVER_SERVICES
from panther_ops.errors import RemoteStateError
from panther_ops.transport.base import Command

DRIVERS = tuple(zip(DRIVER_SERVICES, DRIVER_ENV_FILES, strict=True))
"""The driver's container and compose service name (as compose.yaml's) and the environment
file the Built-in Computer's OS writes for that stack (2.2+, up to 2.1)."""

#: On the robot: an exec in the running driver container (named husarion_ugv_ros or
#: panther_ros, else the container of that compose service), made with the docker engine's
#: API on its socket (what `docker exec` sends, without starting the docker CLI twice per
#: robot). $1 the exec's JSON (the container script and its arguments), then pairs of a
#: name and its stack's environment file (:data:`DRIVERS`).
#: Few processes (the shell, then curl twice: the exec made, then started in its place): the
#: name whose environment file exists is asked for first (the other only when it has no
#: container: one more curl, and the engine logs the miss), the answers are read with the
#: shell's own expansions; only when neither name has a running container is the compose
#: service looked up. The output is the engine's multiplexed stream (8-byte frame headers),
#: or its error.
ROBOT_SCRIPT = r"""body=$1; shift
sock=/var/run/docker.sock
case "${DOCKER_HOST:-}" in unix://*) sock=${DOCKER_HOST#unix://} ;; esac
likely= other=
while [ $# -ge 2 ]; do
    if [ -e "$2" ]; then likely="$likely $1"; else other="$other $1"; fi
    shift 2
done
id= why=
exec_in() {  # $1 a container: id set when the engine made the exec, else its words kept in why
    out=$(curl -sS --unix-socket "$sock" -H 'Content-Type: application/json' -d "$body" \
        "http://docker/containers/$1/exec") || exit 4
    case $out in
        *'"Id":"'*) id=${out#*'"Id":"'}; id=${id%%'"'*} ;;
        *"No such container"*) return 1 ;;
        *) why="$why $out"; return 1 ;;
    esac
}
for c in $likely $other; do
    exec_in "$c" && break
done
if [ -z "$id" ]; then
    for svc in $likely $other; do
        out=$(curl -sS --unix-socket "$sock" -G \
            --data-urlencode "filters={\"label\":[\"com.docker.compose.service=$svc\"]}" \
            http://docker/containers/json) || exit 4
        case $out in '[{"Id":"'*) ;; *) continue ;; esac
        c=${out#'[{"Id":"'}; c=${c%%'"'*}
        exec_in "$c" && break
    done
fi
if [ -z "$id" ]; then
    echo "no running driver container (named or a compose service$likely$other)${why:+:$why}" >&2
    exit 3
fi
echo "@@container $c" >&2
exec curl -sS --unix-socket "$sock" -H 'Content-Type: application/json' -d '{"Detach":false,"Tty":false}' \
    "http://docker/exec/$id/start"
"""

#: The start of every container script: ``$ns`` the namespace asked for ('' = the driver's
#: own: the launch's ``namespace:=`` argument of the container's main process, else
#: ROBOT_NAMESPACE), normalised; ``$p`` its topic prefix ('' or ``/<ns>``); prints ``@@ns``.
NAMESPACE_SH = r"""if [ -z "$ns" ] && [ -r /proc/1/cmdline ]; then
    set -f
    for w in $(tr '\000' ' ' < /proc/1/cmdline); do
        case $w in namespace:=*) ns=${w#namespace:=} ;; esac
    done
    set +f
fi
[ -n "$ns" ] || ns=${ROBOT_NAMESPACE:-}
ns=${ns#/}; ns=${ns%/}; p=${ns:+/$ns}
echo "@@ns ${p:-/}"
"""


def command(script: str, args: Sequence[str]) -> Command:
    """The one command the robot runs: ``script`` (a container script) with ``args`` in the
    driver container, after its entrypoint (one argv in the exec's JSON: no shell in between)."""
    argv = ["/ros_entrypoint.sh", "sh", "-c", script, "sh", *args]
    body = json.dumps({"AttachStdout": True, "AttachStderr": True, "Cmd": argv}, separators=(",", ":"))
    return Command.sh(ROBOT_SCRIPT, body, *(word for pair in DRIVERS for word in pair))


def ask(ctx: RobotContext, cmd: Command, timeout: float) -> Answers:
    """Run ``cmd`` (from :func:`command`) on the robot and split its sections; the driver
    container that answered is named. RemoteStateError when no section came back (no
    running driver, no engine), with the robot's or the engine's words."""
    res = ctx.transport.run(cmd, timeout=timeout)
    out, err = docker_stream(res.raw_stdout)
    got = split(out)
    stderr = "\n".join(ln for ln in res.stderr.splitlines() if not ln.startswith("@@container "))
    if not got.sections:
        why = (stderr or err or out).strip()[-300:]
        raise RemoteStateError(f"the driver did not answer (exit {res.exit_status}): {why}",
                               hint="panther-ops driver status")
    return Answers(got.namespace, got.sections, container_of(res.stderr))
