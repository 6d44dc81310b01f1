#!/usr/bin/env bash
# Rewrites the README's generated blocks (between `<!-- generated: ... -->` and
# `<!-- end generated -->`) from this build: console blocks from the commands they show, the
# reproduce tables from docs/reproduce_of_record.json. The test readme_generated_blocks fails
# until this is run after a change that moves them.
#
#   bash scripts/update_readme.sh                  # the blocks, from the record as it is
#   bash scripts/update_readme.sh --rerun-reproduce # first a full `aggpack reproduce` (about
#                                                   # 20 min on two cores) to renew the record:
#                                                   # when results or the plan of reproduce changed
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
if [ "${1:-}" = "--rerun-reproduce" ]; then
  out=$(mktemp -d "${TMPDIR:-/tmp}/aggpack-reproduce.XXXXXX")
  ./build/aggpack reproduce --out "$out" --quiet
  cp "$out/reproduce.json" docs/reproduce_of_record.json
  echo "renewed docs/reproduce_of_record.json from $out (add its wall time to BENCHMARKS.md)"
fi
python3 tests/tools/readme_blocks.py update build/aggpack .
