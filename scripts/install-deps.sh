#!/usr/bin/env bash
# Installs the Debian packages aggpack builds with, only those that are missing.
set -euo pipefail
packages=(g++ cmake ninja-build pkg-config libtomlplusplus-dev nlohmann-json3-dev libcli11-dev libfmt-dev
          libgtest-dev libbenchmark-dev zlib1g-dev libhwy-dev libcereal-dev libxxhash-dev libqhull-dev python3
          lammps openmpi-bin pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib gmsh
          calculix-ccx python3-venv python3-pip python3-setuptools)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "aggpack: installing ${missing[*]}"
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
"${sudo_cmd[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
