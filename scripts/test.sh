#!/usr/bin/env bash
# Runs every test of contactdd: the Rust workspace (release mode: the convergence and contact
# tests are numerical) and the Python package (built and installed into a private venv).
# Needs only cargo and python3; installs maturin, numpy, pytest, matplotlib and meshio itself. The
# MPI tests (scripts/test_mpi.sh) run with CONTACTDD_MPI=1, and always in CI.
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

# The distributed solve against the single process (docs/mpi.md) installs OpenMPI and libclang
# with apt-get when they are missing and builds contactdd once more with --features mpi (a few
# minutes on a fresh machine): it runs here with CONTACTDD_MPI=1, and always in CI (.ci/run).
if [ "${CONTACTDD_MPI:-0}" = 1 ]; then
  echo "== MPI tests (scripts/test_mpi.sh; installs OpenMPI with apt-get if missing)"
  bash scripts/test_mpi.sh
else
  echo "== MPI tests not run here: bash scripts/test_mpi.sh (or CONTACTDD_MPI=1) runs them"
fi
