#!/usr/bin/env bash
# Friction in space, the decomposition against the monolithic reference (docs/three-d.md,
# "Friction in space"): each case solved by both, with the Newton steps, wall times, the
# sticking and slipping points and the largest differences of the pressures and tractions over
# the peak pressure, as the markdown table of the docs. About three minutes on 2 cores (the
# reference on the ball takes most of it).
#
#   bash scripts/friction_space.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet --bin contactdd
bin=target/release/contactdd
out=$(mktemp -d /tmp/friction-space.XXXX)
trap 'rm -rf "$out"' EXIT

# name | file | extra arguments
cases=(
  "friction_block.toml (μ = 0.3)|examples/space/friction_block.toml|"
  "sphere_block.toml, --friction coulomb:0.3|examples/space/sphere_block.toml|--friction coulomb:0.3"
  "sphere_block.toml, --friction tresca:500|examples/space/sphere_block.toml|--friction tresca:500"
)
echo "| case | points (stick / slip) | decomposition | monolithic reference | pressures | tractions |"
echo "|---|---|---|---|---|---|"
k=0
for entry in "${cases[@]}"; do
  IFS='|' read -r name file extra <<< "$entry"
  k=$((k + 1))
  # shellcheck disable=SC2086
  "$bin" solve "$file" $extra --out "$out/$k-dd" --quiet > /dev/null
  # shellcheck disable=SC2086
  "$bin" monolithic "$file" $extra --out "$out/$k-mono" --quiet > /dev/null
  python3 - "$name" "$out/$k-dd" "$out/$k-mono" <<'EOF'
import csv, json, sys
name, dd, mono = sys.argv[1:]
def table(d):
    return {(r["pair"], r["node"]): r for r in csv.DictReader(open(f"{d}/contact.csv"))}
def summary(d):
    s = json.load(open(f"{d}/summary.json"))
    return s["newton_steps"], sum(v for k, v in s["timings"].items() if not k.startswith("of which"))
a, b = table(dd), table(mono)
peak = max(float(r["pressure"]) for r in a.values())
diff = lambda cols: max(abs(float(a[k][c]) - float(b[k][c])) for k in a for c in cols) / peak
status = [r["status"] for r in a.values()]
same = all(a[k]["status"] == b[k]["status"] for k in a)
(sd, td), (sm, tm) = summary(dd), summary(mono)
print(f"| {name} | {len(a)} ({status.count('stick')} / {status.count('slip')}) "
      f"| {sd} Newton steps, {td:.2f} s | {sm} Newton steps, {tm:.2f} s "
      f"| {diff(['pressure']):.1e} | {diff(['traction_x', 'traction_y', 'traction_z']):.1e}"
      f"{'' if same else ' (statuses differ)'} |")
EOF
done
