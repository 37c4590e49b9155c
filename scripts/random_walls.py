#!/usr/bin/env python3
"""Random walls of elastic blocks, solved by the default decomposition and by the monolithic
reference, seed by seed: a held-out family of hard cases (many bodies, non-matching meshes,
material contrast up to 1000, stiff and soft penalties, P1 and P2, balanced and own-side pairs,
floating blocks held only by contact, notched gaps).

    cargo build --release -p contactdd-cli
    python3 scripts/random_walls.py 1 400               # seeds 1 … 400, penalty contact
    python3 scripts/random_walls.py 1 50 --keep /tmp/w  # keep the problem files and results
    CONTACTDD_BIN=/path/to/contactdd python3 scripts/random_walls.py 1 400   # another build
    python3 scripts/random_walls.py 1 100 --condensation sparse    # every block on the sparse path
    python3 scripts/random_walls.py 1 200 --friction coulomb:0.3   # Coulomb friction on every pair

A seed's wall has 2 to 4 rows of 1 to 3 blocks on a clamped base row; each block has its own
mesh size, diagonal and material, the last block of a row is pushed sideways or held, and the
top row is pressed down. Per seed the script prints both exit codes and, where both converged,
the largest difference of the contact pressures relative to the peak. A seed counts as failed
when the decomposition does not converge while the reference does, or when the two disagree by
more than 1e-6 of the peak (both solve with tol 1e-9; with `--enforcement augmented`, 1e-3, as
each meets the exact contact only to its gap tolerance). Where the decomposition does not
converge, the line names its stop from summary.json (diverged, stalled, unenforced, or
unbalanced: converged, but a body's loads, contact forces and reactions do not balance), and an
unbalanced stop adds the worst body's imbalance and rounding floor.
"""
import csv
import json
import random
import subprocess
import sys
import tempfile
from pathlib import Path

import os

# The binary to test: CONTACTDD_BIN, or this checkout's release build.
BINARY = os.environ.get("CONTACTDD_BIN") or (
    Path(__file__).resolve().parent.parent / "target" / "release" / "contactdd")


def wall(seed):
    """The problem file of one seed (TOML text)."""
    r = random.Random(seed)
    rows = r.randint(1, 3) + 1
    c = r.choice([0.5, 0.05, 5e-3, 5e-4])
    forces = r.choice(["balanced", "own-side"])
    enforcement = r.choice(["penalty", "penalty", "augmented"])
    order = r.choice(["p1", "p1", "p2"])
    width = r.choice([2.0, 4.0, 8.0])
    s = f'name = "wall{seed}"\nplane = "strain"\n'
    for k in range(3):
        s += (f"[materials.m{k}]\nyoung = {r.choice([1e3, 1e4, 2.1e5, 1e6])}\n"
              f"poisson = {r.choice([0.2, 0.3, 0.45])}\n")
    layout, y = [], 0.0
    for _ in range(rows):
        h = r.choice([0.5, 1.0, 2.0])
        n = r.choice([1, 1, 2, 3])
        xs = [0.0] + sorted(r.uniform(0.2, 0.8) * width for _ in range(n - 1)) + [width]
        layout.append([(xs[i], xs[i + 1], y, y + h) for i in range(n)])
        y += h
    names = {}
    for j, row in enumerate(layout):
        for i, (x0, x1, y0, y1) in enumerate(row):
            name = names[(j, i)] = f"b{j}_{i}"
            cell = r.choice([0.05, 0.1, 0.13, 0.2])
            nx, ny = max(2, round((x1 - x0) / cell)), max(2, round((y1 - y0) / cell))
            supports = []
            if j == 0:
                supports.append('{ boundary = "bottom", component = "y" }')
            if i == 0:
                supports.append('{ boundary = "left", component = "x" }')
            if i == len(row) - 1 and (r.random() < 0.5 or j == 0):
                supports.append('{ boundary = "right", component = "x" }')
            loads = []
            if j == rows - 1:
                loads.append(f'{{ kind = "pressure", boundary = "top", value = {r.choice([1.0, 10.0, 100.0])} }}')
            if i == len(row) - 1 and not any('"right"' in x for x in supports):
                loads.append(f'{{ kind = "pressure", boundary = "right", value = {r.choice([1.0, 10.0])} }}')
            if r.random() < 0.3:
                loads.append(f'{{ kind = "body-force", value = [0.0, {-r.choice([0.1, 1.0])}] }}')
            diagonal = r.choice(["right", "left", "alternate"])
            s += (f'[[bodies]]\nname = "{name}"\nmaterial = "m{r.randint(0, 2)}"\n'
                  f'mesh = {{ kind = "rectangle", x = [{x0}, {x1}], y = [{y0}, {y1}], nx = {nx}, '
                  f'ny = {ny}, diagonal = "{diagonal}", order = "{order}" }}\n'
                  f'supports = [{", ".join(supports)}]\nloads = [{", ".join(loads)}]\n')

    def pair(a, b, side_a, side_b, gap=""):
        return (f'[[contact]]\nbodies = ["{a}", "{b}"]\nboundaries = ["{side_a}", "{side_b}"]\n'
                f'penalty = {{ c = {c}, h = 1.0 }}\nforces = "{forces}"\n'
                f'enforcement = "{enforcement}"\n{gap}')

    for j, row in enumerate(layout):
        for i in range(len(row) - 1):
            s += pair(names[(j, i)], names[(j, i + 1)], "right", "left")
        if j + 1 < rows:
            for i, (a0, a1, _, _) in enumerate(row):
                for k, (b0, b1, _, _) in enumerate(layout[j + 1]):
                    if min(a1, b1) - max(a0, b0) > 1e-9:
                        gap = ""
                        if r.random() < 0.4:
                            gap = (f'gap = {{ kind = "notch", r0 = {r.choice([1e-4, 1e-3])}, '
                                   f'b = {width / 4}, centre = {width / 2}, power = 1.5 }}\n')
                        s += pair(names[(j, i)], names[(j + 1, k)], "top", "bottom", gap)
    return s + "[solver]\ntol = 1e-9\n"


def pressures(path):
    """Contact pressure per (pair, body, point) of a contact.csv."""
    with open(path) as f:
        return {(row["pair"], row["body"], round(float(row["x"]), 9), round(float(row["y"]), 9)):
                float(row["pressure"]) for row in csv.DictReader(f)}


def stop(out):
    """How the decomposition's solve in `out` ended, from its summary.json ("" if converged)."""
    try:
        summary = json.loads((out / "summary.json").read_text())
    except (OSError, ValueError):
        return " (no summary.json)"
    if summary.get("converged"):
        return ""
    shown = f" ({summary.get('stop')}"
    balance = summary.get("balance") or {}
    if summary.get("stop") == "unbalanced" and balance.get("bodies"):
        worst = max(balance["bodies"], key=lambda body: body["imbalance"] or 0.0)
        shown += f": imbalance {worst['imbalance']:.1e}, floor {worst['floor']:.1e}"
        shown += f", loads {balance.get('loads') or 0.0:.1e}"
    return shown + ")"


def run(seed, work, enforcement, condensation, friction=()):
    problem = work / f"wall{seed}.toml"
    problem.write_text(wall(seed) + (f'condensation = "{condensation}"\n' if condensation else ""))
    codes = []
    for command in ("solve", "monolithic"):
        out = work / f"{command}{seed}"
        result = subprocess.run([str(BINARY), command, str(problem), "--quiet", "--out", str(out),
                                 "--enforcement", enforcement, *friction], capture_output=True,
                                text=True)
        codes.append(result.returncode)
    solve_stop = stop(work / f"solve{seed}") if codes[0] != 0 else ""
    difference = None
    if codes == [0, 0]:
        a, b = pressures(work / f"solve{seed}/contact.csv"), pressures(work / f"monolithic{seed}/contact.csv")
        peak = max((abs(v) for v in b.values()), default=0.0) or 1.0
        difference = max((abs(a[k] - b[k]) for k in b), default=0.0) / peak if a.keys() == b.keys() else float("inf")
    # Exact contact is met to a gap tolerance, which leaves each solver's pressures that far off.
    limit = 1e-6 if enforcement == "penalty" else 1e-3
    failed = (codes[0] != 0 and codes[1] == 0) or (difference is not None and difference > limit)
    return codes, solve_stop, difference, failed


def main():
    args = sys.argv[1:]
    keep = None
    enforcement = "penalty"
    if "--keep" in args:
        keep = Path(args.pop(args.index("--keep") + 1))
        args.remove("--keep")
    if "--enforcement" in args:
        enforcement = args.pop(args.index("--enforcement") + 1)
        args.remove("--enforcement")
    condensation = None
    if "--condensation" in args:
        condensation = args.pop(args.index("--condensation") + 1)
        args.remove("--condensation")
    friction = ()
    if "--friction" in args:
        friction = ("--friction", args.pop(args.index("--friction") + 1))
        args.remove("--friction")
    first, last = int(args[0]), int(args[1])
    with tempfile.TemporaryDirectory() as tmp:
        work = keep or Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        failures, both = [], 0
        for seed in range(first, last + 1):
            codes, solve_stop, difference, failed = run(seed, work, enforcement, condensation,
                                                        friction)
            both += codes == [0, 0]
            shown = "" if difference is None else f" difference {difference:.1e}"
            print(f"seed {seed}: solve exit {codes[0]}{solve_stop}, monolithic exit {codes[1]}{shown}"
                  f"{'  FAILED' if failed else ''}", flush=True)
            if failed:
                failures.append(seed)
        total = last - first + 1
        print(f"{total} seeds: both converged on {both}; failed {len(failures)}: {failures}")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
