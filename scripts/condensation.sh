#!/usr/bin/env bash
# Times the default solve (interface Newton) of the notch example with NX × NY cells per body
# (NX + 1 contact points per body) on a condensation path: prints the wall time, the peak memory
# and the phases of summary.json (docs/sparse-path.md).
#
#   bash scripts/condensation.sh PATH NXxNY [NXxNY ...]     PATH: auto | dense | sparse
#   bash scripts/condensation.sh auto 368x184 4000x16
set -euo pipefail
cd "$(dirname "$0")/.."
path=${1:?auto, dense or sparse}
shift
cargo build --release -q -p contactdd-cli
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for size in "$@"; do
  nx=${size%x*}
  ny=${size#*x}
  sed -e "s/nx = 32, ny = 16/nx = $nx, ny = $ny/g" -e '/^method = /d' -e '/^gamma = /d' \
    -e "s/^\[solver\]/[solver]\ncondensation = \"$path\"/" examples/notch.toml > "$work/n$size.toml"
  /usr/bin/time -f "$path $size: %e s wall, %M KB peak" \
    target/release/contactdd solve "$work/n$size.toml" --quiet --out "$work/out$size"
  python3 -c "import json,sys; t=json.load(open(sys.argv[1]))['timing_s']; print('  ' + ', '.join(f'{k} {v:.3f} s' for k, v in sorted(t.items())))" "$work/out$size/summary.json"
done
