#!/usr/bin/env bash
# Times the default solve on long contact zones: the notch example with nx × 16 cells per body
# (nx + 1 contact points per body), its method and gamma lines removed so that the interface
# Newton method runs. Prints the wall time, peak memory and the phases of summary.json.
#
#   bash scripts/long_zone.sh [nx ...]          (default: 1000 2000)
#   SOLVE_ARGS="--enforcement augmented --tol 1e-8" bash scripts/long_zone.sh 2000 4000
#                                               (extra arguments of `contactdd solve`)
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q -p contactdd-cli
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for nx in "${@:-1000 2000}"; do
  for n in $nx; do
    sed -e "s/nx = 32, ny = 16/nx = $n, ny = 16/g" -e '/^method = /d' -e '/^gamma = /d' \
      examples/notch.toml > "$work/long$n.toml"
    /usr/bin/time -f "nx = $n: %e s wall, %M KB peak" \
      target/release/contactdd solve "$work/long$n.toml" --quiet --out "$work/out$n" ${SOLVE_ARGS:-} || true
    python3 -c "import json,sys; t=json.load(open(sys.argv[1]))['timing_s']; print('  ' + ', '.join(f'{k} {v:.3f} s' for k, v in sorted(t.items())))" "$work/out$n/summary.json"
  done
done
