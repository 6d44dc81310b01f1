#!/usr/bin/env bash
# ctest python_install: the module installed by `cmake --install` imports where Python looks,
# from outside the checkout and without PYTHONPATH (README, "Python"):
#   - into a fresh virtual environment (--system-site-packages: numpy), its prefix the venv;
#   - into the user base (~/.local; here a scratch PYTHONUSERBASE), the user site;
#   - `pip install --no-build-isolation .` into another fresh venv, reusing this build.
# Only the module's component is installed (`--component python`): no second build, seconds.
#
#   install_module.sh BUILD_DIR SOURCE_DIR PYTHON
set -euo pipefail
build_dir=$(realpath "$1")
source_dir=$(realpath "$2")
python=$3

fail() { echo "FAIL: $*" >&2; exit 1; }

scratch=$(realpath "$(mktemp -d "${TMPDIR:-/tmp}/aggpack-python-install.XXXXXX")")
trap 'rm -rf "$scratch"' EXIT
case "$scratch/" in "$source_dir"/*) fail "the scratch folder $scratch lies inside the checkout $source_dir";; esac
mkdir "$scratch/elsewhere"
unset PYTHONPATH

# Imports aggpack with `interpreter` from outside the checkout; the module must lie under `expected`.
check_import() {
  local interpreter=$1 expected=$2
  (cd "$scratch/elsewhere" && "$interpreter" - "$expected" <<'PY') || fail "import aggpack failed with $interpreter"
import sys
import aggpack
where = aggpack.__file__
assert where.startswith(sys.argv[1]), f"aggpack imported from {where}, not from {sys.argv[1]}"
s = aggpack.Scenario.from_dict({"container": {"side": 0.06, "height": 0.3}, "particles": {"diameter": 0.01, "count": 300},
                                "deposition": {}, "analysis": {"box_sides": [0.03]}})
report = aggpack.run(s, threads=1)
assert report.bed.positions.shape == (300, 3) and 0.4 < report.density < 0.7
print(f"aggpack {aggpack.__version__} from {where}")
PY
}

# A virtual environment, by cmake --install.
"$python" -m venv --system-site-packages "$scratch/venv" || fail "$python -m venv failed (python3-venv)"
cmake --install "$build_dir" --prefix "$scratch/venv" --component python > "$scratch/venv.log" 2>&1 ||
  fail "cmake --install into the venv failed: $(cat "$scratch/venv.log")"
site=$("$scratch/venv/bin/python" -c 'import sysconfig; print(sysconfig.get_path("platlib"))')
check_import "$scratch/venv/bin/python" "$site/aggpack"

# The user base, as `cmake --install build --prefix ~/.local` (a scratch one: PYTHONUSERBASE).
export PYTHONUSERBASE=$scratch/userbase
cmake --install "$build_dir" --prefix "$PYTHONUSERBASE" --component python > "$scratch/user.log" 2>&1 ||
  fail "cmake --install into the user base failed: $(cat "$scratch/user.log")"
user_site=$("$python" -c 'import site; print(site.getusersitepackages())')
check_import "$python" "$user_site/aggpack"
unset PYTHONUSERBASE

# pip, offline, reusing this build: the wheel of the module CMake built.
"$python" -m venv --system-site-packages "$scratch/pipvenv" || fail "$python -m venv failed"
AGGPACK_BUILD_DIR=$build_dir "$scratch/pipvenv/bin/python" -m pip install --no-build-isolation --no-index \
  --no-cache-dir -q "$source_dir" > "$scratch/pip.log" 2>&1 || fail "pip install failed: $(cat "$scratch/pip.log")"
pip_site=$("$scratch/pipvenv/bin/python" -c 'import sysconfig; print(sysconfig.get_path("platlib"))')
check_import "$scratch/pipvenv/bin/python" "$pip_site/aggpack"
echo "python_install: the venv, the user site and pip each import aggpack"
