#!/usr/bin/env bash
# The whole test suite: install, build, run the unit tests and the validation runs (labels
# "unit" and "validation", a few minutes), then build the same suite with AddressSanitizer
# and UBSan (the "sanitize" preset, build-sanitize/) and run its unit tests under them (the
# validation runs under the sanitizers take too long for CI's 30 minutes:
# `ctest --preset sanitize` runs them too). Runs labelled "long" are left out.
# Under CI (CI=true) warnings are errors.
# Two tests run at once on the two cores, so each gets one OpenMP thread (threads spinning
# on a shared core slow everything down); the thread-identity tests set their own counts.
# AGGPACK_SKIP_SANITIZE=1 runs the normal suite only.
set -euo pipefail
cd "$(dirname "$0")/.."
werror=()
[ "${CI:-}" = "true" ] && werror=(-DAGGPACK_WERROR=ON)
bash scripts/build.sh "${werror[@]}"
OMP_NUM_THREADS=1 ctest --test-dir build --output-on-failure --parallel 2 --label-exclude long
if [ "${AGGPACK_SKIP_SANITIZE:-}" != "1" ]; then
  cmake --preset sanitize "${werror[@]}" >/dev/null
  cmake --build --preset sanitize
  ctest --preset sanitize --label-regex unit
fi
