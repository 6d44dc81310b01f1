#!/usr/bin/env bash
# The whole test suite: install, build, run the unit tests and the validation runs (labels
# "unit" and "validation", a few minutes), then build the same suite with AddressSanitizer
# and UBSan (the "sanitize" preset, build-sanitize/, at -O1 -g1) and run its "unit" tests
# again under them (the validation runs check numbers the normal build checks, and cost
# minutes under the sanitizers: `ctest --preset sanitize -L validation` runs them).
# Runs labelled "long" are left out.
# Under CI (CI=true) warnings are errors.
# Two tests run at once on the two cores, so each gets one OpenMP thread, and threads wait
# passively (threads spinning on a shared core slow everything down: under the sanitizers two
# 2-thread tests side by side took 7 times as long); the thread-identity tests set their own
# counts.
# AGGPACK_SKIP_SANITIZE=1 runs the normal suite only.
set -euo pipefail
cd "$(dirname "$0")/.."
werror=()
[ "${CI:-}" = "true" ] && werror=(-DAGGPACK_WERROR=ON)
bash scripts/build.sh "${werror[@]}"
OMP_NUM_THREADS=1 OMP_WAIT_POLICY=PASSIVE ctest --test-dir build --output-on-failure --parallel 2 --label-exclude long
if [ "${AGGPACK_SKIP_SANITIZE:-}" != "1" ]; then
  cmake --preset sanitize "${werror[@]}" >/dev/null
  cmake --build --preset sanitize --target unit_tests  # not the validation runs' executables
  ctest --preset sanitize-unit
fi
