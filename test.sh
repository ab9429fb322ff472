#!/usr/bin/env bash
# The one test command: the Rust workspace's tests, then the Python package built from this
# tree (installed into the Python of $PYTHON, default python3) and its tests.
# The Python needs maturin, numpy, pytest and scikit-learn (ray for the Ray sweep test):
#   python3 -m pip install maturin numpy pytest scikit-learn ray
set -euo pipefail
cd "$(dirname "$0")"

cargo test --workspace --locked

PY="${PYTHON:-python3}"
if ! "$PY" -c "import maturin, numpy, pytest, sklearn" 2>/dev/null; then
  echo "error: $PY lacks maturin, numpy, pytest or scikit-learn; install them with" >&2
  echo "  $PY -m pip install maturin numpy pytest scikit-learn ray" >&2
  exit 1
fi
# maturin's build hook runs the `maturin` program: the one installed beside that Python.
PATH="$("$PY" -c 'import os, sys; print(os.path.dirname(sys.executable))'):$PATH"
export PATH
# The dev profile of the workspace: the wheel reuses what `cargo test` just built.
# Quiet when it works; the whole build log (cargo's and maturin's) when it does not.
build_log="$(mktemp)"
if ! MATURIN_PEP517_ARGS="--profile dev" "$PY" -m pip install --verbose --no-deps \
  --force-reinstall --no-build-isolation ./python >"$build_log" 2>&1; then
  cat "$build_log" >&2
  echo "error: building the Python package from ./python failed (its build log is above)" >&2
  exit 1
fi
rm -f "$build_log"
# The Python tests compare the package with the command cargo built.
export STRIDER_BIN="${CARGO_TARGET_DIR:-$PWD/target}/debug/strider"
"$PY" -m pytest -q python/tests
