#!/usr/bin/env python3
"""Columns of N floating blocks, or walls of N × N, solved by `contactdd solve`: how the cost
grows with the number of bodies (docs/interface-newton.md, "Many bodies").

    cargo build --release -p contactdd-cli
    python3 scripts/columns.py 64 256 1024
    python3 scripts/columns.py --wall 8 16 32                          # 64 to 1024 blocks
    CONTACTDD_BIN=/path/to/contactdd python3 scripts/columns.py 1024   # another build
    python3 scripts/columns.py --monolithic 64 256                     # also the reference

A column's blocks are 2 × 0.25, held sideways on their left edge and free vertically; steel and
aluminium alternate with 8 and 10 cells across, so every interface is non-matching; the bottom
block rests on the floor and the top one is pressed by p = 100. A wall's blocks are 1 × 0.5 with
4 or 5 cells across (neighbours never match), floating in all three rigid modes inside; the
bottom row rests on the floor, the side columns on the walls, and the top row is pressed by
p = 100. Per problem the script prints the iterations, the `iterate` time of summary.json and the
whole run's wall time. With `--monolithic` it also runs `contactdd monolithic` on the same file and
prints its Newton steps, its wall time and the ratio of the two wall times (docs/monolithic.md,
"Many bodies").
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


def wall(n):
    """The problem file of a wall of n × n blocks (TOML text)."""
    s = (f'name = "wall{n}"\nplane = "strain"\n'
         '[materials.a]\nyoung = 2.1e5\npoisson = 0.3\n'
         '[materials.b]\nyoung = 7.0e4\npoisson = 0.33\n')
    w, h = 1.0, 0.5
    for r in range(n):
        for c in range(n):
            supports = []
            if r == 0:
                supports.append('{ boundary = "bottom", component = "y" }')
            if c == 0:
                supports.append('{ boundary = "left", component = "x" }')
            if c == n - 1:
                supports.append('{ boundary = "right", component = "x" }')
            load = ('loads = [{ kind = "pressure", boundary = "top", value = 100.0 }]\n'
                    if r == n - 1 else '')
            s += (f'[[bodies]]\nname = "b{r}_{c}"\nmaterial = "{"ab"[(r + c) % 2]}"\n'
                  f'mesh = {{ kind = "rectangle", x = [{c * w}, {(c + 1) * w}], '
                  f'y = [{r * h}, {(r + 1) * h}], nx = {4 + (r + c) % 2}, ny = 3 }}\n'
                  f'supports = [{", ".join(supports)}]\n{load}')
    for r in range(n):
        for c in range(n):
            for (a, b, sides) in [((r, c + 1), c + 1 < n, '["right", "left"]'),
                                  ((r + 1, c), r + 1 < n, '["top", "bottom"]')]:
                if b:
                    s += (f'[[contact]]\nbodies = ["b{r}_{c}", "b{a[0]}_{a[1]}"]\n'
                          f'boundaries = {sides}\npenalty = {{ c = 0.05, h = 0.5 }}\n')
    return s


def run(command, problem, out):
    """Runs `contactdd COMMAND problem`; returns (summary.json, wall time) or an error line."""
    start = time.perf_counter()
    result = subprocess.run([str(BINARY), command, str(problem), "--quiet", "--out", str(out)],
                            capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    if result.returncode != 0:
        return f"{command} exit {result.returncode}: {result.stderr.strip()}", elapsed
    return json.loads((out / "summary.json").read_text()), elapsed


def main():
    args = sys.argv[1:]
    make = column
    if "--wall" in args:
        args.remove("--wall")
        make = wall
    monolithic = "--monolithic" in args
    if monolithic:
        args.remove("--monolithic")
    with tempfile.TemporaryDirectory() as tmp:
        for n in map(int, args):
            problem = Path(tmp) / f"{make.__name__}{n}.toml"
            problem.write_text(make(n))
            summary, elapsed = run("solve", problem, Path(tmp) / f"out{n}")
            if isinstance(summary, str):
                print(f"{make.__name__} {n}: {summary}")
                continue
            line = (f"{make.__name__} {n}: {summary['iterations']} iterations, iterate "
                    f"{summary['timing_s']['iterate']:.3f} s, run {elapsed:.2f} s")
            if monolithic:
                reference, seconds = run("monolithic", problem, Path(tmp) / f"mono{n}")
                if isinstance(reference, str):
                    line += f"; monolithic {reference}"
                else:
                    line += (f"; monolithic {reference['newton_steps']} steps, run {seconds:.2f} s"
                             f" ({seconds / elapsed:.2f}x solve)")
            print(line, flush=True)


if __name__ == "__main__":
    main()
