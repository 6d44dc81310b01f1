#!/usr/bin/env bash
# Installs what is missing, then configures and builds aggpack (Release) in build/.
# Extra arguments go to CMake (scripts/test.sh passes -DAGGPACK_WERROR=ON under CI).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build build --parallel
