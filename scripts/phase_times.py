#!/usr/bin/env python3
"""Compares the phase times of two contactdd binaries on problem files, from summary.json's
`timing_s` (medians of 5 runs each, alternating):

    python3 scripts/phase_times.py REF_BINARY NEW_BINARY examples/hertz.toml ...

Prints, per problem, each binary's median `post` (stresses, contact results and the force
balance) and the median sum of the phases (contact setup, setup of the bodies, iteration,
recovery, post), and the ratio of those sums."""

import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

PHASES = ("contact_setup", "assemble_factor_condense", "iterate", "recover", "post")
RUNS = 5


def times(binary, problem, out):
    subprocess.run([binary, "solve", problem, "--out", str(out), "-q"], capture_output=True)
    t = json.loads((out / "summary.json").read_text())["timing_s"]
    return t["post"], sum(t[p] for p in PHASES)


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    ref, new, problems = sys.argv[1], sys.argv[2], sys.argv[3:]
    with tempfile.TemporaryDirectory() as tmp:
        for problem in problems:
            runs = {"ref": [], "new": []}
            for _ in range(RUNS):
                for name, binary in (("ref", ref), ("new", new)):
                    runs[name].append(times(binary, problem, Path(tmp) / name))
            med = {k: [statistics.median(x) for x in zip(*v)] for k, v in runs.items()}
            print(
                f"{problem}: post {med['ref'][0]:.3f} -> {med['new'][0]:.3f} s, "
                f"phases {med['ref'][1]:.3f} -> {med['new'][1]:.3f} s "
                f"(ratio {med['new'][1] / med['ref'][1]:.3f})"
            )


if __name__ == "__main__":
    main()
