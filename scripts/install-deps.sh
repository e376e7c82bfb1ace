#!/usr/bin/env bash
# Installs the Debian 12 packages vppdem needs (as root, or through sudo).
set -euo pipefail
pkgs=(build-essential cmake pkg-config ccache libtomlplusplus-dev libcli11-dev nlohmann-json3-dev
      libgtest-dev libgmock-dev libbenchmark-dev libhwy-dev python3 python3-matplotlib python3-numpy
      pybind11-dev python3-dev python3-pytest
      libopenmpi-dev openmpi-bin zlib1g-dev)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then exit 0; fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
