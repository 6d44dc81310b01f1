#!/usr/bin/env bash
# Rewrites the golden records (tests/golden/*.json) from the current build. Do it only on
# purpose, when a change is meant to move the results, and commit the records on their own
# so that the change is one reviewable diff.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
python3 tests/tools/golden.py record build/aggpack .
# Results that move the golden records move the README's full run of record too, which CI
# cannot rerun (about 20 minutes): renew it in the same change.
echo "Results moved: renew the README's run of record too: bash scripts/update_readme.sh --rerun-reproduce"
