#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (AddressSanitizer and UBSan on) and runs each for
# SECONDS (default 600) on its seed corpus in fuzz/corpus, one target after another, or
# TARGET alone. Findings go to build-fuzz/findings/<target>/; copy each into
# tests/fuzz_regressions/<target>/ once fixed, so the normal test suite replays it.
#   bash scripts/fuzz.sh [SECONDS] [scenario_reader|grading_reader|particle_file_reader|calibration_reader|checkpoint_reader|material_reader|shape_reader|material_file_reader]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-600}"
targets="${2:-scenario_reader grading_reader particle_file_reader calibration_reader checkpoint_reader material_reader shape_reader material_file_reader}"
command -v clang++ >/dev/null || { echo "scripts/fuzz.sh needs clang (apt-get install clang libomp-dev)" >&2; exit 2; }
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DAGGPACK_FUZZ=ON -DAGGPACK_BUILD_TESTS=OFF -DAGGPACK_BUILD_BENCH=OFF >/dev/null
ninja -C build-fuzz $(for t in $targets; do echo "fuzz/fuzz_$t"; done)
declare -A corpus=([scenario_reader]=scenario [grading_reader]=grading [particle_file_reader]=particles
                  [calibration_reader]=calibration [checkpoint_reader]=checkpoint [material_reader]=materials
                  [shape_reader]=shape [material_file_reader]=material_file)
for t in $targets; do
  work="build-fuzz/corpus/$t" findings="build-fuzz/findings/$t"
  mkdir -p "$work" "$findings" "tests/fuzz_regressions/${corpus[$t]}"  # libFuzzer needs every corpus folder
  echo "== fuzz_$t for $seconds s"
  # 2 GiB of memory and 10 s per input at most: more is a finding (an unbounded input).
  UBSAN_OPTIONS=print_stacktrace=1 "build-fuzz/fuzz/fuzz_$t" "$work" "fuzz/corpus/${corpus[$t]}" \
    "tests/fuzz_regressions/${corpus[$t]}" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 \
    -max_len=65536 -artifact_prefix="$findings/" -print_final_stats=1 2>&1 | tail -n 25 || true
done
