#!/usr/bin/env bash
# Rewrites the golden records (tests/golden/*.json) from the current build. Do it only on
# purpose, when a change is meant to move the results, and commit the records on their own
# so that the change is one reviewable diff.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
python3 tests/tools/golden.py record build/aggpack .
