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

    python3 scripts/random_walls.py 1 150 --hard --keep /tmp/hard   # the hard family

`--hard` draws another family (problem files hard<seed>.toml): a column of 2 to 6 blocks (held
sideways on their left edge, resting on each other, the bottom one on the floor) or a wall of 2
to 4 rows of 1 to 3 blocks, P1 or P2; every block has its own Young's modulus, log-uniform over
1e3 … 1e9 (a quarter of them at either end: contrasts up to 1e6 between neighbours); each pair's
θ is 1e-3 to 10 times the rod model's (c = 0.05, h = 1), log-uniform; loads scale with the
softest block. Half the seeds have non-matching meshes (each block its own cell size, notched
gaps); the other half share one cell size with every split and height on its grid, so that
neighbours' interface nodes match, and then one block or one whole row may be moved by 1e-10 …
1e-8 of its size along x, along y (a gap or an overlap) or both: near-coincident nodes. Pairs are
balanced, or own-side on a third of the matching columns. Each line names the seed's traits, and
the last line also counts the seeds where the reference converged. Where the decomposition
stops without a summary.json (a refusal before solving), the line quotes its error.
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


def block_supports(r, j, i, blocks, sideways=True):
    """The supports of block i of row j (of `blocks`): the base row on the floor, the first block
    on the left wall, the last one on the right wall half the time (always on the base row) when
    `sideways`; draws from `r` only for a last block, as the families always have."""
    supports = []
    if j == 0:
        supports.append('{ boundary = "bottom", component = "y" }')
    if i == 0:
        supports.append('{ boundary = "left", component = "x" }')
    if sideways and i == blocks - 1 and (r.random() < 0.5 or j == 0):
        supports.append('{ boundary = "right", component = "x" }')
    return supports


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
            supports = block_supports(r, j, i, len(row))
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


def hard(seed):
    """The problem file of one seed of the `--hard` family (TOML text) and a short description."""
    r = random.Random(seed)
    order = r.choice(["p1", "p2"])
    column = r.random() < 0.4
    matching = r.random() < 0.5
    # Own-side pairs balance only node for node: on the matching columns, whose pairs span
    # whole edges (a wall's rows split at different places).
    forces = (r.choice(["balanced", "balanced", "own-side"]) if matching and column
              else "balanced")
    width = r.choice([0.5, 1.0, 2.0]) if column else r.choice([2.0, 4.0])
    # A matching family shares one cell size, with every split and height on its grid.
    across = r.choice([32, 48, 64] if column else [64, 96, 128])
    cell = width / across
    s = f'name = "hard{seed}"\nplane = "strain"\n'
    layout, y = [], 0.0
    for _ in range(r.randint(2, 6) if column else r.randint(2, 4)):
        h = (cell * r.randint(across // 10, across // (2 if column else 4)) if matching
             else r.choice([0.25, 0.5, 1.0]))
        n = 1 if column else r.choice([1, 2, 3])
        cells = round(width / cell)
        cuts = sorted(r.sample(range(2, cells - 1), n - 1)) if matching else sorted(
            r.uniform(0.2, 0.8) * cells for _ in range(n - 1))
        xs = [0.0] + [k * cell for k in cuts] + [width]
        layout.append([[xs[i], xs[i + 1], y, y + h] for i in range(n)])
        y += h
    # Near-coincident meshes: one block, or one whole row, moved by 1e-10 … 1e-8 of its size
    # along the interface (x), across it (y: a gap or an overlap), or both.
    shift = "none"
    if matching:
        shift = r.choice(["none", "block", "row"])
        if shift != "none":
            j = r.randrange(len(layout))
            moved = layout[j] if shift == "row" else [r.choice(layout[j])]
            axes = r.choice(["x", "y", "xy"])
            dx = r.choice([-1, 1]) * 10 ** r.uniform(-10, -8) if "x" in axes else 0.0
            dy = r.choice([-1, 1]) * 10 ** r.uniform(-10, -8) if "y" in axes else 0.0
            for block in moved:
                size = max(block[1] - block[0], block[3] - block[2])
                block[0] += dx * size
                block[1] += dx * size
                block[2] += dy * size
                block[3] += dy * size
            shift = f"{shift} {j} {axes} {max(abs(dx), abs(dy)):.0e}"
    young = {}
    names = {}
    for j, row in enumerate(layout):
        for i, (x0, x1, y0, y1) in enumerate(row):
            name = names[(j, i)] = f"b{j}_{i}"
            # Young's moduli log-uniform over 6 decades, a quarter of them at either end.
            u = r.random() if r.random() < 0.75 else r.choice([0.0, 1.0])
            young[name] = 10 ** (3 + 6 * u)
            s += f"[materials.{name}]\nyoung = {young[name]!r}\npoisson = {r.choice([0.0, 0.2, 0.3, 0.45, 0.49])}\n"
    soft = min(young.values())
    for j, row in enumerate(layout):
        for i, (x0, x1, y0, y1) in enumerate(row):
            name = names[(j, i)]
            size = cell if matching else width / r.choice([32, 48, 64] if column else [64, 96, 128])
            nx, ny = max(2, round((x1 - x0) / size)), max(2, round((y1 - y0) / size))
            supports = block_supports(r, j, i, len(row), sideways=not column)
            loads = []
            p = soft * 10 ** r.uniform(-5, -3)
            if j == len(layout) - 1:
                loads.append(f'{{ kind = "pressure", boundary = "top", value = {p!r} }}')
            if (i == len(row) - 1 and not any('"right"' in x for x in supports)
                    and (not column or r.random() < 0.5)):
                loads.append(f'{{ kind = "pressure", boundary = "right", value = {p / 10!r} }}')
            if r.random() < 0.3:
                loads.append(f'{{ kind = "body-force", value = [0.0, {-p / width!r}] }}')
            s += (f'[[bodies]]\nname = "{name}"\nmaterial = "{name}"\n'
                  f'mesh = {{ kind = "rectangle", x = [{x0!r}, {x1!r}], y = [{y0!r}, {y1!r}], '
                  f'nx = {nx}, ny = {ny}, diagonal = "{r.choice(["right", "left", "alternate"])}", '
                  f'order = "{order}" }}\n'
                  f'supports = [{", ".join(supports)}]\nloads = [{", ".join(loads)}]\n')

    def pair(a, b, side_a, side_b, gap=""):
        # θ from 1e-3 to 10 times the rod model's (c = 0.05, h = 1), log-uniform.
        c = 0.05 * 10 ** r.uniform(-3, 1)
        return (f'[[contact]]\nbodies = ["{a}", "{b}"]\nboundaries = ["{side_a}", "{side_b}"]\n'
                f'penalty = {{ c = {c!r}, h = 1.0 }}\nforces = "{forces}"\n{gap}')

    for j, row in enumerate(layout):
        for i in range(len(row) - 1):
            s += pair(names[(j, i)], names[(j, i + 1)], "right", "left")
        if j + 1 < len(layout):
            for i, (a0, a1, _, _) in enumerate(row):
                for k, (b0, b1, _, _) in enumerate(layout[j + 1]):
                    if min(a1, b1) - max(a0, b0) > 1e-6 * width:
                        gap = ""
                        if not matching and r.random() < 0.3:
                            gap = (f'gap = {{ kind = "notch", r0 = {r.choice([1e-4, 1e-3]) * width}, '
                                   f'b = {width / 4}, centre = {width / 2}, power = 1.5 }}\n')
                        s += pair(names[(j, i)], names[(j + 1, k)], "top", "bottom", gap)
    kind = f"column {len(layout)}" if column else f"wall {len(layout)} rows"
    mesh = "matching" if matching else "non-matching"
    contrast = max(young.values()) / soft
    about = f"{kind}, {order}, {forces}, {mesh}, shift {shift}, contrast {contrast:.0e}"
    return s + "[solver]\ntol = 1e-9\n", about

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


def run(seed, work, enforcement, condensation, friction=(), family=None):
    """Both solves of one seed: exit codes, the decomposition's stop, the difference, failed?

    `family` is `hard` for `--hard` (its problem files are hard<seed>.toml), else the walls."""
    if family is None:
        problem = work / f"wall{seed}.toml"
        text = wall(seed)
    else:
        problem = work / f"hard{seed}.toml"
        text, _ = family(seed)
    problem.write_text(text + (f'condensation = "{condensation}"\n' if condensation else ""))
    codes = []
    for command in ("solve", "monolithic"):
        out = work / f"{command}{seed}"
        result = subprocess.run([str(BINARY), command, str(problem), "--quiet", "--out", str(out),
                                 "--enforcement", enforcement, *friction], capture_output=True,
                                text=True)
        codes.append(result.returncode)
        if command == "solve":
            error = result.stderr.strip().splitlines()
    solve_stop = stop(work / f"solve{seed}") if codes[0] != 0 else ""
    if family is not None and solve_stop == " (no summary.json)" and error:
        solve_stop = f" (no summary.json: {error[-1]})"
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
    family = None
    if "--hard" in args:
        family = hard
        args.remove("--hard")
    first, last = int(args[0]), int(args[1])
    with tempfile.TemporaryDirectory() as tmp:
        work = keep or Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        failures, both, reference = [], 0, 0
        for seed in range(first, last + 1):
            codes, solve_stop, difference, failed = run(seed, work, enforcement, condensation,
                                                        friction, family)
            both += codes == [0, 0]
            reference += codes[1] == 0
            shown = "" if difference is None else f" difference {difference:.1e}"
            about = f" [{family(seed)[1]}]" if family else ""
            print(f"seed {seed}{about}: solve exit {codes[0]}{solve_stop}, monolithic exit "
                  f"{codes[1]}{shown}{'  FAILED' if failed else ''}", flush=True)
            if failed:
                failures.append(seed)
        total = last - first + 1
        converged = f"the reference converged on {reference}, " if family else ""
        print(f"{total} seeds: {converged}both converged on {both}; failed {len(failures)}: "
              f"{failures}")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
