#!/usr/bin/env bash
# The main job on the embedded demo fleet, on a fresh machine, with no robot:
# installs panther-ops in .venv, creates the demo fleet and runs it (scripts/demo-job.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON="${PYTHON:-python3}"
if [ ! -x .venv/bin/python ]; then
  "$PYTHON" -m venv .venv
fi
.venv/bin/python -m pip install -q --upgrade pip >/dev/null
.venv/bin/python -m pip install -q -e .
PO=.venv/bin/panther-ops bash scripts/demo-job.sh
