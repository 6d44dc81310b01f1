#!/usr/bin/env bash
# The whole test suite: install, build, run the unit tests and the validation runs (labels
# "unit" and "validation", both well under a minute); only runs labelled "long" are left out.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
ctest --test-dir build --output-on-failure --parallel 2 --label-exclude long
