#!/usr/bin/env bash
# The decomposition in space at scale (docs/three-d.md, "Scale"): two P1 boxes of N cubes per
# side (the upper one N − 1: non-matching) pressed together, solved by the decomposition, and the
# same two bodies factorised and solved alone, each in its own process so that each peak resident
# memory is its own. Prints both runs' phases, wall times and peaks.
#
# Usage: bash scripts/scale_space.sh [N]    (default 45: about 2.9e5 DOFs in the lower box)
# Needs /usr/bin/time (the Debian package `time`).
set -euo pipefail
cd "$(dirname "$0")/.."
n=${1:-45}
cargo build --release --quiet --example scale_space
bin=${CARGO_TARGET_DIR:-target}/release/examples/scale_space
for mode in bodies dd; do
  /usr/bin/time -f "  peak resident memory %M kB" "$bin" "$mode" "$n"
done
