#!/usr/bin/env bash
# Reproduces docs/performance.md: runs the benches, examples and scripts it cites and prints each
# table in the page's markdown form (criterion tables from the medians of
# $CARGO_TARGET_DIR/criterion/<group>/<case>/new/estimates.json; the other commands' own output
# in a text block where the page summarises it). Run it on an idle machine: the whole page takes
# about an hour on 2 cores, most of it the large benches and the MPI runs.
#
#   bash scripts/performance.sh                 every section
#   bash scripts/performance.sh core ddm        some sections
#   bash scripts/performance.sh --tables ddm    print the tables of the last criterion runs only
#
# Sections: core ddm iterations monolithic large columns condensation long-zone mpi
set -euo pipefail
cd "$(dirname "$0")/.."
target=${CARGO_TARGET_DIR:-target}
bin=${CONTACTDD_BIN:-$target/release/contactdd}   # CONTACTDD_BIN: another build

run_benches=1
if [ "${1:-}" = --tables ]; then
  run_benches=0
  shift
fi
all=(core ddm iterations monolithic large columns condensation long-zone mpi)
sections=("$@")
if [ ${#sections[@]} = 0 ]; then sections=("${all[@]}"); fi

# Prints the markdown table of one criterion section from the stored medians.
tables() {
  python3 - "$target/criterion" "$1" <<'EOF'
import json, os, re, sys

root, section = sys.argv[1], sys.argv[2]
medians = {}
for d, _, files in os.walk(root):
    if os.path.basename(d) == "new" and "benchmark.json" in files and "estimates.json" in files:
        full_id = json.load(open(os.path.join(d, "benchmark.json")))["full_id"]
        medians[full_id] = json.load(open(os.path.join(d, "estimates.json")))["median"]["point_estimate"]


def t(full_id):
    """The median of one case with 3 significant digits, or '—' when it was not run."""
    ns = medians.get(full_id)
    if ns is None:
        return "—"
    for scale, unit in ((1e9, "s"), (1e6, "ms"), (1e3, "µs"), (1.0, "ns")):
        if ns >= scale:
            return f"{ns / scale:.3g} {unit}"
    return f"{ns:.3g} ns"


def sci(x):
    """x as 8e−9 or 1.0e4."""
    x = float(x)
    text = f"{x:.1e}" if x >= 1 else f"{x:.0e}"
    return re.sub(r"e([+-])0*(\d)", lambda m: "e" + ("−" if m.group(1) == "-" else "") + m.group(2), text)


def rows(header, body):
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for row in body:
        print("| " + " | ".join(row) + " |")
    print()


def ids(pattern):
    """The stored ids matching pattern, in numeric order of their last component."""
    found = [i for i in medians if re.fullmatch(pattern, i)]
    return sorted(found, key=lambda i: float(i.rsplit("/", 1)[1]))


if section == "core":
    dofs = sorted({int(m.group(1)) for i in medians for m in [re.match(r"core/(\d+)dofs/", i)] if m})
    phases = ["assembly", "symbolic", "numeric", "solve", "faer_symbolic", "faer_numeric", "faer_solve"]
    rows(["DOFs"] + [p.replace("_", " ") for p in phases],
         [[sci(n)] + [t(f"core/{n}dofs/{p}/{n}") for p in phases] for n in dofs])
elif section == "ddm":
    rows(["what", "median"], [
        ["notch: prepare (assembly, factorisation, condensation)", t("notch/prepare")],
        ["notch: one iteration", t("notch/one_iteration")],
        ["notch: solve after setup, active-set γ = 0.5 / newton-chord γ = 0.3 / newton-kurchatov γ = 0.5",
         " / ".join(t(f"notch/solve/{m}") for m in ("active-set", "newton-chord", "newton-kurchatov"))],
        ["notch: γ sweep, 45 runs (3 methods × 15 γ)", t("notch/sweep_45_runs")],
        ["8-body stack, prepare + solve, 1 / 2 threads",
         " / ".join(t(f"stack8/prepare_and_solve/{n}") for n in (1, 2))],
        ["contact search, m = 1000 / 2000 / 4000 points per side",
         " / ".join(t(f"contact_search/interface/{m}") for m in (1000, 2000, 4000))],
    ])
    rows(["column of N floating blocks, solve after setup", "interface Newton", "two-level sweeps", "one-level"],
         [[f"N = {n}", t(f"column/newton_solve/{n}"), t(f"column/two_level_solve/{n}"),
           t(f"column/one_level_solve/{n}")] for n in (8, 64)])
    rows(["`examples/hertz.toml`, interface Newton, tol 1e−9", "median"],
         [[f"θ = {sci(i.rsplit('/', 1)[1])}", t(i)] for i in ids(r"hertz/newton_solve/.*")])
elif section == "condensation":
    rows(["case", "median"],
         [["paper's notch, " + p, t(f"condensation/notch/{p}")] for p in ("dense", "sparse", "auto")]
         + [[f"long strip, m = {nx + 1}", t(f"condensation/long_strip/{nx}")] for nx in (1000, 2000, 4000)]
         + [["compact 368 × 184", t("condensation/compact_368x184")]])
    long, compact = medians.get("condensation/long_strip/4000"), medians.get("condensation/compact_368x184")
    if long and compact:
        print(f"Long (m = 4001) against compact: {long / compact:.2f}\n")
EOF
}

# Runs a command, printing it and its output as a text block.
block() {
  echo '```text'
  echo "\$ $*"
  "$@" 2>&1 || echo "(exit $?)"
  echo '```'
  echo
}

build() {
  if [ -z "${CONTACTDD_BIN:-}" ]; then cargo build --release -q -p contactdd-cli; fi
}

for section in "${sections[@]}"; do
  echo "## $section"
  echo
  case "$section" in
  core)
    if [ $run_benches = 1 ]; then
      CONTACTDD_BENCH_LARGE=1 cargo bench -q --bench core >&2
    fi
    tables core
    if [ $run_benches = 1 ]; then
      cargo build --release -q --example core_phases
      block /usr/bin/time -f "peak %M KB" "$target/release/examples/core_phases"
    fi
    ;;
  ddm)
    if [ $run_benches = 1 ]; then
      cargo bench -q --bench ddm -- "^(notch|stack8|column|hertz|contact_search)/" >&2
    fi
    tables ddm
    ;;
  condensation)
    if [ $run_benches = 1 ]; then
      CONTACTDD_BENCH_LARGE=1 cargo bench -q --bench ddm -- "^condensation/" >&2
    fi
    tables condensation
    [ $run_benches = 1 ] || continue
    echo "Whole runs, \`bash scripts/condensation.sh PATH NXxNY ...\`:"
    echo
    block bash scripts/condensation.sh auto 1000x16 2000x16 4000x16 8000x16 368x184
    block bash scripts/condensation.sh dense 1000x16 2000x16 4000x16 368x184
    block bash scripts/condensation.sh sparse 1000x16 368x184
    ;;
  iterations)
    [ $run_benches = 1 ] || continue
    block cargo run --release -q --example iteration_counts
    ;;
  monolithic)
    [ $run_benches = 1 ] || continue
    build
    work=$(mktemp -d)
    echo "| file | monolithic steps | monolithic | solve |"
    echo "|---|---|---|---|"
    for f in notch stack three_bodies hertz; do
      m=$( { /usr/bin/time -f "%e %M" "$bin" monolithic "examples/$f.toml" --quiet --out "$work/m" >/dev/null; } 2>&1 | tail -1)
      s=$( { /usr/bin/time -f "%e %M" "$bin" solve "examples/$f.toml" --quiet --out "$work/s" >/dev/null; } 2>&1 | tail -1)
      python3 - "$f" "$m" "$s" "$work/m/summary.json" "$work/s/summary.json" <<'EOF'
import json, sys
name, m, s = sys.argv[1:4]
(mt, mk), (st, sk) = m.split(), s.split()
steps = json.load(open(sys.argv[4]))["newton_steps"]
its = json.load(open(sys.argv[5]))["iterations"]
print(f"| `examples/{name}.toml` | {steps} | {float(mt):.2f} s, {int(mk) / 1e6:.2f} GB "
      f"| {float(st):.2f} s, {int(sk) / 1e6:.2f} GB ({its} iteration{'s' if its != 1 else ''}) |")
EOF
    done
    rm -rf "$work"
    echo
    ;;
  large)
    [ $run_benches = 1 ] || continue
    for run in 1 2 3; do
      block cargo run --release -q --example large_two_bodies
    done
    ;;
  columns)
    [ $run_benches = 1 ] || continue
    build
    block python3 scripts/columns.py 64 256 1024 2048
    block python3 scripts/columns.py --wall 8 16 32
    ;;
  long-zone)
    [ $run_benches = 1 ] || continue
    block env SOLVE_ARGS="--enforcement augmented --tol 1e-8" bash scripts/long_zone.sh 2000 4000
    ;;
  mpi)
    [ $run_benches = 1 ] || continue
    if [ -x "$target/mpi/contactdd" ]; then
      block bash scripts/bench_mpi.sh
    else
      echo "(no $target/mpi/contactdd: run \`bash scripts/test_mpi.sh\` first)"
      echo
    fi
    ;;
  *)
    echo "unknown section '$section'; sections: ${all[*]}" >&2
    exit 1
    ;;
  esac
done
