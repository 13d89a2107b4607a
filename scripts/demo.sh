#!/usr/bin/env bash
# The main job on the embedded demo fleet, on a fresh machine, with no robot:
# installs panther-ops in .venv, creates the demo fleet and runs it.
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON="${PYTHON:-python3}"
if [ ! -x .venv/bin/python ]; then
  "$PYTHON" -m venv .venv
fi
.venv/bin/python -m pip install -q --upgrade pip >/dev/null
.venv/bin/python -m pip install -q -e .
PO=.venv/bin/panther-ops
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
# Remote control: the E-stop and the WebUI of each demo robot as they answered (recorded answers)
$PO -i demo-fleet estop status --all
$PO -i demo-fleet webui status --all
