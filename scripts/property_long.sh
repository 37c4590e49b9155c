#!/usr/bin/env bash
# The long budget of the property test on random multi-body problems (tests/property.rs): runs
# N cases (default 10000) and prints the summary line, the outcome table and every failed case.
# A failed case is rerun alone, with its problem file printed, by
#
#   CONTACTDD_PROPERTY_CASE=k cargo test --release --test property -- --nocapture
#
#   bash scripts/property_long.sh [N]
#
# Exits 1 if a case failed (a converged result out of balance, a panic, a hang, a refusal
# without a clear message).
set -uo pipefail
cd "$(dirname "$0")/.."
cases="${1:-10000}"
log=$(mktemp)
trap 'rm -f "$log"' EXIT
CONTACTDD_PROPERTY_CASES="$cases" cargo test --release -q --test property -- --nocapture \
  >"$log" 2>&1
status=$?
grep -E '^(FAILED case|property:|\|)' "$log" || { cat "$log"; exit 1; }
[ "$status" -eq 0 ] || exit 1
