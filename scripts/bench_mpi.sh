#!/usr/bin/env bash
# Distributed solve benchmark (docs/mpi.md): wall time, peak memory per rank and time in
# communication on 1 and 2 MPI ranks, for
# - a column of 64 blocks (the examples/stack.toml column, 64 blocks high), and
# - a column of 16 bodies of about 1e5 DOFs each (P1, 100 × 500 cells per body),
# each with the interface Newton method (the default) and the two-level sweeps (many exchanges).
# Every process runs one thread (--threads 1), so that 2 ranks on 2 cores compare with 1 process
# on 1 core; rank 0 writes the results (the VTU files of 1.6e6 DOFs take seconds: `total`).
# Needs the mpi build (scripts/test_mpi.sh installs OpenMPI and builds it into target/mpi).
#
# Usage: bash scripts/bench_mpi.sh [RANKS...]     (default: 1 2)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${CONTACTDD_BIN:-$(pwd)/target/mpi/contactdd}
if [ ! -x "$bin" ]; then
  echo "no $bin: run scripts/test_mpi.sh first (it builds contactdd --features mpi)" >&2
  exit 1
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
ranks=("$@")
if [ ${#ranks[@]} = 0 ]; then ranks=(1 2); fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# A column of N blocks of nx × ny cells each, steel and aluminium alternating, on a frictionless
# floor, pressed on top (the examples/stack.toml set-up).
column() {
  local n=$1 nx=$2 ny=$3 h=$4
  python3 - "$n" "$nx" "$ny" "$h" <<'EOF'
import sys
n, nx, ny, h = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
print(f'name = "column{n}"\nplane = "strain"\n')
print('[materials.steel]\nyoung = 2.1e5\npoisson = 0.3\n')
print('[materials.aluminium]\nyoung = 7.0e4\npoisson = 0.33\n')
for k in range(n):
    mat = "steel" if k % 2 == 0 else "aluminium"
    cells = nx if k % 2 == 0 else nx - nx // 4
    supports = '{ boundary = "left", component = "normal" }'
    if k == 0:
        supports += ', { boundary = "bottom", component = "normal" }'
    print(f'[[bodies]]\nname = "b{k}"\nmaterial = "{mat}"')
    print(f'mesh = {{ kind = "rectangle", x = [0.0, 2.0], y = [{k * h}, {(k + 1) * h}], '
          f'nx = {cells}, ny = {ny} }}')
    print(f'supports = [{supports}]')
    if k == n - 1:
        print('loads = [{ kind = "pressure", boundary = "top", value = 100.0 }]')
    print()
for k in range(n - 1):
    print(f'[[contact]]\nbodies = ["b{k}", "b{k + 1}"]\nboundaries = ["top", "bottom"]')
    print(f'penalty = {{ c = 0.5, h = {h} }}\n')
EOF
}

column 64 40 5 0.25 >"$work/column64.toml"
column 16 100 500 2.0 >"$work/large16.toml"

printf '%-20s %5s %10s %10s  %s\n' case ranks "wall (s)" iterations "per rank: communication (s), peak memory (MiB)"
# Runs $bin with its arguments, then prints its peak resident memory in MiB on stderr.
peak() {
  python3 -c '
import resource, subprocess, sys
code = subprocess.run(sys.argv[1:]).returncode
print(round(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024), file=sys.stderr)
sys.exit(code)' "$@"
}

for case in column64 large16; do
  for scheme in newton two-level; do
    args=(--threads 1)
    if [ "$scheme" = two-level ]; then args+=(--accelerator none); fi
    for n in "${ranks[@]}"; do
      out="$work/$case-$scheme-$n"
      start=$(date +%s.%N)
      if [ "$n" = 1 ]; then
        peak "$bin" solve "$work/$case.toml" --out "$out" "${args[@]}" >"$out.log" 2>"$out.peak"
        detail="one process: peak memory $(cat "$out.peak") MiB"
      else
        mpirun --oversubscribe -n "$n" "$bin" solve "$work/$case.toml" --out "$out" "${args[@]}" >"$out.log"
        detail=$(sed -n 's/^ranks: //p' "$out.log")
      fi
      end=$(date +%s.%N)
      iterations=$(sed -n 's/^converged in \([0-9]*\) iterations.*/\1/p' "$out.log")
      printf '%-20s %5s %10.2f %10s  %s\n' "$case $scheme" "$n" "$(awk -v a="$start" -v b="$end" 'BEGIN { print b - a }')" \
        "$iterations" "$detail"
      sed -n 's/^time: /    time: /p' "$out.log"
    done
  done
done
