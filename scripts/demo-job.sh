#!/usr/bin/env bash
# The README's main job on the embedded demo fleet, in the current directory, with the
# panther-ops given as PO (default: panther-ops on PATH). scripts/demo.sh installs and runs it;
# scripts/wheel-check.sh runs it from a wheel installed in a fresh venv.
set -euo pipefail
PO="${PO:-panther-ops}"
$PO demo init --dest demo-fleet --force
$PO -i demo-fleet inventory list
$PO -i demo-fleet status --all
$PO -i demo-fleet doctor --all
# A configuration change, the manual's "Changing Wheel Type": first the exact diff, then
# applied (backup, atomic write; a demo robot has no docker engine to recreate), then idempotent.
$PO -i demo-fleet config set wheel_type WH02 -g warehouse --dry-run
$PO -i demo-fleet config set wheel_type WH02 -g warehouse --yes
$PO -i demo-fleet config set wheel_type WH02 -g warehouse --yes
$PO -i demo-fleet config set controller.linear.x.max_velocity 0.8 -r panther-01 --yes
$PO -i demo-fleet config diff --all
$PO -i demo-fleet config history -r panther-01
# GPS (ANT02 via the RUTX11): the NMEA driver each stack runs (a service on 2.0.4, an argument
# on 2.1.1/2.2), then the fix status (demo robots answer with recorded NMEA).
$PO -i demo-fleet gps enable --all --dry-run
$PO -i demo-fleet gps status --all
# OS reimage: what a backup carries from a robot, then one 0600 archive per robot with a manifest.
$PO -i demo-fleet reimage plan -r panther-03
$PO -i demo-fleet reimage backup --all --out demo-fleet-backups
# Remote control: the E-stop and the WebUI of each demo robot as they answered (recorded answers)
$PO -i demo-fleet estop status --all
$PO -i demo-fleet webui status --all
