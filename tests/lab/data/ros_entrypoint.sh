#!/bin/sh
# Entrypoint of the panther-ops test lab image (tests/lab): like the real images, export the
# robot's environment from /run/husarion/*.env, then run the command.
for f in /run/husarion/panther_config.env /run/husarion/robot_config.env; do
    if [ -f "$f" ]; then
        set -a
        . "$f"
        set +a
    fi
done
exec "$@"
