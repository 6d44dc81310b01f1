#!/usr/bin/env bash
# The whole default test suite: install, build, run every test except long validation runs.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
ctest --test-dir build --output-on-failure --parallel 2 --label-exclude validation
