#!/usr/bin/env bash
# The main job on a shipped example: install, build, deposit the paper's Example 1 and
# measure it, show where the results are.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
./build/aggpack run examples/example1.toml --out out/example1
echo "Results: out/example1/summary.json, particles.csv, supports.csv, particles.vtp"
