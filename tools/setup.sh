#!/usr/bin/env bash
# Install wormgear's build and test dependencies from Debian 12 packages
# (README.md, "Dependencies", says why each is there). Idempotent: installs
# only what is missing. Run as root.
set -euo pipefail
pkgs=(
  build-essential cmake pkg-config dpkg-dev
  libinih-dev
  liblcm-dev liblcm-bin libglib2.0-dev
  libev-dev
  libsystemd-dev systemd
  libcairo2-dev
  iproute2 util-linux procps
  liblcm-java libjchart2d-java default-jdk-headless
  xvfb x11-utils tmux
  fonts-dejavu-core
  libopenmpi-dev openmpi-bin
)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
