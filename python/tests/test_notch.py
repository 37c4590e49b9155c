"""The notch benchmark from a TOML file, from numpy arrays and from the built-in builder."""

import json

import numpy as np
import pytest

import contactdd

Q = 0.01 * 2.1e5  # applied pressure q = 0.01 E
L = 4.0  # body length l


def rectangle(x, y, nx, ny, mirror=False):
    """A structured rectangle mesh with "/" diagonals, numbered like contactdd's own mesher.

    Returns (nodes, triangles, boundaries). With ``mirror`` the mesh is mirrored about its
    horizontal centre line (the upper body of the notch benchmark).
    """
    (x0, x1), (y0, y1) = x, y
    i, j = np.meshgrid(np.arange(nx + 1, dtype=float), np.arange(ny + 1, dtype=float))
    t = j / ny
    if mirror:
        t = 1.0 - t
    nodes = np.column_stack([(x0 + (x1 - x0) * i / nx).ravel(), (y0 + (y1 - y0) * t).ravel()])

    def node(i, j):
        return j * (nx + 1) + i

    ci, cj = np.meshgrid(np.arange(nx), np.arange(ny))
    ci, cj = ci.ravel(), cj.ravel()
    a, b, c, d = node(ci, cj), node(ci + 1, cj), node(ci + 1, cj + 1), node(ci, cj + 1)
    tris = np.stack([np.column_stack([a, b, c]), np.column_stack([a, c, d])], axis=1).reshape(-1, 3)
    if mirror:  # mirroring flips the orientation: restore counter-clockwise order
        tris = tris[:, [0, 2, 1]]
    cols = np.arange(nx)
    rows = np.arange(ny)

    def row(j):
        return np.column_stack([node(cols, j), node(cols + 1, j)])

    def col(i):
        return np.column_stack([node(i, rows), node(i, rows + 1)])

    bottom, top = (ny, 0) if mirror else (0, ny)
    boundaries = {"bottom": row(bottom), "top": row(top), "left": col(0), "right": col(nx)}
    return nodes, tris, boundaries


def notch_from_arrays(nx=32, ny=16, clockwise=False):
    """The notch benchmark built from numpy arrays (with every triangle clockwise if asked)."""
    p = contactdd.Problem(name="notch", plane="strain")
    p.add_material("steel", young=2.1e5, poisson=0.3)
    for name, y, mirror, loaded in [
        ("lower", (0.0, 1.0), False, "bottom"),
        ("upper", (1.0, 2.0), True, "top"),
    ]:
        nodes, tris, boundaries = rectangle((0.0, L), y, nx, ny, mirror)
        if clockwise:
            tris = tris[:, [0, 2, 1]]
        p.add_body(
            name,
            nodes,
            tris,
            boundaries,
            material="steel",
            supports=[{"boundary": "right", "component": "x", "value": 0.0}],
            loads=[{"kind": "pressure", "boundary": loaded, "value": Q}],
        )
    p.add_contact(
        bodies=("lower", "upper"),
        boundaries=("top", "bottom"),
        c=0.05,
        h=1.0,
        gap={"kind": "notch", "r0": 0.05, "b": 1.0, "centre": 4.0, "power": 1.5, "along": "x"},
        name="notch",
    )
    p.solver(method="newton-kurchatov", gamma=0.5, tol=1e-3, u0=1e-4, u_prev=2e-4)
    return p


def assert_same(r1, r2):
    assert r1.iterations == r2.iterations
    for c1, c2 in zip(r1.contact, r2.contact):
        np.testing.assert_allclose(c1.pressure, c2.pressure, rtol=1e-12, atol=1e-12 * Q)
        np.testing.assert_allclose(c1.x, c2.x, rtol=0, atol=1e-14)
    for b1, b2 in zip(r1.bodies, r2.bodies):
        np.testing.assert_allclose(b1.displacement, b2.displacement, rtol=1e-12, atol=1e-18)


def test_toml_and_arrays_agree(notch_toml):
    from_file = contactdd.solve(contactdd.Problem.from_toml(notch_toml))
    from_arrays = contactdd.solve(notch_from_arrays())
    assert from_file.converged and from_arrays.converged
    assert_same(from_file, from_arrays)


def test_clockwise_triangles_are_reordered(notch_toml):
    """As the Gmsh reader does: the same problem, the same answer."""
    from_file = contactdd.solve(contactdd.Problem.from_toml(notch_toml))
    assert_same(from_file, contactdd.solve(notch_from_arrays(clockwise=True)))


def test_toml_str_and_builtin_agree(notch_toml, notch):
    text = notch_toml.read_text()
    p = contactdd.Problem.from_toml_str(text, base_dir=notch_toml.parent)
    assert p.name == "notch" and p.bodies == ["lower", "upper"] and p.contacts == ["notch"]
    assert p.settings["gamma"] == 0.5
    assert_same(contactdd.solve(p), contactdd.solve(notch))


def test_rectangle_builder_matches_arrays():
    p = contactdd.Problem(name="notch")
    p.add_material("steel", 2.1e5, 0.3)
    for name, y, mirror, loaded in [
        ("lower", (0.0, 1.0), False, "bottom"),
        ("upper", (1.0, 2.0), True, "top"),
    ]:
        p.add_rectangle_body(
            name, x=(0.0, L), y=y, nx=32, ny=16, material="steel", mirror=mirror,
            supports=[{"boundary": "right", "component": "x"}],
            loads=[{"kind": "pressure", "boundary": loaded, "value": Q}],
        )
    assert p.boundaries("lower") == ["bottom", "left", "right", "top"]
    p.add_contact(("lower", "upper"), ("top", "bottom"), c=0.05, h=1.0,
                  gap={"kind": "notch", "r0": 0.05, "b": 1.0, "centre": 4.0})
    assert p.contacts == ["lower-upper"]
    r = contactdd.solve(p, method="newton-kurchatov", gamma=0.5, tol=1e-3)
    assert_same(r, contactdd.solve(notch_from_arrays()))


def test_force_balance(notch):
    r = contactdd.solve(notch)
    (c,) = r.contact
    assert c.bodies == ("lower", "upper")
    (f0x, f0y), (f1x, f1y) = c.forces
    # The contact carries the applied load q·l on each body.
    assert f0y == pytest.approx(-Q * L, rel=1e-9)
    assert f1y == pytest.approx(Q * L, rel=1e-9)
    assert abs(f0x) < 1e-9 * Q * L and abs(f1x) < 1e-9 * Q * L
    # The same from the per-point arrays: Σ w σ_n n_y = −Σ w p n_y per side (own-side pair).
    side = np.asarray(c.side)
    for s, f in [(0, f0y), (1, f1y)]:
        m = side == s
        total = np.sum(c.weight[m] * c.nodal_traction[m] * c.normal[m, 1])
        assert total == pytest.approx(f, rel=1e-12)
        assert -np.sum(c.weight[m] * c.pressure[m] * c.normal[m, 1]) == pytest.approx(f, rel=1e-12)
    assert np.all(c.pressure >= 0) and np.all(c.nodal_traction <= 0)
    assert np.array_equal(c.closed, c.pressure > 0)
    assert set(c.status) <= {"closed", "open", "no-partner"}
    # The notch opens next to the symmetry line x = 4, the rest is closed.
    lower = side == 0
    assert not c.closed[lower & (c.x > 3.95)].any()
    assert c.closed[lower & (c.x < 2.5)].all()


def test_result_contents(notch):
    r = contactdd.solve(notch)
    assert r.converged and r.stop == "converged" and r.message is None
    assert r.method == "newton-kurchatov" and r.gamma == 0.5
    assert r.theta == [pytest.approx(2 * 0.05 * 1.0 * (1 - 0.3**2) / 2.1e5)]
    h = r.history
    m = r.iterations
    assert h["k"].tolist() == list(range(1, m + 1))
    assert h["rel_change"].shape == (m, 2) and h["active"].shape == (m, 2)
    assert h["normal_force"].shape == (m, 2) and h["gamma"].shape == (m,)
    assert np.all(h["rel_change"][-1] <= 1e-3)
    lower, upper = r.bodies
    assert (lower.name, upper.name) == ("lower", "upper")
    n = lower.nodes.shape[0]
    assert lower.nodes.shape == (n, 2) == lower.displacement.shape
    assert lower.triangles.shape == (1024, 3) and lower.order == "p1"
    assert lower.stress.shape == (n, 4)
    assert lower.von_mises.shape == (n,) == lower.contact_pressure.shape
    assert set(r.timing) >= {"iterate", "assemble_factor_condense"}


def test_summary_and_files(notch, tmp_path):
    r = contactdd.solve(notch)
    s = r.summary()
    assert s["converged"] is True and s["iterations"] == r.iterations
    assert s["method"] == "newton-kurchatov"
    assert [b["name"] for b in s["bodies"]] == ["lower", "upper"]
    written = r.write_vtu(tmp_path / "out")
    names = sorted(p.split("/")[-1] for p in written)
    assert "summary.json" in names and "lower.vtu" in names and "upper.vtu" in names
    on_disk = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert on_disk["iterations"] == s["iterations"]
    assert on_disk["contact"] == s["contact"]


def test_overrides_do_not_change_problem(notch):
    r = contactdd.solve(notch, method="active-set", gamma=0.3, tol=1e-6, max_iter=1000)
    assert r.converged and r.method == "active-set" and r.gamma == 0.3
    assert notch.settings["method"] == "newton-kurchatov"
    auto = contactdd.solve(notch, gamma="auto", tol=1e-6)
    assert auto.converged and auto.gamma == "auto"


def test_monolithic_agrees_with_dd(notch):
    dd = contactdd.solve(notch, method="active-set", gamma=0.5, tol=1e-10, max_iter=2000)
    mono = contactdd.monolithic(notch)
    assert mono.newton_steps >= 1 and len(mono.rigid_modes) == 1
    np.testing.assert_allclose(mono.contact[0].pressure, dd.contact[0].pressure,
                               rtol=0, atol=1e-6 * Q)
    assert mono.summary()["solver"] == "monolithic"


def test_p2(tmp_path):
    r = contactdd.solve(contactdd.notch_benchmark(nx=16, ny=8, order="p2"))
    assert r.converged
    assert r.bodies[0].order == "p2" and r.bodies[0].triangles.shape[1] == 6
    assert r.contact[0].forces[1][1] == pytest.approx(Q * L, rel=1e-9)
