#!/usr/bin/env bash
# Install wormgear's build and test dependencies from Debian 12 packages
# (README.md, "Dependencies", says why each is there), and the dashboard's
# npm packages (web/package-lock.json: uPlot, and the test clients) with
# `npm ci`. Idempotent: installs only what is missing. Run as root.
# --check: install nothing; name what is missing (exit 1) or say nothing
# (exit 0). sys.readme_bench asks it, from a network namespace.
# --help: this text; any other argument is refused.
set -euo pipefail
. "$(dirname "$0")/args.sh"
args_help "$@"
check=0
case $# in
0) ;;
1) [ "$1" = --check ] && check=1 || args_refuse setup.sh "unknown argument '$1' (--check, or none)" ;;
*) args_refuse setup.sh "one argument at most (--check), got $#" ;;
esac
lack=() # --check: what would be installed
# apt_install PKG...: from Debian's archive (--check: noted in lack instead)
apt_install() {
  if [ $check = 1 ]; then
    lack+=("$@")
    return
  fi
  echo "setup: installing $*"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "$@" >/dev/null
}
pkgs=(
  build-essential cmake pkg-config dpkg-dev
  libinih-dev
  liblcm-dev liblcm-bin libglib2.0-dev
  libev-dev
  libsodium-dev
  libsystemd-dev systemd
  libcairo2-dev
  iproute2 util-linux procps
  liblcm-java libjchart2d-java default-jdk-headless
  xvfb x11-utils tmux
  fonts-dejavu-core
  libopenmpi-dev openmpi-bin
  libwebsockets-dev libcjson-dev chromium
  libgsl-dev libsundials-dev
)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] || apt_install "${missing[@]}"

# Node and npm (the dashboard's packages and its tests): Debian's when the
# machine has none.
command -v npm >/dev/null 2>&1 || apt_install nodejs npm
# web/node_modules from the lock file, unless it is already up to date.
web=$(cd "$(dirname "$0")/../web" && pwd)
if [ ! -f "$web/node_modules/.package-lock.json" ] ||
   [ "$web/package-lock.json" -nt "$web/node_modules/.package-lock.json" ]; then
  if [ $check = 1 ]; then
    lack+=("web/node_modules (npm ci)")
  else
    echo "setup: npm ci in $web"
    (cd "$web" && npm ci --no-audit --no-fund --loglevel=error)
  fi
fi
if [ ${#lack[@]} -gt 0 ]; then
  echo "setup: missing: ${lack[*]}"
  exit 1
fi
