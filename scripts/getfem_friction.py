#!/usr/bin/env python3
"""contactdd against GetFEM on a block pressed on a foundation and pushed sideways.

Both codes solve the same discrete problem: the same P1 triangles (nodes and diagonals), the
same consistent loads, node-to-node contact on meshes that match along the contact line, and
Coulomb's law at every contact node in one step from the unloaded state, exactly (contactdd's
augmented Lagrangian, GetFEM's Alart–Curnier augmented Lagrangian with Lagrange multipliers:
no penalty enters either answer). Two cases:

  friction      the block floats: a pressure p on its top presses it (N = 2p), a traction q on
                its left side pushes it (Q = q); Coulomb μ = 0.3 holds it with part of the base
                slipping (Q/μN = 0.67);
  frictionless  μ = 0, the push removed and the block's left side on rollers (u_x = 0): the
                same contact without friction, which separates friction from the contact
                discretisation.

GetFEM: `add_nodal_contact_between_nonmatching_meshes_brick` (block bottom slave, foundation top
master), whose multipliers are the nodal contact forces. contactdd: `contactdd solve` on a TOML
this script writes, `enforcement = "augmented"`, tight stopping tolerances. The script compares
the resultant forces, the stick and slip lengths, the pressure and tangential traction along the
base (nodal forces over the block's trapezoid weights), the block's horizontal displacement
(mean u_x of its top nodes) and the times, and exits 1 when they disagree beyond the tolerance
(TOL below). `--enforcement penalty` runs contactdd with the regularised law instead, a different
discrete problem: the comparison then shows the penalty's share of the answer, and fails.

Run:  /usr/bin/python3 scripts/getfem_friction.py   (GetFEM: apt-get install python3-getfem;
      the contactdd binary: CONTACTDD_BIN, else $CARGO_TARGET_DIR/release/contactdd, else
      target/release/contactdd)
"""

import contextlib
import json
import os
import subprocess
import sys
import tempfile
import time

try:
    import numpy as np
    import getfem as gf
except ImportError as e:
    sys.exit(
        f"getfem_friction.py needs GetFEM's Python module ({e}): apt-get install python3-getfem, "
        "then run it with the system Python, /usr/bin/python3"
    )

E, NU = 1000.0, 0.3
P, Q, MU = 10.0, 4.0, 0.3
FOUNDATION = dict(x=(0.0, 4.0), y=(0.0, 1.0), nx=32, ny=8)
BLOCK = dict(x=(1.0, 3.0), y=(1.0, 2.0), nx=16, ny=8)
# Both codes solve one discrete problem; what separates their answers is where each solver stops.
# contactdd's augmented loop runs to tol = 1e-10 and gap-tol = 1e-12 (the TOML below): a slip or
# gap of 1e-12 left at a point moves its nodal force by about the interface stiffness times it,
# (E/h)·h·1e-12 = 1e-9, and its traction by 8e-9, 3e-10 of the peak pressure (27); GetFEM's
# Newton method stops at a residual of 1e-12 (forces). TOL = 1e-7, relative to the peak pressure
# (to the displacement itself for the block's displacement), stays two orders above both, and
# six below the difference the penalty makes (--enforcement penalty: 1e-1).
TOL = 1e-7
# A point slips when its traction is on the bound to this relative precision.
ON_BOUND = 1e-6
# contactdd's enforcement (the command line's --enforcement).
ENFORCEMENT = "augmented"

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def contactdd_bin():
    """The contactdd binary: CONTACTDD_BIN, the cargo target dir's, or the repository's."""
    if os.environ.get("CONTACTDD_BIN"):
        return os.environ["CONTACTDD_BIN"]
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    return os.path.join(target, "release", "contactdd")


# ---------------------------------------------------------------------------------------------
# GetFEM
# ---------------------------------------------------------------------------------------------


@contextlib.contextmanager
def quiet_stdout():
    """Silences the C++ library's own prints on file descriptor 1 (the interface prints a
    debugging line when a two-body contact brick is added)."""
    sys.stdout.flush()
    saved = os.dup(1)
    with open(os.devnull, "w") as null:
        os.dup2(null.fileno(), 1)
        try:
            yield
        finally:
            os.dup2(saved, 1)
            os.close(saved)


def rectangle(x, y, nx, ny):
    """contactdd's rectangle mesh: (nx + 1)(ny + 1) uniform nodes, every cell cut along the
    "/" diagonal into [a, b, c] and [a, c, d] (a bottom left, counter-clockwise)."""
    m = gf.Mesh("empty", 2)
    xs = np.linspace(x[0], x[1], nx + 1)
    ys = np.linspace(y[0], y[1], ny + 1)
    gt = gf.GeoTrans("GT_PK(2,1)")
    for j in range(ny):
        for i in range(nx):
            a, b = (xs[i], ys[j]), (xs[i + 1], ys[j])
            c, d = (xs[i + 1], ys[j + 1]), (xs[i], ys[j + 1])
            for tri in ((a, b, c), (a, c, d)):
                m.add_convex(gt, np.array(tri).T)
    for rid, direction in ((1, [0, -1]), (2, [0, 1]), (3, [-1, 0]), (4, [1, 0])):
        m.set_region(rid, m.outer_faces_with_direction(direction, 0.01))
    return m


BOTTOM, TOP, LEFT = 1, 2, 3


def getfem_solve(mu, q, roller):
    """Solves the case with GetFEM; returns the block's contact nodes (x, nodal normal force,
    nodal tangential force along +x, both on the block), the mean u_x of its top nodes and the
    time of the solve."""
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))  # plane strain: the 2D Lamé law is plane strain
    shear = E / (2 * (1 + NU))
    meshes = [rectangle(**FOUNDATION), rectangle(**BLOCK)]
    start = time.perf_counter()
    md = gf.Model("real")
    mfs, mims = [], []
    for k, m in enumerate(meshes):
        mf = gf.MeshFem(m, 2)
        mf.set_classical_fem(1)
        mfs.append(mf)
        mims.append(gf.MeshIm(m, gf.Integ("IM_TRIANGLE(4)")))
        md.add_fem_variable(f"u{k}", mf)
    md.add_initialized_data("lambda", [lam])
    md.add_initialized_data("mu", [shear])
    for k in range(2):
        md.add_isotropic_linearized_elasticity_brick(mims[k], f"u{k}", "lambda", "mu")
    md.add_initialized_data("zero", [0.0, 0.0])
    md.add_Dirichlet_condition_with_multipliers(mims[0], "u0", mfs[0], BOTTOM, "zero")
    md.add_initialized_data("press", [0.0, -P])
    md.add_source_term_brick(mims[1], "u1", "press", TOP)
    if q != 0.0:
        md.add_initialized_data("push", [q, 0.0])
        md.add_source_term_brick(mims[1], "u1", "push", LEFT)
    if roller:
        md.add_normal_Dirichlet_condition_with_multipliers(mims[1], "u1", 1, LEFT)
    md.add_initialized_data("r", [E])
    with quiet_stdout():
        if mu > 0.0:
            md.add_initialized_data("fr", [mu])
            # The interface reads the argument after multname_t and drops it before reading
            # dataname_r and dataname_fr: "r" is given twice.
            md.add_nodal_contact_between_nonmatching_meshes_brick(
                mims[1], mims[0], "u1", "u0", "lam_n", "lam_t", "r", "r", "fr", BOTTOM, TOP
            )
        else:
            md.add_nodal_contact_between_nonmatching_meshes_brick(
                mims[1], mims[0], "u1", "u0", "lam_n", "r", BOTTOM, TOP
            )
    # The multipliers follow the block's bottom dofs in their order (one per node).
    dofs = mfs[1].basic_dof_on_region(BOTTOM)
    nodes = mfs[1].basic_dof_nodes(dofs[0::2])
    x = nodes[0]
    # The block floats: Newton starts from the pressure p at every contact node (the start
    # only; the law decides the answer), so that its first step holds the block.
    weights = block_weights(x)
    md.set_variable("lam_n", -P * weights)
    solve_start = time.perf_counter()
    with quiet_stdout():
        iterations, converged = md.solve("max_iter", 200, "max_res", 1e-12)
    end = time.perf_counter()
    if not converged:
        sys.exit(f"GetFEM's Newton method did not converge in {iterations} iterations")
    fn = -md.variable("lam_n")
    # GetFEM's multipliers are the forces on the slave (the block) with the sign reversed, the
    # tangential one along (1, 0) (the balance checks it: the forces on the block sum to (−q, 2p)).
    ft = -md.variable("lam_t") if mu > 0.0 else np.zeros_like(fn)
    u1 = md.variable("u1")
    top = mfs[1].basic_dof_on_region(TOP)
    ux_top = float(np.mean(u1[top[0::2]]))
    order = np.argsort(x)
    return dict(
        x=x[order],
        fn=fn[order],
        ft=ft[order],
        ux=ux_top,
        time=end - start,
        solve_time=end - solve_start,
        iterations=iterations,
    )


def block_weights(x):
    """The trapezoid weights of the block's bottom nodes at abscissae x (any order)."""
    xs = np.sort(x)
    w = np.zeros_like(xs)
    w[:-1] += 0.5 * np.diff(xs)
    w[1:] += 0.5 * np.diff(xs)
    order = np.argsort(x)
    out = np.empty_like(w)
    out[order] = w
    return out


# ---------------------------------------------------------------------------------------------
# contactdd
# ---------------------------------------------------------------------------------------------


def toml_case(mu, q, roller):
    """The problem file of the case: the same meshes, loads, supports and contact."""
    f, b = FOUNDATION, BLOCK
    loads = [f'{{ kind = "pressure", boundary = "top", value = {P} }}']
    if q != 0.0:
        loads.append(f'{{ kind = "traction", boundary = "left", value = [{q}, 0.0] }}')
    supports = '\nsupports = [{ boundary = "left", component = "x" }]' if roller else ""
    friction = f'\nfriction = {{ law = "coulomb", mu = {mu} }}' if mu > 0.0 else ""
    return f"""name = "getfem_block"
plane = "strain"

[materials.soft]
young = {E}
poisson = {NU}

[[bodies]]
name = "foundation"
material = "soft"
mesh = {{ kind = "rectangle", x = [{f['x'][0]}, {f['x'][1]}], y = [{f['y'][0]}, {f['y'][1]}], nx = {f['nx']}, ny = {f['ny']} }}
supports = [{{ boundary = "bottom", component = "both" }}]

[[bodies]]
name = "block"
material = "soft"
mesh = {{ kind = "rectangle", x = [{b['x'][0]}, {b['x'][1]}], y = [{b['y'][0]}, {b['y'][1]}], nx = {b['nx']}, ny = {b['ny']} }}
loads = [{", ".join(loads)}]{supports}

[[contact]]
name = "joint"
bodies = ["foundation", "block"]
boundaries = ["top", "bottom"]
penalty = {{ c = 0.05, h = 1.0 }}
enforcement = "{ENFORCEMENT}"{friction}

[solver]
tol = 1e-10
gap-tol = 1e-12
"""


def vtu_arrays(path):
    """The points and the displacement of an ASCII VTU file written by contactdd."""
    import xml.etree.ElementTree as ET

    arrays = {}
    for da in ET.parse(path).getroot().iter("DataArray"):
        name = da.get("Name") or ""
        if name in ("Points", "displacement") and da.get("format") == "ascii":
            n = int(da.get("NumberOfComponents", "1"))
            arrays[name] = np.array(da.text.split(), dtype=float).reshape(-1, n)
    points = arrays.get("Points")
    if points is None:  # contactdd writes the points' array without a name
        for piece in ET.parse(path).getroot().iter("Points"):
            da = piece.find("DataArray")
            points = np.array(da.text.split(), dtype=float).reshape(-1, 3)
    return points, arrays["displacement"]


def contactdd_solve(mu, q, roller, folder):
    """Solves the case with `contactdd solve`; the same quantities as getfem_solve."""
    problem = os.path.join(folder, "case.toml")
    with open(problem, "w") as f:
        f.write(toml_case(mu, q, roller))
    out = os.path.join(folder, "out")
    binary = contactdd_bin()
    if not os.path.exists(binary):
        sys.exit(
            f"no contactdd binary at {binary}: "
            "cargo build --release -p contactdd-cli, or set CONTACTDD_BIN"
        )
    start = time.perf_counter()
    run = subprocess.run(
        [binary, "solve", problem, "-o", out, "-q"], capture_output=True, text=True
    )
    elapsed = time.perf_counter() - start
    if run.returncode != 0:
        sys.exit(f"contactdd solve failed ({run.returncode}):\n{run.stdout}\n{run.stderr}")
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    pair = summary["contact"][0]
    on_block = [i for i, b in enumerate(pair["body"]) if b == "block"]
    x = np.array([pair["x"][i] for i in on_block])
    force = np.array([pair["nodal_force"][i] for i in on_block])
    order = np.argsort(x)
    # The statuses live on the reference side's points (on this tie of two straight sides, the
    # foundation's), at the block's nodes' abscissae.
    statuses = pair.get("friction_status")
    status = {}
    if statuses:
        reference = {pair["body"][i] for i, s in enumerate(statuses) if s in ("stick", "slip")}
        for i, b in enumerate(pair["body"]):
            if b in reference and pair["status"][i] != "no-partner":
                status[round(pair["x"][i], 9)] = statuses[i]
    points, disp = vtu_arrays(os.path.join(out, "block.vtu"))
    top = np.abs(points[:, 1] - BLOCK["y"][1]) < 1e-9
    timing = summary["timing_s"]
    phases = ("contact_setup", "assemble_factor_condense", "iterate", "recover")
    solve_s = sum(timing[k] for k in phases)
    return dict(
        x=x[order],
        fn=force[order, 1],
        ft=force[order, 0],
        ux=float(np.mean(disp[top, 0])),
        time=elapsed,
        solve_time=solve_s,
        iterations=summary["iterations"],
        updates=summary.get("updates"),
        stick=pair.get("stick_length"),
        slip=pair.get("slip_length"),
        status=status,
    )


# ---------------------------------------------------------------------------------------------
# The comparison
# ---------------------------------------------------------------------------------------------


def getfem_statuses(g, mu):
    """GetFEM's status per node: open without a normal force, slip on the Coulomb bound."""
    out = []
    for fn, ft in zip(g["fn"], g["ft"]):
        if fn <= 0.0:
            out.append("open")
        elif mu > 0.0 and abs(ft) >= mu * fn * (1.0 - ON_BOUND):
            out.append("slip")
        else:
            out.append("stick")
    return out


def compare(name, mu, q, roller):
    """Solves one case with both codes, prints its table and returns the failed checks."""
    g = getfem_solve(mu, q, roller)
    with tempfile.TemporaryDirectory() as folder:
        c = contactdd_solve(mu, q, roller, folder)
    if len(c["x"]) != len(g["x"]) or np.max(np.abs(c["x"] - g["x"])) > 1e-12:
        sys.exit(f"{name}: the two codes' contact nodes differ")
    w = block_weights(g["x"])
    pg, pc = g["fn"] / w, c["fn"] / w
    tg, tc = g["ft"] / w, c["ft"] / w
    peak = np.max(np.abs(pg))

    def l2(d):
        return float(np.sqrt(np.sum(w * d**2) / np.sum(w * pg**2)))

    d = dict(
        fn=abs(c["fn"].sum() - g["fn"].sum()),
        ft=abs(c["ft"].sum() - g["ft"].sum()),
        p_l2=l2(pc - pg),
        p_max=float(np.max(np.abs(pc - pg)) / peak),
        t_l2=l2(tc - tg),
        t_max=float(np.max(np.abs(tc - tg)) / peak),
        ux=abs(c["ux"] - g["ux"]) / max(abs(g["ux"]), 1e-300),
    )
    sg = getfem_statuses(g, mu)
    if mu > 0.0:
        sc = [c["status"].get(round(x, 9), "?") for x in g["x"]]
    else:
        sc = ["open" if fn <= 0.0 else "stick" for fn in c["fn"]]
    d["statuses"] = sum(a != b for a, b in zip(sg, sc))
    g["stick"] = float(np.sum(w[[s == "stick" for s in sg]]))
    g["slip"] = float(np.sum(w[[s == "slip" for s in sg]]))

    rollers = ", the block's left side on rollers" if roller else ""
    print(f"\n{name}: mu = {mu}, p = {P:g} (N = {2 * P:g}), q = {q:g}{rollers}")
    print_table(c, g, d, (pc, pg), mu, (sc, sg))

    failed = []
    checks = [
        ("resultant normal force", d["fn"] / (2 * P)),
        ("resultant tangential force", d["ft"] / (2 * P)),
        ("pressure, max", d["p_max"]),
        ("tangential traction, max", d["t_max"]),
        ("horizontal displacement", d["ux"]),
    ]
    for what, err in checks:
        if not err <= TOL:
            failed.append(f"{name}: {what} differs by {err:.1e} > {TOL:g}")
    if d["statuses"]:
        failed.append(f"{name}: {d['statuses']} stick/slip/open statuses differ")
    return failed


def print_table(c, g, d, pressures, mu, statuses):
    """The comparison's markdown table: contactdd (c), GetFEM (g), differences (d)."""
    (pc, pg), (sc, sg) = pressures, statuses

    def row(k, a, b, diff):
        print(f"| {k} | {a} | {b} | {diff} |")

    def slipping(x, s):
        return ", ".join(f"{xi:g}" for xi, si in zip(x, s) if si == "slip") or "none"

    print("| quantity | contactdd | GetFEM | difference |")
    print("|---|---|---|---|")
    row("normal force on the block Σ F_n", f"{c['fn'].sum():.10f}", f"{g['fn'].sum():.10f}",
        f"{d['fn']:.1e}")
    row("tangential force on the block Σ F_t", f"{c['ft'].sum():.10f}", f"{g['ft'].sum():.10f}",
        f"{d['ft']:.1e}")
    if mu > 0.0:
        for k in ("stick", "slip"):
            row(f"{k} length", f"{c[k]:.4f}", f"{g[k]:.4f}", f"{abs(c[k] - g[k]):.1e}")
        row("slipping nodes (x)", slipping(g["x"], sc), slipping(g["x"], sg),
            f"{d['statuses']} statuses differ")
    else:
        closed = [f"{sum(s != 'open' for s in ss)} of {len(ss)}" for ss in (sc, sg)]
        row("closed nodes", closed[0], closed[1], f"{d['statuses']} differ")
    row("peak pressure", f"{np.max(pc):.8f}", f"{np.max(pg):.8f}",
        f"{abs(np.max(pc) - np.max(pg)):.1e}")
    row("pressure along the base: L2 / max, of the peak", "", "",
        f"{d['p_l2']:.1e} / {d['p_max']:.1e}")
    row("tangential traction along the base: L2 / max, of the peak", "", "",
        f"{d['t_l2']:.1e} / {d['t_max']:.1e}")
    row("block's horizontal displacement (mean u_x of its top)", f"{c['ux']:.10f}",
        f"{g['ux']:.10f}", f"{d['ux']:.1e} (relative)")
    updates = f", {c['updates']} multiplier updates" if c.get("updates") is not None else ""
    steps = [f"{n} Newton step{'' if n == 1 else 's'}" for n in (c["iterations"], g["iterations"])]
    row("iterations", steps[0] + updates, steps[1], "")
    row("time: solve / whole run (s)", f"{c['solve_time']:.3f} / {c['time']:.3f}",
        f"{g['solve_time']:.3f} / {g['time']:.3f}", "")


def main():
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument(
        "--enforcement",
        choices=["augmented", "penalty"],
        default="augmented",
        help="contactdd's enforcement; `penalty` solves the regularised law (penalty c = 0.05), "
        "a different discrete problem, and the comparison reports the difference and fails",
    )
    parser.add_argument(
        "--mu",
        type=float,
        default=MU,
        help=f"the friction coefficient of the frictional case (default {MU}; "
        f"it holds the block while mu > Q/N = {Q / (2 * P):g})",
    )
    args = parser.parse_args()
    global ENFORCEMENT
    ENFORCEMENT = args.enforcement
    gf.util_trace_level(0)
    gf.util_warning_level(0)
    failed = compare("friction", args.mu, Q, False)
    failed += compare("frictionless", 0.0, 0.0, True)
    print()
    if failed:
        print("\n".join(failed))
        return 1
    print(f"agree: every difference within {TOL:g} of the peak pressure (displacement: relative)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
