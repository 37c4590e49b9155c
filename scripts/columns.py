#!/usr/bin/env python3
"""Columns of N floating blocks, solved by `contactdd solve`: how the cost grows with the number
of bodies (docs/interface-newton.md, "Many bodies").

    cargo build --release -p contactdd-cli
    python3 scripts/columns.py 64 256 1024
    CONTACTDD_BIN=/path/to/contactdd python3 scripts/columns.py 1024   # another build

Each block is 2 × 0.25, held sideways on its left edge and free vertically; steel and
aluminium alternate with 8 and 10 cells across, so every interface is non-matching; the bottom
block rests on the floor and the top one is pressed by p = 100. Per N the script prints the
iterations, the `iterate` time of summary.json and the whole run's wall time.
"""
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

BINARY = os.environ.get("CONTACTDD_BIN") or (
    Path(__file__).resolve().parent.parent / "target" / "release" / "contactdd")


def column(n):
    """The problem file of a column of n blocks (TOML text)."""
    s = (f'name = "column{n}"\nplane = "strain"\n'
         '[materials.a]\nyoung = 2.1e5\npoisson = 0.3\n'
         '[materials.b]\nyoung = 7.0e4\npoisson = 0.33\n')
    h = 0.25
    for i in range(n):
        supports = '{ boundary = "left", component = "normal" }'
        if i == 0:
            supports += ', { boundary = "bottom", component = "normal" }'
        load = ('loads = [{ kind = "pressure", boundary = "top", value = 100.0 }]\n'
                if i == n - 1 else '')
        s += (f'[[bodies]]\nname = "b{i}"\nmaterial = "{"ab"[i % 2]}"\n'
              f'mesh = {{ kind = "rectangle", x = [0.0, 2.0], y = [{i * h}, {(i + 1) * h}], '
              f'nx = {8 + 2 * (i % 2)}, ny = 3 }}\nsupports = [{supports}]\n{load}')
    for i in range(n - 1):
        s += (f'[[contact]]\nbodies = ["b{i}", "b{i + 1}"]\nboundaries = ["top", "bottom"]\n'
              'penalty = { c = 0.05, h = 0.25 }\n')
    return s


def main():
    with tempfile.TemporaryDirectory() as tmp:
        for n in map(int, sys.argv[1:]):
            problem = Path(tmp) / f"column{n}.toml"
            problem.write_text(column(n))
            out = Path(tmp) / f"out{n}"
            start = time.perf_counter()
            result = subprocess.run([str(BINARY), "solve", str(problem), "--quiet", "--out", str(out)],
                                    capture_output=True, text=True)
            wall = time.perf_counter() - start
            if result.returncode != 0:
                print(f"N = {n}: exit {result.returncode}: {result.stderr.strip()}")
                continue
            summary = json.loads((out / "summary.json").read_text())
            print(f"N = {n}: {summary['iterations']} iterations, iterate "
                  f"{summary['timing_s']['iterate']:.3f} s, run {wall:.2f} s", flush=True)


if __name__ == "__main__":
    main()
