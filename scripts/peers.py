#!/usr/bin/env python3
"""contactdd against two peer codes on the same discrete problems: time and peak memory.

The notch of examples/notch.toml (two P1 blocks 4 × 1, mirror meshes matching along y = 1, the
notch gap d(x) = r0·[1 − (x − 4)²/b²]₊^{3/2}, q = 2100 on the outer faces, u_x = 0 on the right
edges, the bodies held vertically only by the contact) with nx × ny cells per body, exact
frictionless contact, solved by three codes:

  contactdd  `contactdd solve` on the example's file with the mesh size changed,
             `enforcement = "augmented"` and the default solver (the interface Newton method) at
             tol = 1e-10, gap-tol = 1e-12; the output folder written as by default (summary.json,
             contact.csv, history.csv, zlib VTU per body);
  cholmod    this script (`--child cholmod`): the same P1 plane-strain triangles and consistent
             loads assembled with numpy, node-to-node contact across y = 1 solved by a primal–dual
             active set method (a semismooth Newton method) on the condensed SPD system,
             factorised by CHOLMOD (scikit-sparse; one symbolic analysis, a numeric factorisation
             per active set);
  getfem     this script (`--child getfem`): the same triangles in GetFEM, its linear elasticity,
             source term and normal Dirichlet bricks, its basic contact brick (node-to-node, with
             the gap vector d) with the non-symmetric Alart–Curnier augmented Lagrangian, its
             Newton solver with MUMPS.

Each run is its own process: the wall time is the whole process's (start-up, reading, assembly,
solve, writing), the memory its peak resident set (getrusage of the child via os.wait4). The
codes run interleaved (contactdd, cholmod, getfem, contactdd, …), `--repeat` rounds; the table
gives each code's median time and peak memory and the median over the rounds of its ratio to
contactdd's run in the same round. The three codes' nodal contact forces must agree within TOL of
the largest one (exit 1 otherwise), and each code's resultant must be q·4 = 8400.

With `--columns N …` also the column of N floating blocks of scripts/columns.py (non-matching
interfaces), contactdd (its default penalty enforcement, as columns.py) against GetFEM (its nodal
contact brick between non-matching meshes, exact contact): different discrete problems, so only
the times, the memory and the total contact force are compared. contactdd's time includes writing
its result folder, GetFEM writes none; `--column-vtu-layout collection` has contactdd write the
column's bodies into one `bodies.vtu` (`vtu-layout = "collection"`, docs/outputs.md) instead of
one `.vtu` per block (`per-body`, the default).

Install the peers (Debian 12; numpy, scipy and GetFEM then use OpenBLAS through
/etc/alternatives/libblas.so.3, which the script reports per code):

    apt-get install -y python3-getfem libsuitesparse-dev libopenblas-dev python3-scipy
    /usr/bin/python3 -m venv --system-site-packages /tmp/venv-peers
    /tmp/venv-peers/bin/pip install "cython<3.1" setuptools wheel
    /tmp/venv-peers/bin/pip install --no-build-isolation "scikit-sparse<0.5"

(scikit-sparse 0.5 needs numpy 2 and SuiteSparse 7; Debian 12 has numpy 1.24, SuiteSparse 5.12.)

Run:  CONTACTDD_BIN=target/release/contactdd /tmp/venv-peers/bin/python scripts/peers.py \
          128x64 512x256 --columns 64 256 --write
      (--only contactdd,cholmod to leave a code out, --repeat N rounds, 5 by default)
"""

import argparse
import importlib.util
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
import tomllib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
NOTCH = os.path.join(ROOT, "examples", "notch.toml")
CODES = ("contactdd", "cholmod", "getfem")
# What each peer needs beyond numpy (the module, and what installs it).
NEEDS = {
    "cholmod": [("scipy", "python3-scipy (apt)"),
                ("sksparse", "scikit-sparse (pip, see the docstring)")],
    "getfem": [("getfem", "python3-getfem (apt)")],
}
# GetFEM's runs grow faster than the others' with the mesh: one run at 1000 × 500 cells per body
# had not finished after 11 minutes (7.4 GB), against 1.5 minutes for the CHOLMOD code. Larger
# notches leave it out unless --getfem-cells says otherwise.
GETFEM_CELLS = 512 * 256
# The three codes solve one discrete problem; what separates their answers is where each solver
# stops: contactdd at gap-tol = 1e-12 (a length; a gap of 1e-12 left at a node moves its force by
# about E·1e-12 = 2e-7, 1e-10 of the peak nodal force at 512 × 256) and tol = 1e-10, the active
# set method exactly (up to rounding), GetFEM's Newton method at a residual of 1e-10 of the load.
# Relative to the largest nodal contact force.
TOL = 1e-8
# The resultant contact force must be q·4 to this fraction.
RESULTANT_TOL = 1e-8
# A pair counts as closed when its force exceeds this fraction of the largest one (the codes leave
# forces of rounding size, of either sign, at open pairs).
CLOSED = 1e-9
# The column's load p·2 (scripts/columns.py: p = 100 on a top 2 wide), carried by every interface.
COLUMN_FORCE = 200.0


def contactdd_bin():
    """The contactdd binary: CONTACTDD_BIN, the cargo target dir's, or the repository's."""
    if os.environ.get("CONTACTDD_BIN"):
        return os.environ["CONTACTDD_BIN"]
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    return os.path.join(target, "release", "contactdd")


# ---------------------------------------------------------------------------------------------
# The notch problem: read from examples/notch.toml, so that every code solves the example's data
# ---------------------------------------------------------------------------------------------


def notch_data():
    """The example's material, geometry, loads and gap (a dict), checked to be the layout the
    peers build: two P1 rectangles, the upper mirrored, pressure on the outer faces."""
    with open(NOTCH, "rb") as f:
        doc = tomllib.load(f)
    lower, upper = doc["bodies"]
    mat = doc["materials"][lower["material"]]
    gap = doc["contact"][0]["gap"]
    ml, mu = lower["mesh"], upper["mesh"]
    assert doc["plane"] == "strain" and upper["material"] == lower["material"]
    assert ml["x"] == mu["x"] and ml["y"][1] == mu["y"][0] and mu["mirror"] and not ml["mirror"]
    assert ml.get("diagonal", "right") == "right" == mu.get("diagonal", "right")
    assert lower["loads"][0]["boundary"] == "bottom" and upper["loads"][0]["boundary"] == "top"
    return dict(
        E=mat["young"], nu=mat["poisson"], x=ml["x"], y_lower=ml["y"], y_upper=mu["y"],
        q=lower["loads"][0]["value"], r0=gap["r0"], b=gap["b"], centre=gap["centre"],
        power=gap.get("power", 1.5),
    )


def notch_toml(nx, ny):
    """examples/notch.toml with nx × ny cells per body, exact contact and tight tolerances."""
    with open(NOTCH) as f:
        text = f.read()
    text, count = re.subn(r"nx = \d+, ny = \d+", f"nx = {nx}, ny = {ny}", text)
    assert count == 2, "examples/notch.toml: expected two `nx = …, ny = …` meshes"
    text = re.sub(r"(\ngap = [^\n]*\n)", r'\1enforcement = "augmented"\n', text)
    head, _solver = text.split("\n[solver]", 1)
    return head + "\n[solver]\ntol = 1e-10\ngap-tol = 1e-12\n"


def notch_gap(p, x):
    """The initial gap d(x) of the example."""
    import numpy as np

    s = np.maximum(1.0 - ((x - p["centre"]) / p["b"]) ** 2, 0.0)
    return p["r0"] * s ** p["power"]


def notch_nodes(p, nx, ny, mirror, shift=0.0):
    """The nodes of contactdd's rectangle mesh of one body ((nx+1)(ny+1) × 2, node j(nx+1)+i)
    and its triangles (cells cut along "/" into [a, b, c], [a, c, d]; a mirrored body's row j
    sits where row ny − j of the plain one would, its triangles reversed to stay
    counter-clockwise). `shift` moves the body up (GetFEM: to keep the bodies' nodes apart)."""
    import numpy as np

    (x0, x1) = p["x"]
    (y0, y1) = p["y_upper"] if mirror else p["y_lower"]
    i = np.arange(nx + 1)
    j = np.arange(ny + 1)
    t = j / ny
    if mirror:
        t = 1.0 - t
    xs = x0 + (x1 - x0) * i / nx
    ys = y0 + (y1 - y0) * t + shift
    X, Y = np.meshgrid(xs, ys)
    nodes = np.column_stack([X.ravel(), Y.ravel()])
    I, J = np.meshgrid(np.arange(nx), np.arange(ny))
    a = (J * (nx + 1) + I).ravel()
    b, c, d = a + 1, a + nx + 2, a + nx + 1
    tris = np.empty((2 * a.size, 3), dtype=np.int64)
    tris[0::2] = np.column_stack([a, b, c])
    tris[1::2] = np.column_stack([a, c, d])
    if mirror:
        tris = tris[:, [0, 2, 1]]
    return nodes, tris


# ---------------------------------------------------------------------------------------------
# Peer 1: numpy/scipy assembly, primal–dual active set, CHOLMOD
# ---------------------------------------------------------------------------------------------


def p1_stiffness(nodes, tris, E, nu, offset, ndof):
    """The plane-strain P1 stiffness of one body (scipy CSC, ndof × ndof, the body's dofs from
    2·offset), assembled in chunks of elements with numpy."""
    import numpy as np
    import scipy.sparse as sp

    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    D = np.array([[lam + 2 * mu, lam, 0.0], [lam, lam + 2 * mu, 0.0], [0.0, 0.0, mu]])
    K = None
    for start in range(0, len(tris), 1 << 18):
        t = tris[start:start + (1 << 18)]
        p0, p1, p2 = nodes[t[:, 0]], nodes[t[:, 1]], nodes[t[:, 2]]
        det = (p1[:, 0] - p0[:, 0]) * (p2[:, 1] - p0[:, 1]) - (p2[:, 0] - p0[:, 0]) * (
            p1[:, 1] - p0[:, 1])
        bx = np.column_stack([p1[:, 1] - p2[:, 1], p2[:, 1] - p0[:, 1], p0[:, 1] - p1[:, 1]])
        by = np.column_stack([p2[:, 0] - p1[:, 0], p0[:, 0] - p2[:, 0], p1[:, 0] - p0[:, 0]])
        bx /= det[:, None]
        by /= det[:, None]
        B = np.zeros((len(t), 3, 6))
        B[:, 0, 0::2] = bx
        B[:, 1, 1::2] = by
        B[:, 2, 0::2] = by
        B[:, 2, 1::2] = bx
        Ke = np.einsum("eki,kl,elj->eij", B, D, B, optimize=True) * (0.5 * np.abs(det))[:, None,
                                                                                          None]
        dofs = np.empty((len(t), 6), dtype=np.int32)
        dofs[:, 0::2] = 2 * (t + offset)
        dofs[:, 1::2] = 2 * (t + offset) + 1
        rows = np.broadcast_to(dofs[:, :, None], Ke.shape).ravel()
        cols = np.broadcast_to(dofs[:, None, :], Ke.shape).ravel()
        part = sp.csc_matrix((Ke.ravel(), (rows, cols)), shape=(ndof, ndof))
        K = part if K is None else K + part
    return K


def edge_loads(nodes, ids, value, ndof, offset):
    """Consistent nodal loads of a uniform force per length `value` (in y) on the chain of
    boundary nodes `ids` (ordered along the edge)."""
    import numpy as np

    f = np.zeros(ndof)
    h = np.abs(np.diff(nodes[ids, 0]))
    np.add.at(f, 2 * (ids[:-1] + offset) + 1, 0.5 * value * h)
    np.add.at(f, 2 * (ids[1:] + offset) + 1, 0.5 * value * h)
    return f


def cholmod_child(nx, ny):
    """The notch by numpy assembly and a primal–dual active set method with CHOLMOD. Returns the
    pairs' x and nodal contact forces (on the upper body, along +y) and the counts."""
    import numpy as np
    import scipy.sparse as sp
    from sksparse.cholmod import analyze

    p = notch_data()
    n_body = (nx + 1) * (ny + 1)
    ndof = 4 * n_body
    lower, tris = notch_nodes(p, nx, ny, mirror=False)
    upper, tris_u = notch_nodes(p, nx, ny, mirror=True)
    K = p1_stiffness(lower, tris, p["E"], p["nu"], 0, ndof)
    K = K + p1_stiffness(upper, tris_u, p["E"], p["nu"], n_body, ndof)
    row0 = np.arange(nx + 1)  # row j = 0: the lower body's bottom, the upper body's top
    f = edge_loads(lower, row0, p["q"], ndof, 0) + edge_loads(upper, row0, -p["q"], ndof, n_body)
    # Contact pairs: row j = ny of both bodies (y = 1), node k at x_k.
    k = ny * (nx + 1) + np.arange(nx + 1)
    low_y, up_y = 2 * k + 1, 2 * (k + n_body) + 1
    x = lower[k, 0]
    d = notch_gap(p, x)
    # Variables v: u_up_y = u_low_y + t at the pairs (t replaces u_up_y), the rest unchanged.
    T = sp.identity(ndof, format="csc") + sp.csc_matrix(
        (np.ones(len(k)), (up_y, low_y)), shape=(ndof, ndof))
    # Supports: u_x = 0 on the right edges (i = nx), and u_y = 0 at the lower body's bottom left
    # node, which removes the free vertical motion of the pair (the loads balance, so its
    # reaction is zero and the contact forces are those of the problem as posed).
    right = (nx + 1) * np.arange(ny + 1) + nx
    fixed = np.concatenate([2 * right, 2 * (right + n_body), [1]])
    keep = np.setdiff1d(np.arange(ndof), fixed)
    Kt = (T.T @ K @ T).tocsc()[keep][:, keep].tocsc()
    Kt.sort_indices()
    ft = (T.T @ f)[keep]
    where = np.full(ndof, -1)
    where[keep] = np.arange(len(keep))
    tdof = where[up_y]
    # Entry-wise row and column of Kt's stored values, and where its diagonal sits.
    cols = np.repeat(np.arange(Kt.shape[1]), np.diff(Kt.indptr))
    rows = Kt.indices
    diag = np.flatnonzero(rows == cols)
    assert len(diag) == Kt.shape[0]
    base = Kt.data.copy()
    # METIS: a slower analysis than CHOLMOD's default (AMD) but 30 % less fill and a faster
    # factorisation, which every active set repeats (512 × 256: 3.1 s once, then 2.0 s against
    # 0.35 s and 2.9 s per factorisation).
    factor = analyze(Kt, ordering_method="metis")
    c = p["E"]  # the active set's complementarity constant (a stiffness per node)
    active = np.ones(len(k), dtype=bool)  # start closed everywhere
    for it in range(1, 200):
        # Active pairs: t = −d (no gap), as a prescribed value; inactive: zero force.
        pres = np.zeros(Kt.shape[0], dtype=bool)
        pres[tdof[active]] = True
        free = ~pres
        Kt.data = base * (free[rows] & free[cols])
        Kt.data[diag[pres]] = 1.0
        vp = np.zeros(Kt.shape[0])
        vp[tdof[active]] = -d[active]
        rhs = ft - (stored_mul(base, rows, cols, vp, Kt.shape[0]))
        rhs[pres] = vp[pres]
        factor.cholesky_inplace(Kt)
        v = factor(rhs)
        # The contact force on the upper body: the t rows' residual.
        force = stored_mul(base, rows, cols, v, Kt.shape[0])[tdof] - ft[tdof]
        gap = d + v[tdof]
        new = force - c * gap > 0.0
        if np.array_equal(new, active):
            break
        active = new
    else:
        raise SystemExit("cholmod: the active set method did not settle in 200 steps")
    return dict(x=x.tolist(), force=force.tolist(), steps=it, closed=int(active.sum()),
                penetration=float(max(0.0, -gap.min())))


def stored_mul(data, rows, cols, v, n):
    """y = A v for the matrix with stored values `data` at (`rows`, `cols`)."""
    import numpy as np

    return np.bincount(rows, weights=data * v[cols], minlength=n)


# ---------------------------------------------------------------------------------------------
# Peer 2: GetFEM (bricks, Alart–Curnier augmented Lagrangian, MUMPS)
# ---------------------------------------------------------------------------------------------


def quiet_fd1():
    """Redirects the C++ library's prints on file descriptor 1 to /dev/null for the rest of the
    child process (the result goes to a file)."""
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 1)


def getfem_child(nx, ny):
    """The notch in GetFEM. Both bodies in one mesh and one variable; the upper body is moved up
    by 1 (a rigid shift: its stiffness and loads are unchanged) so that GetFEM keeps its contact
    nodes apart from the lower body's; the gap between the pairs is the vector d of the basic
    contact brick (B_N u ≤ d, B_N u = u_y(lower) − u_y(upper))."""
    import numpy as np
    import getfem as gf

    quiet_fd1()
    gf.util_trace_level(0)
    gf.util_warning_level(0)
    p = notch_data()
    lower, tris = notch_nodes(p, nx, ny, mirror=False)
    upper, tris_u = notch_nodes(p, nx, ny, mirror=True, shift=1.0)
    pts = np.vstack([lower, upper])
    cells = np.vstack([tris, tris_u + len(lower)])
    m = gf.Mesh("pt2D", pts.T, cells.T)
    (x0, x1) = p["x"]
    y_top = p["y_upper"][1] + 1.0
    eps = 1e-9
    BOTTOM, TOP, RIGHT = 1, 2, 3
    m.set_region(BOTTOM, m.outer_faces_in_box([x0 - 1, -eps], [x1 + 1, eps]))
    m.set_region(TOP, m.outer_faces_in_box([x0 - 1, y_top - eps], [x1 + 1, y_top + eps]))
    m.set_region(RIGHT, m.outer_faces_in_box([x1 - eps, -1.0], [x1 + eps, y_top + 1.0]))
    mf = gf.MeshFem(m, 2)
    mf.set_classical_fem(1)
    # One point per triangle integrates the P1 stiffness exactly; the supports' multipliers
    # need the edges' P1 × P1 products exactly, hence degree 2 there.
    mim = gf.MeshIm(m, gf.Integ("IM_TRIANGLE(1)"))
    mim2 = gf.MeshIm(m, gf.Integ("IM_TRIANGLE(2)"))
    E, nu = p["E"], p["nu"]
    md = gf.Model("real")
    md.add_fem_variable("u", mf)
    md.add_initialized_data("lambda", [E * nu / ((1 + nu) * (1 - 2 * nu))])
    md.add_initialized_data("mu", [E / (2 * (1 + nu))])
    md.add_isotropic_linearized_elasticity_brick(mim, "u", "lambda", "mu")
    md.add_initialized_data("q_lower", [0.0, p["q"]])
    md.add_initialized_data("q_upper", [0.0, -p["q"]])
    md.add_source_term_brick(mim, "u", "q_lower", BOTTOM)
    md.add_source_term_brick(mim, "u", "q_upper", TOP)
    md.add_normal_Dirichlet_condition_with_multipliers(mim2, "u", 1, RIGHT)
    # The dofs: two per node (x, y), found by their coordinates.
    where = mf.basic_dof_nodes()
    ndof = where.shape[1]
    ydofs = np.arange(1, ndof, 2)
    xy = where[:, ydofs]
    y_contact = p["y_lower"][1]
    low = ydofs[np.abs(xy[1] - y_contact) < eps]
    up = ydofs[np.abs(xy[1] - (y_contact + 1.0)) < eps]
    low = low[np.argsort(where[0, low])]
    up = up[np.argsort(where[0, up])]
    x = where[0, low]
    assert len(low) == len(up) == nx + 1 and np.allclose(where[0, up], x, atol=1e-12)
    # The pair's free vertical motion: u_y = 0 at the lower body's bottom left node.
    corner = ydofs[(np.abs(xy[0] - x0) < eps) & (np.abs(xy[1]) < eps)]
    md.add_variable("fix", 1)
    B = gf.Spmat("empty", 1, ndof)
    B.add([0], [int(corner[0])], np.ones((1, 1)))
    md.add_constraint_with_multipliers("u", "fix", B, [0.0])
    nc = len(low)
    BN = gf.Spmat("empty", nc, ndof)
    ident = gf.Spmat("identity", nc)
    BN.add(list(range(nc)), low.tolist(), ident)
    minus = gf.Spmat("identity", nc)
    minus.scale(-1.0)
    BN.add(list(range(nc)), up.tolist(), minus)
    md.add_initialized_data("r", [E])
    md.add_initialized_data("gap", notch_gap(p, x))
    md.add_variable("lam_n", nc)
    md.add_initialized_data("alpha", np.ones(nc))
    # Frictionless (u, λ_n, r, B_N, gap, alpha, version): 1 is the non-symmetric Alart–Curnier
    # augmented Lagrangian.
    md.add_basic_contact_brick("u", "lam_n", "r", BN, "gap", "alpha", 1)
    # Newton starts from the pressure q at every pair (compressive multipliers ≤ 0), so that its
    # first step holds the upper body; the law decides the answer.
    w = np.zeros(nc)
    w[:-1] += 0.5 * np.diff(x)
    w[1:] += 0.5 * np.diff(x)
    md.set_variable("lam_n", -p["q"] * w)
    iterations, converged = md.solve("lsolver", "mumps", "max_iter", 100,
                                     "max_res", 1e-10)
    if not converged:
        raise SystemExit(f"getfem: Newton did not converge in {iterations} iterations")
    force = -md.variable("lam_n")
    return dict(x=x.tolist(), force=force.tolist(), steps=int(iterations),
                closed=int((force > 0).sum()))


# ---------------------------------------------------------------------------------------------
# contactdd
# ---------------------------------------------------------------------------------------------


def contactdd_result(out):
    """The nodal contact forces on the upper body (along +y) from summary.json, sorted by x."""
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    pair = summary["contact"][0]
    pts = [(x, fy[1]) for x, b, fy in zip(pair["x"], pair["body"], pair["nodal_force"])
           if b == "upper"]
    pts.sort()
    return dict(x=[a for a, _ in pts], force=[b for _, b in pts],
                steps=summary["iterations"], updates=summary.get("updates"),
                closed=sum(1 for _, b in pts if b > 0.0))


# ---------------------------------------------------------------------------------------------
# Column of floating blocks (scripts/columns.py): GetFEM's own non-matching contact
# ---------------------------------------------------------------------------------------------


def column_toml(n):
    """The column of scripts/columns.py."""
    spec = importlib.util.spec_from_file_location("columns", os.path.join(ROOT, "scripts",
                                                                          "columns.py"))
    columns = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(columns)
    return columns.column(n)


def column_child(n):
    """The column of n blocks in GetFEM: one mesh, variable and elasticity brick per block,
    `add_nodal_contact_between_nonmatching_meshes_brick` between neighbours (the upper block's
    bottom nodes on the lower block's top), Alart–Curnier, MUMPS. Returns the resultant of each
    interface's contact forces."""
    import numpy as np
    import getfem as gf

    quiet_fd1()
    gf.util_trace_level(0)
    gf.util_warning_level(0)
    doc = tomllib.loads(column_toml(n))
    md = gf.Model("real")
    BOTTOM, TOP, LEFT = 1, 2, 3
    mims, mfs, xs = [], [], []
    for i, body in enumerate(doc["bodies"]):
        mesh = body["mesh"]
        nx, ny = mesh["nx"], mesh["ny"]
        (x0, x1), (y0, y1) = mesh["x"], mesh["y"]
        pts, tris = notch_nodes(dict(x=(x0, x1), y_lower=(y0, y1)), nx, ny, mirror=False)
        m = gf.Mesh("pt2D", pts.T, tris.T)
        for rid, direction in ((BOTTOM, [0, -1]), (TOP, [0, 1]), (LEFT, [-1, 0])):
            m.set_region(rid, m.outer_faces_with_direction(direction, 0.01))
        mf = gf.MeshFem(m, 2)
        mf.set_classical_fem(1)
        mim = gf.MeshIm(m, gf.Integ("IM_TRIANGLE(2)"))  # exact for the supports' multipliers
        mat = doc["materials"][body["material"]]
        E, nu = mat["young"], mat["poisson"]
        md.add_fem_variable(f"u{i}", mf)
        md.add_initialized_data(f"la{i}", [E * nu / ((1 + nu) * (1 - 2 * nu))])
        md.add_initialized_data(f"mu{i}", [E / (2 * (1 + nu))])
        md.add_isotropic_linearized_elasticity_brick(mim, f"u{i}", f"la{i}", f"mu{i}")
        md.add_normal_Dirichlet_condition_with_multipliers(mim, f"u{i}", 1, LEFT)
        if i == 0:
            md.add_normal_Dirichlet_condition_with_multipliers(mim, f"u{i}", 1, BOTTOM)
        for load in body.get("loads", []):
            md.add_initialized_data(f"p{i}", [0.0, -load["value"]])
            md.add_source_term_brick(mim, f"u{i}", f"p{i}", TOP)
        mims.append(mim)
        mfs.append(mf)
        xs.append(np.linspace(x0, x1, nx + 1))
    p = doc["bodies"][-1]["loads"][0]["value"]
    md.add_initialized_data("r", [doc["materials"]["a"]["young"]])
    for i in range(n - 1):
        md.add_nodal_contact_between_nonmatching_meshes_brick(
            mims[i + 1], mims[i], f"u{i + 1}", f"u{i}", f"lam{i}", "r", BOTTOM, TOP)
        # Newton starts from the pressure p at every slave node (the start only).
        w = np.zeros(len(xs[i + 1]))
        w[:-1] += 0.5 * np.diff(xs[i + 1])
        w[1:] += 0.5 * np.diff(xs[i + 1])
        md.set_variable(f"lam{i}", -p * w)
    # The chain of floating blocks amplifies rounding: on 256 blocks Newton's residual stalls at
    # 1.3e-10 after its first step, so the column asks 1e-8.
    iterations, converged = md.solve("lsolver", "mumps", "max_iter", 100,
                                     "max_res", 1e-8)
    if not converged:
        raise SystemExit(f"getfem column: Newton did not converge in {iterations} iterations")
    forces = [float(-np.sum(md.variable(f"lam{i}"))) for i in range(n - 1)]
    return dict(forces=forces, steps=int(iterations))


# ---------------------------------------------------------------------------------------------
# Measuring
# ---------------------------------------------------------------------------------------------


def run_measured(cmd, log):
    """Runs `cmd` as a child process; returns (exit code, wall s, peak RSS MB)."""
    start = time.perf_counter()
    with open(log, "w") as out:
        proc = subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT)
        _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    proc.returncode = os.waitstatus_to_exitcode(status)
    return proc.returncode, wall, usage.ru_maxrss / 1024.0


#: The `--vtu-layout` of contactdd's column runs (`--column-vtu-layout`).
COLUMN_VTU_LAYOUT = ["per-body"]


def run_code(code, problem, size, folder):
    """One measured run of `code` on `problem` ("notch" with size (nx, ny), or "column" with n
    blocks); returns (wall s, peak RSS MB, result dict)."""
    tag = f"{code}-{problem}-{size}"
    log = os.path.join(folder, tag + ".log")
    if code == "contactdd":
        toml = os.path.join(folder, f"{problem}-{size}.toml")
        out = os.path.join(folder, tag + "-out")
        cmd = [contactdd_bin(), "solve", toml, "-o", out, "-q"]
        if problem == "column":
            cmd += ["--vtu-layout", COLUMN_VTU_LAYOUT[0]]
    else:
        out = os.path.join(folder, tag + ".json")
        cmd = [sys.executable, os.path.abspath(__file__), "--child", code, "--problem", problem,
               "--size", str(size), "--result", out]
    rc, wall, rss = run_measured(cmd, log)
    if rc != 0:
        with open(log) as f:
            sys.exit(f"{code} on {problem} {size} failed (exit {rc}):\n{f.read()[-3000:]}")
    if code == "contactdd":
        if problem == "notch":
            result = contactdd_result(out)
        else:
            with open(os.path.join(out, "summary.json")) as f:
                s = json.load(f)
            result = dict(forces=[c["force"][1][1] for c in s["contact"]], steps=s["iterations"])
    else:
        with open(out) as f:
            result = json.load(f)
    return wall, rss, result


def libraries_of(code):
    """The numerical libraries (BLAS, LAPACK, CHOLMOD, MUMPS) a peer's process maps, read from
    /proc/self/maps of a short child that imports what the peer imports."""
    if code == "contactdd":
        return "none (pure Rust)"
    imports = "import numpy, scipy.sparse, sksparse.cholmod" if code == "cholmod" else \
        "import getfem"
    probe = (imports + "; import re; print(', '.join(sorted({l.split('/')[-1].strip() "
             "for l in open('/proc/self/maps') if re.search('blas|lapack|cholmod|mumps', "
             "l.split('/')[-1]) and 'cpython' not in l})))")
    run = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
    blas = os.path.realpath("/usr/lib/x86_64-linux-gnu/libblas.so.3")
    return f"{run.stdout.strip() or run.stderr.strip()[-200:]} (libblas.so.3 → {blas})"


def machine():
    """The CPU model and core count."""
    model = "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return f"{model}, {os.cpu_count()} cores"


def measure(problem, size, codes, repeat, folder):
    """Interleaved rounds of every code on one problem; returns per code the lists of times,
    peaks and ratios, and the first result."""
    if problem == "notch":
        nx, ny = size
        text = notch_toml(nx, ny)
        name = f"{nx}x{ny}"
    else:
        text = column_toml(size)
        name = str(size)
    with open(os.path.join(folder, f"{problem}-{name}.toml"), "w") as f:
        f.write(text)
    rows = {c: dict(wall=[], rss=[], rwall=[], rrss=[], result=None) for c in codes}
    for r in range(repeat):
        round_ = {}
        for code in codes:
            wall, rss, result = run_code(code, problem, name, folder)
            round_[code] = (wall, rss)
            row = rows[code]
            row["wall"].append(wall)
            row["rss"].append(rss)
            if row["result"] is None:
                row["result"] = result
            print(f"  {problem} {name} round {r + 1}: {code} {wall:.2f} s {rss:.0f} MB",
                  file=sys.stderr, flush=True)
        if "contactdd" in round_:
            w0, m0 = round_["contactdd"]
            for code in codes:
                rows[code]["rwall"].append(round_[code][0] / w0)
                rows[code]["rrss"].append(round_[code][1] / m0)
    return rows


def table(rows):
    """The markdown table of one problem."""
    lines = ["| code | median wall s | ratio to contactdd | peak RSS MB | ratio |",
             "|---|---|---|---|---|"]
    for code, r in rows.items():
        med = statistics.median
        rw = f"{med(r['rwall']):.2f}" if r["rwall"] else "—"
        rm = f"{med(r['rrss']):.2f}" if r["rrss"] else "—"
        lines.append(f"| {code} | {med(r['wall']):.3f} | {rw} | {med(r['rss']):.0f} | {rm} |")
    return lines


def notch_agreement(rows, p):
    """The agreement lines of the notch and whether they pass."""
    import numpy as np

    codes = list(rows)
    ref = rows[codes[0]]["result"]
    x0 = np.array(ref["x"])
    f0 = np.array(ref["force"])
    peak = np.max(np.abs(f0))
    load = p["q"] * (p["x"][1] - p["x"][0])
    ok = True
    parts = []
    for code in codes:
        res = rows[code]["result"]
        f = np.array(res["force"])
        total = f.sum()
        rel = abs(total - load) / load
        ok &= rel <= RESULTANT_TOL
        steps = plural(res["steps"], "step") + (
            f", {res['updates']} updates" if res.get("updates") is not None else "")
        closed = int(np.sum(f > CLOSED * peak))
        parts.append(f"{code}: Σ F = {total:.6f} ({rel:.1e} from q·4 = {load:g}), "
                     f"{closed} of {len(f)} pairs closed, {steps}")
    lines = ["resultant contact force on the upper body: " + "; ".join(parts) + "."]
    diffs = []
    for code in codes[1:]:
        res = rows[code]["result"]
        if len(res["x"]) != len(x0) or np.max(np.abs(np.array(res["x"]) - x0)) > 1e-12:
            ok = False
            diffs.append(f"{code}: different contact nodes")
            continue
        err = float(np.max(np.abs(np.array(res["force"]) - f0)) / peak)
        ok &= err <= TOL
        diffs.append(f"{code} {err:.1e}")
    if diffs:
        lines.append(f"largest difference of a nodal contact force from {codes[0]}'s, relative "
                     f"to the largest ({peak:.4f}): " + ", ".join(diffs) + f" (TOL {TOL:g}).")
    return lines, ok


def column_agreement(rows, n):
    """The total contact force of the column's interfaces per code (each should be p·2)."""
    parts = []
    for code, r in rows.items():
        forces = r["result"]["forces"]
        worst = max(abs(f - COLUMN_FORCE) for f in forces) / COLUMN_FORCE
        parts.append(f"{code} Σ {sum(forces):.6f}, every interface within {worst:.1e} of "
                     f"{COLUMN_FORCE:g}, {plural(r['result']['steps'], 'step')}")
    return [f"contact force of the {n - 1} interfaces (p·2 = {COLUMN_FORCE:g} each, "
            f"{(n - 1) * COLUMN_FORCE:g} in all): " + "; ".join(parts) + "."]


def plural(n, word):
    """"1 step", "2 steps"."""
    return f"{n} {word}{'' if n == 1 else 's'}"


def check_peers(codes):
    """Exits naming the missing package when a peer cannot run."""
    for code in codes:
        for module, package in NEEDS.get(code, []):
            if importlib.util.find_spec(module) is None:
                sys.exit(f"peer `{code}` needs the Python module `{module}` ({package}), "
                         f"missing in {sys.executable}; leave the peer out with --only, or "
                         "install it as the docstring of scripts/peers.py says")
    if "contactdd" in codes and not os.path.exists(contactdd_bin()):
        sys.exit(f"no contactdd binary at {contactdd_bin()}: cargo build --release -p "
                 "contactdd-cli, or set CONTACTDD_BIN")


def child_main(args):
    """The peer child process: solve, write the result JSON."""
    if args.problem == "notch":
        nx, ny = map(int, args.size.split("x"))
        start = time.perf_counter()
        result = (cholmod_child if args.child == "cholmod" else getfem_child)(nx, ny)
    else:
        start = time.perf_counter()
        result = column_child(int(args.size))
    result["inside_s"] = time.perf_counter() - start
    with open(args.result, "w") as f:
        json.dump(result, f)
    return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("sizes", nargs="*", default=["128x64", "512x256"],
                        help="notch meshes, cells per body NXxNY (default 128x64 512x256)")
    parser.add_argument("--only", default=",".join(CODES),
                        help="comma-separated codes to run (contactdd, cholmod, getfem)")
    parser.add_argument("--repeat", type=int, default=5, help="interleaved rounds (default 5)")
    parser.add_argument("--columns", type=int, nargs="*", default=[],
                        help="also columns of N floating blocks: contactdd and GetFEM")
    parser.add_argument("--getfem-cells", type=int, default=GETFEM_CELLS,
                        help="notch meshes above this many cells per body leave GetFEM out "
                        f"(default {GETFEM_CELLS})")
    parser.add_argument("--column-vtu-layout", choices=["per-body", "collection"],
                        default="per-body",
                        help="contactdd's .vtu layout on the columns: one file per block "
                             "(per-body, the default) or one for all blocks (collection)")
    parser.add_argument("--write", action="store_true", help="also write scripts/peers.md")
    parser.add_argument("--child", choices=["cholmod", "getfem"], help=argparse.SUPPRESS)
    parser.add_argument("--problem", default="notch", help=argparse.SUPPRESS)
    parser.add_argument("--size", help=argparse.SUPPRESS)
    parser.add_argument("--result", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        return child_main(args)
    COLUMN_VTU_LAYOUT[0] = args.column_vtu_layout
    codes = [c.strip() for c in args.only.split(",") if c.strip()]
    unknown = set(codes) - set(CODES)
    if unknown:
        sys.exit(f"--only: unknown code(s) {', '.join(sorted(unknown))} (known: "
                 f"{', '.join(CODES)})")
    codes = [c for c in CODES if c in codes]
    check_peers(codes + (["getfem"] if args.columns else []))
    p = notch_data()
    ok = True
    lines = ["# contactdd against its peers (`scripts/peers.py`)", "",
             f"`python3 {' '.join(['scripts/peers.py'] + sys.argv[1:])}`: {args.repeat} "
             f"interleaved round{'s' if args.repeat > 1 else ''} on {machine()}, Python "
             f"{sys.version.split()[0]}. Libraries: "
             + "; ".join(f"{c}: {libraries_of(c)}" for c in codes) + ".", ""]
    with tempfile.TemporaryDirectory(prefix="peers-") as folder:
        for size in args.sizes:
            nx, ny = map(int, size.lower().split("x"))
            here = [c for c in codes if c != "getfem" or nx * ny <= args.getfem_cells]
            rows = measure("notch", (nx, ny), here, args.repeat, folder)
            lines += [f"## Notch, {nx} × {ny} cells per body "
                      f"({2 * 2 * (nx + 1) * (ny + 1)} DOFs, {nx + 1} contact pairs)", ""]
            lines += table(rows) + [""]
            if here != codes:
                lines += [f"GetFEM left out: {nx * ny} cells per body is more than "
                          f"--getfem-cells = {args.getfem_cells}.", ""]
            more, good = notch_agreement(rows, p)
            ok &= good
            lines += more + [""]
        for n in args.columns:
            rows = measure("column", n, ["contactdd", "getfem"], args.repeat, folder)
            lines += [f"## Column of {n} floating blocks (scripts/columns.py)", "",
                      "Non-matching interfaces: contactdd's penalty contact of columns.py against "
                      "GetFEM's exact nodal contact between non-matching meshes, two different "
                      "discrete problems; only the time, the memory and the contact forces are "
                      "compared. contactdd's time includes writing its result folder, its "
                      f"`.vtu` files in the `{args.column_vtu_layout}` layout; GetFEM writes "
                      "none.", ""]
            lines += table(rows) + [""]
            lines += column_agreement(rows, n) + [""]
    text = "\n".join(lines)
    print(text)
    if args.write:
        with open(os.path.join(ROOT, "scripts", "peers.md"), "w") as f:
            f.write(text)
    if not ok:
        print("FAILED: the codes disagree beyond the tolerance", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
