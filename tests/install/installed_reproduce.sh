#!/usr/bin/env bash
# ctest install_layout and install_reproduce_quick: an installed aggpack runs `reproduce`
# from its own share/aggpack/, with nothing of the checkout it was built from.
#
#   installed_reproduce.sh BUILD_DIR SOURCE_DIR layout|reproduce
#
# layout:    installs the build tree into a scratch prefix outside the checkout; checks that
#            every shipped scenario and table is under share/aggpack/examples, that the
#            installed binary plans its reproduce from there (--dry-run, from a folder outside
#            the checkout), and that a copy of the binary without share/ refuses with exit 2
#            naming where it looked, rather than falling back to the checkout.
# reproduce: the same install, then `reproduce --quick` run from outside the checkout; its
#            reproduce.json names the installed examples, it ran the runs --dry-run planned,
#            and no file it wrote names the checkout.
set -euo pipefail
build_dir=$(realpath "$1")
source_dir=$(realpath "$2")
mode=$3

fail() { echo "FAIL: $*" >&2; exit 1; }

scratch=$(realpath "$(mktemp -d "${TMPDIR:-/tmp}/aggpack-install-test.XXXXXX")")
trap 'rm -rf "$scratch"' EXIT
case "$scratch/" in "$source_dir"/*) fail "the scratch folder $scratch lies inside the checkout $source_dir";; esac
prefix=$scratch/prefix
cmake --install "$build_dir" --prefix "$prefix" > "$scratch/install.log" || fail "cmake --install failed: $(cat "$scratch/install.log")"

installed_examples=$prefix/share/aggpack/examples
for shipped in "$source_dir"/examples/*; do
  [ -e "$installed_examples/$(basename "$shipped")" ] || fail "$(basename "$shipped") of examples/ is not installed in $installed_examples"
done

mkdir "$scratch/elsewhere"
cd "$scratch/elsewhere"
aggpack=$prefix/bin/aggpack

if [ "$mode" = layout ]; then
  plan=$("$aggpack" reproduce --dry-run) || fail "reproduce --dry-run exited $?: $plan"
  echo "$plan"
  grep -qxF "examples: $installed_examples" <<< "$plan" || fail "the installed binary does not plan from $installed_examples"
  # A binary without its share/ must not find the checkout's examples instead.
  mkdir -p "$scratch/bare/bin"
  cp "$aggpack" "$scratch/bare/bin/aggpack"
  set +e
  refusal=$("$scratch/bare/bin/aggpack" reproduce --dry-run 2>&1)
  code=$?
  set -e
  echo "$refusal"
  [ "$code" -eq 2 ] || fail "a binary without share/aggpack exited $code, expected 2: $refusal"
  grep -qF "$scratch/bare/share/aggpack/examples" <<< "$refusal" || fail "the refusal does not name where it looked: $refusal"
  # --examples still overrides.
  "$scratch/bare/bin/aggpack" reproduce --dry-run --examples "$installed_examples" > /dev/null \
    || fail "--examples $installed_examples was not taken"
  echo "ok: installed under $prefix, reproduce plans from $installed_examples"
elif [ "$mode" = reproduce ]; then
  planned=$("$aggpack" reproduce --quick --dry-run | sed -n 's/^runs: \([0-9]*\) .*/\1/p')
  [ -n "$planned" ] || fail "reproduce --quick --dry-run printed no runs line"
  out=$scratch/reproduce
  OMP_NUM_THREADS=${OMP_NUM_THREADS:-1} "$aggpack" reproduce --quick --out "$out" --threads 1 > "$scratch/reproduce.log" 2>&1 \
    || fail "reproduce --quick exited $?: $(tail -20 "$scratch/reproduce.log")"
  head -1 "$scratch/reproduce.log"
  python3 - "$out/reproduce.json" "$installed_examples" "$planned" <<'PY' || fail "reproduce.json"
import json, sys
record = json.load(open(sys.argv[1]))
assert record["examples_dir"] == sys.argv[2], f"examples_dir: {record['examples_dir']}, expected {sys.argv[2]}"
assert record["runs"] == int(sys.argv[3]), f"runs: {record['runs']}, --dry-run planned {sys.argv[3]}"
assert record["mode"] == "quick", record["mode"]
PY
  [ -s "$out/report.html" ] || fail "no report.html in $out"
  if grep -rlF "$source_dir" "$out" "$scratch/reproduce.log"; then fail "the files above name the checkout $source_dir"; fi
  echo "ok: reproduce --quick from $prefix, $planned runs, nothing of $source_dir"
else
  fail "mode $mode: expected layout or reproduce"
fi
