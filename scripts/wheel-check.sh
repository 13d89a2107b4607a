#!/usr/bin/env bash
# The wheel is the product: build it from a clean checkout (the files git tracks or would
# add, else a copy of the tree), install it into a fresh venv outside the checkout, and run the README's main
# job (scripts/demo-job.sh) and the template-reading commands from there.
#
#   bash scripts/wheel-check.sh                 # with python3
#   bash scripts/wheel-check.sh --python PATH
set -euo pipefail
cd "$(dirname "$0")/.."
REPO="$PWD"
PYTHON=python3
if [ "${1:-}" = "--python" ]; then PYTHON="$2"; fi
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
mkdir "$WORK/src" "$WORK/dist" "$WORK/run"
if git -C "$REPO" rev-parse --verify -q HEAD >/dev/null 2>&1; then
  # the files git knows or would add (nothing ignored: no venv, build or egg-info)
  git -C "$REPO" ls-files -z -c -o --exclude-standard \
    | (cd "$REPO" && tar --null --ignore-failed-read -T - -cf -) 2>/dev/null | tar -x -C "$WORK/src"
else
  tar -C "$REPO" --exclude='./.venv*' --exclude='./build' --exclude='./dist' --exclude='*.egg-info' -cf - . \
    | tar -x -C "$WORK/src"
fi
echo "== wheel from a clean checkout" >&2
"$PYTHON" -m pip wheel -q --no-deps -w "$WORK/dist" "$WORK/src"
WHEEL="$(ls "$WORK"/dist/panther_ops-*.whl)"
"$PYTHON" -m zipfile -l "$WHEEL" | grep -q 'panther_ops/templates/lights/led_config.yaml' \
  || { echo "the wheel has no templates: $WHEEL" >&2; exit 1; }
echo "== fresh venv outside the checkout: $WORK/venv" >&2
"$PYTHON" -m venv "$WORK/venv"
"$WORK/venv/bin/python" -m pip install -q "$WHEEL"
cd "$WORK/run"
PO="$WORK/venv/bin/panther-ops"
# Nothing may come from the checkout: the package and its templates are the installed ones.
"$WORK/venv/bin/python" - "$REPO" <<'PY'
import sys
from pathlib import Path

import panther_ops
from panther_ops.core.fleet.templates import templates_dir

repo = Path(sys.argv[1]).resolve()
for where in (Path(panther_ops.__file__).resolve(), templates_dir().resolve()):
    assert repo not in where.parents, f"{where} is in the checkout {repo}"
print(f"panther_ops from {Path(panther_ops.__file__).parent}, templates {templates_dir()}", file=sys.stderr)
PY
PO="$PO" bash "$REPO/scripts/demo-job.sh" >/dev/null
"$PO" lights validate "$("$WORK/venv/bin/python" -c 'from panther_ops.core.fleet.templates import template_path; print(template_path("lights", "user_animations.example.yaml"))')"
"$PO" manager run --sim --scenario low_battery --duration 2 --json >/dev/null
echo "== the wheel runs the main job" >&2
