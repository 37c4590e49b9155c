#!/usr/bin/env python3
"""contactdd in space against a SciPy + CHOLMOD monolithic Newton method on the same discrete
problem: wall time and agreement.

For each problem file in space (default: examples/space/sphere_block.toml, Hertz), the script
takes contactdd's discrete problem from `contactdd.space.system` (every body's stiffness matrix,
loads and prescribed DOFs, the contact points' dual mortar rows a_j, gaps d_j, weights w_j and
penalties θ) and solves it twice:

  contactdd  `contactdd.space.solve(problem)`: the whole solve (contact geometry, assembly,
             factorisation of every body, the Newton iteration on the contact points, recovery
             of the fields, the independent force balance);
  cholmod    this script: the coupled system of all bodies, K + Σ_{closed} (w_j/θ) a_j a_jᵀ,
             with the prescribed DOFs eliminated, solved by a semismooth Newton method (a primal
             active set, closing the points with a_j·u > d_j until the set repeats) from the
             points with d_j ≤ 0, factorised by CHOLMOD (scikit-sparse; one symbolic analysis
             with every point's springs in the pattern, one numeric factorisation per step).
             Its time starts from contactdd's matrices: assembly and contact geometry are not
             counted.

The two run interleaved, `--repeat` rounds; the table gives each one's median time and the median
over the rounds of cholmod's time over contactdd's in the same round. The pressures must agree
within 1e-8 of the peak (exit 1 otherwise). Bodies that only contact holds are left to
contactdd: the cholmod Newton method starts from d_j ≤ 0 and needs every body held by its
supports.

Install (Debian 12): see scripts/peers.py for scikit-sparse; then `pip install ./python` into the
same venv. Run:

    /tmp/venv-peers/bin/python scripts/peers_space.py [files…] --repeat 5
"""

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp
from sksparse.cholmod import analyze

from contactdd import space

REPO = Path(__file__).resolve().parent.parent
TOL = 1e-8


def coupled(system):
    """The coupled stiffness, loads and prescribed DOFs of every body."""
    blocks, loads, fixed, values = [], [], [], []
    for at, body in zip(system["offsets"], system["bodies"]):
        data, indices, indptr = body["stiffness"]
        n = len(indptr) - 1
        blocks.append(sp.csc_matrix((data, indices, indptr), shape=(n, n)))
        loads.append(body["load"])
        fixed.append(at + body["prescribed_dofs"])
        values.append(body["prescribed_values"])
    k = sp.block_diag(blocks, format="csc")
    return k, np.concatenate(loads), np.concatenate(fixed), np.concatenate(values)


def cholmod_newton(system):
    """Pressures and Newton steps of the semismooth Newton method on the coupled system."""
    k, f, fixed, values = coupled(system)
    n = system["dofs"]
    rows = system["rows"]
    if rows["exact"].any():
        sys.exit("peers_space.py compares penalty contact; the problem has augmented pairs")
    a = sp.csr_matrix((rows["data"], rows["indices"], rows["indptr"]), shape=(len(rows["gap"]), n))
    gap, spring = rows["gap"], rows["weight"] / rows["theta"]
    free = np.setdiff1d(np.arange(n), fixed)
    u = np.zeros(n)
    u[fixed] = values
    af, ap = a[:, free].tocsc(), a[:, fixed].tocsc()
    kff, kfp = k[free][:, free], k[free][:, fixed]
    # One analysis with every point's springs in the pattern.
    factor = analyze((kff + af.T @ sp.diags(spring) @ af).tocsc())
    closed = gap <= 0
    for step in range(1, 61):
        d = sp.diags(spring * closed)
        m = (kff + af.T @ d @ af).tocsc()
        rhs = f[free] - kfp @ values + af.T @ (spring * closed * (gap - ap @ values))
        factor.cholesky_inplace(m)
        u[free] = factor(rhs)
        s = a @ u
        nxt = s > gap
        if np.array_equal(nxt, closed):
            return np.maximum(s - gap, 0.0) / rows["theta"], step
        closed = nxt
    raise RuntimeError("the closed set did not settle")


def run(path, repeat):
    problem = space.Problem.from_toml(path)
    ours, theirs, ratios = [], [], []
    for _ in range(repeat):
        t = time.perf_counter()
        result = space.solve(problem)
        ours.append(time.perf_counter() - t)
        system = space.system(problem)
        t = time.perf_counter()
        pressure, steps = cholmod_newton(system)
        theirs.append(time.perf_counter() - t)
        ratios.append(theirs[-1] / ours[-1])
    mine = result.contact["pressure"]
    peak = float(np.max(mine))
    worst = float(np.max(np.abs(pressure - mine))) / peak
    dofs = system["dofs"]
    print(f"\n## {Path(path).name} ({dofs} DOFs, {len(mine)} contact points)\n")
    print("| code | median wall s | ratio to contactdd | Newton steps |")
    print("|---|---|---|---|")
    print(f"| contactdd | {statistics.median(ours):.3f} | 1.00 | {result.newton_steps} |")
    print(f"| cholmod | {statistics.median(theirs):.3f} | {statistics.median(ratios):.2f} | {steps} |")
    print(f"\nlargest pressure difference, relative to the peak ({peak:.6g}): {worst:.1e} (TOL {TOL:g})")
    return worst <= TOL


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("files", nargs="*", default=[str(REPO / "examples/space/sphere_block.toml")])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    ok = all([run(f, args.repeat) for f in args.files])
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
