#!/usr/bin/env bash
# Checks that the command line behaves as it did at a reference git revision: runs `contactdd
# solve` on every examples/*.toml and the paper's γ sweep with both the reference build and the
# working tree's build, and compares the outputs byte for byte (summary.json without its timings,
# contact.csv, history.csv, results.pvd, the sweep CSV), the output of `contactdd check` and the
# exit codes. Keys that only the working tree's summary.json has (new outputs) are named and left
# out of the comparison; every other key must match. The VTU files are compared by their numbers,
# not their encoding: scripts/vtu_decode.py turns each (ASCII, binary or zlib) into its elements,
# attributes and values (floats as their 64 bits), which must then match exactly.
#
# Usage: bash scripts/same_outputs.sh [REV]      (REV defaults to main)
#
# The reference is built from a temporary `git worktree` of REV into its own target folder
# (target/same-outputs/target, kept between runs; its first build compiles every dependency), and
# its binary is cached per commit, so later runs against the same revision only rebuild this tree.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

rev=${1:-main}
sha=$(git rev-parse --verify "$rev^{commit}")
work="$root/target/same-outputs"
# This tree's own build honours CARGO_TARGET_DIR.
own_target=${CARGO_TARGET_DIR:-$root/target}
ref_bin="$work/bin-$sha/contactdd"
mkdir -p "$work"

out=$(mktemp -d)
src="$work/src-$sha"
cleanup() {
  rm -rf "$out"
  if [ -d "$src" ]; then git -C "$root" worktree remove --force "$src"; fi
}
trap cleanup EXIT

if [ ! -x "$ref_bin" ]; then
  git worktree add --detach --force "$src" "$sha" >/dev/null
  if [ ! -d "$work/target" ] && [ -d "$own_target/release/deps" ]; then
    # Seed with this tree's compiled dependencies: the same registry crates need no rebuild.
    mkdir -p "$work/target"
    cp -a "$own_target/release" "$work/target/release"
  fi
  echo "== building the reference ($rev = ${sha:0:12})"
  cargo build --release --quiet -p contactdd-cli --manifest-path "$src/Cargo.toml" \
    --target-dir "$work/target"
  mkdir -p "$(dirname "$ref_bin")"
  cp "$work/target/release/contactdd" "$ref_bin"
  # The worktree only lives for this build; the cached binary is what later runs reuse.
  git -C "$root" worktree remove --force "$src"
fi

echo "== building the working tree"
cargo build --release --quiet -p contactdd-cli
new_bin="$own_target/release/contactdd"

# Runs every case with binary $2 into folder $1; records the exit codes in $1/exit-codes.
run_all() {
  local dir=$1 bin=$2 code
  mkdir -p "$dir"
  : >"$dir/exit-codes"
  for file in examples/*.toml; do
    local name
    name=$(basename "$file" .toml)
    code=0
    "$bin" solve "$file" --out "$dir/$name" --quiet >/dev/null || code=$?
    echo "solve $name: $code" >>"$dir/exit-codes"
    code=0
    "$bin" check "$file" >"$dir/$name.check.txt" || code=$?
    echo "check $name: $code" >>"$dir/exit-codes"
    if [ -f "$dir/$name/summary.json" ]; then
      # Timings differ from run to run: drop the "timing_s" object of the pretty-printed JSON.
      awk '/^  "timing_s": \{/ { skip = 1 } !skip { print } skip && /^  \},?$/ { skip = 0 }' \
        "$dir/$name/summary.json" >"$dir/$name/summary.no-timing.json"
      rm "$dir/$name/summary.json"
    fi
  done
  code=0
  "$bin" sweep examples/notch.toml --method active-set,newton-chord,newton-kurchatov \
    --gamma 0.05:0.85:0.05 --out "$dir/notch-sweep.csv" >/dev/null || code=$?
  echo "sweep notch: $code" >>"$dir/exit-codes"
}

echo "== running the reference"
run_all "$out/reference" "$ref_bin"
echo "== running the working tree"
run_all "$out/current" "$new_bin"
python3 scripts/vtu_decode.py "$out/reference" "$out/current"

# A key that the reference's summary.json lacks is new output, not a changed answer: it is
# dropped from the current summary (and named), so that every key both have must match byte for
# byte.
added=$(python3 - "$out/reference" "$out/current" <<'PY'
import json, pathlib, sys
ref, cur = map(pathlib.Path, sys.argv[1:3])
added = set()
for new in cur.glob("*/summary.no-timing.json"):
    old = ref / new.relative_to(cur)
    if not old.is_file():
        continue
    a, b = json.loads(old.read_text()), json.loads(new.read_text())
    extra = [k for k in b if k not in a]
    if extra:
        added.update(extra)
        for k in extra:
            del b[k]
        new.write_text(json.dumps(b, indent=2) + "\n")
        old.write_text(json.dumps(a, indent=2) + "\n")
print(" ".join(sorted(added)))
PY
)
files=$(find "$out/reference" -type f | wc -l)
if diff -r "$out/reference" "$out/current"; then
  echo "same outputs: $files files identical to $rev (${sha:0:12}) (VTU files by their values), timings ignored${added:+, new summary keys ignored: $added}"
else
  echo "outputs differ from $rev (${sha:0:12})" >&2
  exit 1
fi
