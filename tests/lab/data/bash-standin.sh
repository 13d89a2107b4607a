#!/bin/sh
# `bash` stand-in of the panther-ops test lab image (tests/lab). NOT bash: busybox has none.
#
# husarion/panther-docker@2.0.4 and @2.1.1:demo/compose.minimal-setup.yaml run the gamepad as
# `bash -c "ros2 launch joy2twist ... joy2twist_params_file:=$(ros2 pkg prefix joy2twist)/..."`,
# which needs only what a POSIX shell does (-c, $(...)): busybox sh runs it.
exec /bin/busybox sh "$@"
