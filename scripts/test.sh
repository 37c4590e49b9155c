#!/usr/bin/env bash
# Runs every test of contactdd: the Rust workspace (release mode: the convergence and contact
# tests are numerical) and the Python package (built and installed into a private venv).
# Needs only cargo and python3; installs maturin, numpy, pytest, matplotlib and meshio itself.
set -euo pipefail
cd "$(dirname "$0")/.."

echo "== Rust tests"
cargo test --release --workspace --exclude contactdd-python

echo "== One build for the quick start, the tests and the Python module"
python3 scripts/shared_build.py

echo "== Python tests"
venv="target/test-venv"
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install --quiet --upgrade pip
"$venv/bin/python" -m pip install --quiet "./python[test]"
"$venv/bin/python" -m pytest python/tests -q
