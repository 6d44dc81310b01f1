#!/usr/bin/env bash
# The whole test suite: install, build, run the unit tests and the validation runs (labels
# "unit" and "validation", a few minutes); only runs labelled "long" are left out.
# Under CI (CI=true) warnings are errors.
# Two tests run at once on the two cores, so each gets one OpenMP thread (threads spinning
# on a shared core slow everything down); the thread-identity tests set their own counts.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${CI:-}" = "true" ]; then
  bash scripts/build.sh -DAGGPACK_WERROR=ON
else
  bash scripts/build.sh
fi
OMP_NUM_THREADS=1 ctest --test-dir build --output-on-failure --parallel 2 --label-exclude long
