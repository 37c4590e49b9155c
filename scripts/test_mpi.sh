#!/usr/bin/env bash
# The distributed solve (docs/mpi.md) against the single process, and its failure handling.
#
# Builds `contactdd` with `--features mpi` (installing OpenMPI and libclang with apt-get first if
# they are missing, and saying so), then:
# - solves the notch and the column of blocks (examples/notch.toml, examples/stack.toml) with the
#   interface Newton method (also from a start with nothing closed), the paper's sweeps, the
#   two-level sweeps, Aitken's sweeps without coarse correction and Anderson acceleration, and the Hertz example (Gmsh, a curved balanced
#   pair),
#   in one process and under `mpirun -n 2` and `-n 3`, and compares every output file byte for
#   byte (summary.json without its timings, contact.csv, history.csv, the VTU files): the numbers
#   are written to the last bit, so equal files are equal bits; and the same for load steps (the
#   recess with exact contact, the column in three steps: steps.csv, every step's VTU files), and
#   on the sparse condensation (forced, and chosen for a long contact zone);
# - solves a column whose top block one rank cannot factorise (no support against sliding) and
#   runs in which a body's Robin problem turns singular, and checks that every rank ends with the
#   single process's exit code and the same one message, naming the body, without hanging; and
#   the same for a results folder that cannot be written and for input errors in a body only its
#   own rank meshes; and that rank 0's console report holds every body's loads and reactions;
# - runs `check` and `sweep` under mpirun: rank 0 alone runs them (their output once), and every
#   rank ends with their exit code.
#
# Usage: bash scripts/test_mpi.sh
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v mpirun >/dev/null || ! command -v mpicc >/dev/null; then
  echo "== installing OpenMPI and libclang (apt-get): the mpi feature needs them"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq openmpi-bin libopenmpi-dev libclang-dev >/dev/null
fi
# OpenMPI refuses root without these; CI runs as root.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mpirun=(mpirun --oversubscribe)

echo "== building contactdd --features mpi"
cargo build --release --quiet -p contactdd-cli --features mpi
# Keep this build's binary apart: a default build uplifts its own to target/release.
mkdir -p target/mpi
cp target/release/contactdd target/mpi/contactdd
bin=$(pwd)/target/mpi/contactdd

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
passed=0

# Drops the "timing_s" object of summary.json (timings and per-rank communication differ).
strip_timing() {
  awk '/^  "timing_s": \{/ { skip = 1 } !skip { print } skip && /^  \},?$/ { skip = 0 }' "$1" >"$1.cmp"
  rm "$1"
}

# Runs `contactdd solve` on `ranks` processes (1: no mpirun); records exit code and stderr.
run() {
  local dir=$1 ranks=$2 file=$3
  shift 3
  local code=0
  if [ "$ranks" = 1 ]; then
    timeout 300 "$bin" solve "$file" --out "$dir" --quiet "$@" >"$dir.stdout" 2>"$dir.stderr" || code=$?
  else
    timeout 300 "${mpirun[@]}" -n "$ranks" "$bin" solve "$file" --out "$dir" --quiet "$@" \
      >"$dir.stdout" 2>"$dir.stderr" || code=$?
  fi
  echo "$code" >"$dir.code"
  if [ -f "$dir/summary.json" ]; then strip_timing "$dir/summary.json"; fi
}

check() {
  local what=$1
  shift
  if "$@"; then
    passed=$((passed + 1))
    echo "ok   $what"
  else
    fail=$((fail + 1))
    echo "FAIL $what"
  fi
}

# Same outputs on 1, 2 and 3 ranks for one example and scheme.
same() {
  local name=$1 file=$2
  shift 2
  run "$work/$name-1" 1 "$file" "$@"
  for n in 2 3; do
    run "$work/$name-$n" "$n" "$file" "$@"
    check "$name: -n $n gives the single process's exit code and files bit for bit" \
      diff -r "$work/$name-1" "$work/$name-$n"
    check "$name: -n $n exit code" cmp -s "$work/$name-1.code" "$work/$name-$n.code"
  done
}

same notch-newton examples/notch.toml --accelerator newton
same notch-paper examples/notch.toml --method newton-kurchatov --gamma 0.5
same stack-newton examples/stack.toml
same stack-two-level examples/stack.toml --accelerator none
# Aitken's γ without coarse correction: the sweeps' values go point to point between the ranks of
# neighbouring blocks, and Aitken's dot products are summed per body in body order.
same stack-aitken examples/stack.toml --accelerator none --coarse off --gamma auto --max-iter 300
same stack-anderson examples/stack.toml --accelerator anderson
# A start with nothing closed (u0 = 0): every block is stranded, glued for the first step.
sed 's/^max-iter = 10000$/max-iter = 10000\nu0 = 0.0\nu-prev = 0.0/' examples/stack.toml >"$work/stack_u0.toml"
same stack-u0 "$work/stack_u0.toml"
# Gmsh meshes (their sizes estimated from the file's header) and a curved, non-matching
# balanced pair, whose ranks pair from each other's contact skins.
same hertz examples/hertz.toml
# Coulomb friction: the block held sideways by friction alone, and the column with friction on
# every pair (exact Coulomb by the augmented Lagrangian).
same friction-block examples/friction_block.toml
same stack-friction examples/stack.toml --friction coulomb:0.3 --enforcement augmented
# The Robin sweeps with friction (one-level): the tangential displacements from the shared state.
same stack-friction-sweeps examples/stack.toml --friction coulomb:0.3 --method active-set \
  --gamma auto --coarse off --max-iter 3000
# The sparse condensation: forced on the notch and the column, and chosen by the cost model for
# a long contact zone (1000 × 16 cells per body, 1001 contact points).
sparse() { sed "s/^\[solver\]/[solver]\ncondensation = \"$2\"/" "$1"; }
sparse examples/notch.toml sparse >"$work/notch_sparse.toml"
sparse examples/stack.toml sparse >"$work/stack_sparse.toml"
sed -e 's/nx = 32, ny = 16/nx = 1000, ny = 16/g' -e '/^method = /d' -e '/^gamma = /d' \
  examples/notch.toml >"$work/strip.toml"
same notch-sparse "$work/notch_sparse.toml"
same stack-sparse "$work/stack_sparse.toml"
same stack-sparse-anderson "$work/stack_sparse.toml" --accelerator anderson
same strip-auto "$work/strip.toml"
check "sparse: the cost model chose the sparse path for the strip's bodies" \
  test "$(grep -c '"condensation": "sparse"' "$work/strip-auto-1/summary.json.cmp")" = 2
# Load steps: every step's VTU set, steps.csv and results.pvd, on two bodies with exact contact
# (the recess) and on the column of eight floating blocks in three steps.
same recess-steps examples/recess_steps.toml
# The same with the two-level sweeps: point-to-point exchanges inside every multiplier update of
# every step.
same recess-steps-sweeps examples/recess_steps.toml --accelerator none --max-iter 3000
sed 's/^max-iter = 10000$/max-iter = 10000\nload-steps = 3/' examples/stack.toml >"$work/stack_steps.toml"
same stack-steps "$work/stack_steps.toml"
check "stack steps: the single process wrote three steps" test -f "$work/stack-steps-1/b7-step3.vtu"

# A column whose top block slides freely: the rank that owns it cannot factorise it.
# Drop the last body's (b7's) symmetry support: it is then free to slide sideways.
awk '/^supports = / { last = NR } { line[NR] = $0 } END { for (i = 1; i <= NR; i++) if (i != last) print line[i] }' \
  examples/stack.toml >"$work/sliding.toml"
for n in 1 2 3; do run "$work/sliding-$n" "$n" "$work/sliding.toml"; done
check "sliding block: the single process fails with exit 1" grep -qx 1 "$work/sliding-1.code"
check "sliding block: the message names the body" grep -q "body 'b7'" "$work/sliding-1.stderr"
for n in 2 3; do
  check "sliding block: -n $n ends with exit 1" grep -qx 1 "$work/sliding-$n.code"
  # mpirun adds its own note on stderr; contactdd's lines are the single process's, once.
  check "sliding block: -n $n prints the single process's message once" \
    test "$(grep '^error: ' "$work/sliding-$n.stderr")" = "$(cat "$work/sliding-1.stderr")"
done

# Input errors that only the rank meshing the body meets (each rank meshes its own bodies):
# every rank ends with exit 1 and the single process's one message.
fails_alike() {
  local name=$1 file=$2 pattern=$3
  for n in 1 2 3; do run "$work/$name-$n" "$n" "$file"; done
  check "$name: the single process fails with exit 1 naming the body" \
    sh -c "grep -qx 1 '$work/$name-1.code' && grep -q \"$pattern\" '$work/$name-1.stderr'"
  for n in 2 3; do
    check "$name: -n $n ends with exit 1" grep -qx 1 "$work/$name-$n.code"
    check "$name: -n $n prints the single process's message once" \
      test "$(grep '^error: ' "$work/$name-$n.stderr")" = "$(cat "$work/$name-1.stderr")"
  done
}
# The last block's mesh has no cells.
awk '/^mesh = / { last = NR } { line[NR] = $0 } END { for (i = 1; i <= NR; i++) { if (i == last) sub(/nx = 30/, "nx = 0", line[i]); print line[i] } }' \
  examples/stack.toml >"$work/bad_mesh.toml"
fails_alike bad-mesh "$work/bad_mesh.toml" "body 'b7'"
# A ninth body, last, with neither supports nor contact: only its rank sees that it floats.
cat examples/stack.toml - >"$work/loose.toml" <<'TOML'

[[bodies]]
name = "loose"
material = "steel"
mesh = { kind = "rectangle", x = [3.0, 4.0], y = [0.0, 1.0], nx = 4, ny = 4 }
TOML
fails_alike loose "$work/loose.toml" "loose"

# The paper's sweeps send a rank only its neighbours' values: on the column of 8 blocks over 2
# ranks a sweep brings each rank one block's points (point to point) and 4 checks per body,
# where gathering the sweeps' outputs (2 values per point of the other rank, as before) would
# bring each rank about M values per sweep;
# Anderson's least squares read every point, so it gathers them and sends nothing point to point.
traffic() {
  local name=$1
  shift
  "${mpirun[@]}" -n 2 "$bin" solve examples/stack.toml --out "$work/$name" "$@" >"$work/$name.txt" 2>/dev/null || true
  points=$(($(wc -l <"$work/$name/contact.csv") - 1))
  sweeps=$(($(wc -l <"$work/$name/history.csv") - 1))
  sed -n 's/^ranks: //p' "$work/$name.txt" | tr ';' '\n' |
    sed -n 's/.*received \([0-9]*\) values gathered, \([0-9]*\) point to point.*/\1 \2/p' >"$work/$name.received"
}
traffic paper-traffic --method newton-kurchatov --gamma 0.5 --max-iter 100
check "paper's sweeps: both ranks receive point to point" \
  test "$(awk '$2 > 0' "$work/paper-traffic.received" | wc -l)" = 2
check "paper's sweeps: each rank receives under M/4 values per sweep point to point ($points points, $sweeps sweeps)" \
  test "$(awk -v m="$points" -v k="$sweeps" '$2 < k * m / 4' "$work/paper-traffic.received" | wc -l)" = 2
check "paper's sweeps: each rank receives in all under half of what gathering the sweeps' outputs would" \
  test "$(awk -v m="$points" -v k="$sweeps" '$1 + $2 < k * m / 2' "$work/paper-traffic.received" | wc -l)" = 2
traffic anderson-traffic --accelerator anderson
check "anderson: nothing point to point" \
  test "$(awk '$2 == 0 && $1 > 0' "$work/anderson-traffic.received" | wc -l)" = 2

# The console report (rank 0's) carries every body's applied load and reactions, also those
# of the bodies other ranks hold.
for n in 1 2; do
  if [ "$n" = 1 ]; then "$bin" solve examples/stack.toml --out "$work/report-1" >"$work/report-1.txt"
  else "${mpirun[@]}" -n 2 "$bin" solve examples/stack.toml --out "$work/report-2" >"$work/report-2.txt"; fi
  grep -E '^(applied loads|reactions on)' "$work/report-$n.txt" >"$work/report-$n.lines"
done
check "console report: -n 2 prints the single process's loads and reactions" \
  sh -c "test -s '$work/report-1.lines' && cmp -s '$work/report-1.lines' '$work/report-2.lines'"

# The commands that do not distribute (check, sweep) run on rank 0 alone: their output once, the
# same file, and every rank's exit code theirs (mpirun returns the first non-zero one).
alone() {
  local name=$1
  shift
  local code=0
  "$bin" "$@" >"$work/$name-1.txt" 2>&1 || code=$?
  echo "$code" >"$work/$name-1.code"
  code=0
  "${mpirun[@]}" -n 2 "$bin" "$@" >"$work/$name-2.txt" 2>"$work/$name-2.err" || code=$?
  echo "$code" >"$work/$name-2.code"
}
alone check check examples/stack.toml
check "check: -n 2 prints the single process's description once" cmp -s "$work/check-1.txt" "$work/check-2.txt"
check "check: -n 2 exit code" cmp -s "$work/check-1.code" "$work/check-2.code"
alone sweep sweep examples/notch.toml --gamma 0.5,auto --method active-set --quiet --out "$work/sweep.csv"
check "sweep: -n 2 prints one line naming the CSV" test "$(grep -c '^wrote ' "$work/sweep-2.txt")" = 1
check "sweep: -n 2 exit code" cmp -s "$work/sweep-1.code" "$work/sweep-2.code"
alone check-missing check "$work/no-such-file.toml"
check "check of a missing file: exit 1 on -n 2 as in one process" \
  sh -c "grep -qx 1 '$work/check-missing-1.code' && grep -qx 1 '$work/check-missing-2.code'"
check "check of a missing file: -n 2 says it once" \
  test "$(grep -c '^error: ' "$work/check-missing-2.err")" = 1

# A run that diverges (the paper's neumann rule with γ = 1 on the column): exit 2 everywhere.
same stack-diverges examples/stack.toml --method neumann --gamma 1 --max-iter 50
check "diverging run: the single process exits 2" grep -qx 2 "$work/stack-diverges-1.code"
# A body whose Robin problem turns singular late (it loses all contact): on 3 ranks every body has
# a rank of its own, so the rank that meets it is not the one that reports.
same three-lost examples/three_bodies.toml --method active-set --gamma 1
check "lost contact: the single process exits 2" grep -qx 2 "$work/three-lost-1.code"
for n in 1 2 3; do
  check "lost contact: -n $n names the body" grep -q "body 'upper' lost all contact" "$work/three-lost-$n.stdout"
done

# A results folder nobody can write: every rank ends with exit 1, one message, no hang.
bad=/proc/contactdd-no-such-dir
code=0
"$bin" solve examples/stack.toml --out "$bad" --quiet 2>"$work/unwritable-1.stderr" || code=$?
echo "$code" >"$work/unwritable-1.code"
for n in 2 3; do
  code=0
  timeout 300 "${mpirun[@]}" -n "$n" "$bin" solve examples/stack.toml --out "$bad" --quiet \
    2>"$work/unwritable-$n.stderr" || code=$?
  echo "$code" >"$work/unwritable-$n.code"
done
check "unwritable folder: the message says so" grep -q "cannot write the results" "$work/unwritable-1.stderr"
check "unwritable folder: the single process fails with exit 1" grep -qx 1 "$work/unwritable-1.code"
for n in 2 3; do
  check "unwritable folder: -n $n ends with exit 1" grep -qx 1 "$work/unwritable-$n.code"
  check "unwritable folder: -n $n prints the single process's message once" \
    test "$(grep '^error: ' "$work/unwritable-$n.stderr")" = "$(cat "$work/unwritable-1.stderr")"
done

echo "$passed passed, $fail failed"
[ "$fail" = 0 ]
