#!/usr/bin/env bash
# The main job: install, build, reproduce Fu and Dekelbab (2003) (Examples 1 and 2, deposited
# and poured, the eight Table 2 mixes, three seeds each) and write the report. About fifteen
# minutes on two cores; add --quick for a two-minute pass: bash scripts/demo.sh --quick
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
./build/aggpack reproduce --out out/reproduce "$@"
echo "Open out/reproduce/report.html (or read out/reproduce/report.md)."
