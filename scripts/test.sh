#!/usr/bin/env bash
# The tests: the README's test command, and exactly what CI (.ci/run) runs.
#  1. the Rust workspace: cargo test --workspace --release;
#  2. the Python package: a fresh virtual environment (target/py-venv),
#     maturin, numpy, pytest, dask[distributed] and trimesh from PyPI, the wheel
#     built by `maturin build --release`, installed with pip, and pytest
#     (crates/py/tests) against the CLI binary built in step 1.
# Any failing step fails the script; pytest collecting no test (exit 5)
# is a failure too.
set -euo pipefail
cd "$(dirname "$0")/.."
python=${PYTHON:-python3}
command -v "$python" >/dev/null || { echo "test.sh: $python not found: the Python tests need Python 3.9 or later" >&2; exit 1; }

# Also builds target/release/trigbody, the binary the Python tests compare
# with (a separate `cargo build -p trigbody` would resolve other features
# without the dev-dependencies and rebuild half the tree).
cargo test --workspace --release

venv=target/py-venv
rm -rf "$venv" target/wheels
"$python" -m venv "$venv"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
    "maturin>=1.9,<2" numpy pytest "dask[distributed]" trimesh
"$venv/bin/maturin" build --release --quiet -m crates/py/Cargo.toml -o target/wheels
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check target/wheels/trigbody-*.whl

# From the tests' folder, so `import trigbody` is the installed wheel.
status=0
(cd crates/py/tests && TRIGBODY_BIN="$PWD/../../../target/release/trigbody" \
    "../../../$venv/bin/python" -m pytest -q -p no:cacheprovider .) || status=$?
if [ "$status" -eq 5 ]; then
    echo "test.sh: pytest collected no tests" >&2
    exit 1
fi
exit "$status"
