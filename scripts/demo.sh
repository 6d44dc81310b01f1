#!/usr/bin/env bash
# The main job on a shipped example: install, build, run, show where the results are.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
./build/aggpack run examples/cubic_lattice.toml --out out/cubic_lattice
echo "Results: out/cubic_lattice/summary.json, particles.csv, particles.vtp"
