"""contactdd.space: problems in space (tetrahedral bodies, dimension = 3) solved from Python.

Checked against independent answers: the closed form of examples/space/blocks.toml (a uniform
pressure across a non-matching P1/P2 interface), the monolithic reference against the
decomposition, meshio (an independent VTK reader) against the result's arrays, the geometry of
a 10-node tetrahedron against the node order documented, and the result folder read back."""

import json
import pickle
import re

import numpy as np
import pytest

import contactdd
from contactdd import space
from conftest import REPO

BLOCKS = REPO / "examples" / "space" / "blocks.toml"
DECOMPOSITION = "interface newton (decomposition in space)"
MONOLITHIC = "monolithic reference (semismooth newton)"


@pytest.fixture(scope="module")
def blocks_file():
    if not BLOCKS.is_file():
        pytest.skip(f"{BLOCKS} does not exist (run the tests from a repository checkout)")
    return BLOCKS


@pytest.fixture(scope="module")
def blocks(blocks_file):
    return space.Problem.from_toml(blocks_file)


@pytest.fixture(scope="module")
def solved(blocks):
    return space.solve(blocks)


def closed_form():
    """p = δ / (h₁/E₁ + h₂/E₂ + θ): the file header's uniform pressure."""
    delta, h1, h2, e1, e2, theta = 0.001, 0.5, 0.5, 2.1e5, 7e4, 1e-7
    return delta / (h1 / e1 + h2 / e2 + theta)


def by_point(result):
    """The contact table sorted by (pair, node), so two solvers' points line up."""
    c = result.contact
    order = np.lexsort((c["node"], c["pair"]))
    return {k: v[order] for k, v in c.items()}


def test_problem_from_the_file(blocks):
    assert blocks.name == "blocks"
    assert blocks.bodies == ["lower", "upper"]
    assert len(blocks.contacts) == 1
    assert blocks.balance_tol == 1e-6
    assert blocks.threads is None
    assert "blocks" in repr(blocks)


def test_every_pressure_is_the_closed_form(solved):
    assert solved.converged and solved.reason is None
    assert solved.solver == DECOMPOSITION
    assert solved.newton_steps == 1
    p = solved.contact["pressure"]
    assert len(p) > 0
    np.testing.assert_allclose(p, closed_form(), rtol=1e-8, atol=0)
    assert set(solved.contact["body"]) == {"upper"}
    # The nodal areas cover the unit square interface.
    assert solved.contact["weight"].sum() == pytest.approx(1.0, rel=1e-12)
    for column in ["pair", "body", "node", "x", "y", "z", "weight", "gap", "pressure"]:
        assert solved.contact[column].shape == p.shape, column
    np.testing.assert_allclose(solved.contact["z"], 0.5, atol=1e-15)


def test_bodies_arrays(solved):
    lower, upper = solved.bodies
    assert (lower.name, lower.order, upper.name, upper.order) == ("lower", "p1", "upper", "p2")
    assert lower.tetrahedra.shape == (6 * 6 * 3 * 6, 4)
    assert upper.tetrahedra.shape == (5 * 5 * 3 * 6, 10)
    for b in solved.bodies:
        n = len(b.nodes)
        assert b.nodes.shape == (n, 3) and b.displacement.shape == (n, 3)
        assert b.stress.shape == (n, 6) and b.von_mises.shape == (n,)
        assert b.tetrahedra.dtype == np.int64 and b.tetrahedra.max() == n - 1
        assert b.imbalance <= solved.balance["tol"]
    # Uniaxial stress σ_zz = −p in both blocks.
    for b in solved.bodies:
        np.testing.assert_allclose(b.stress[:, 2], -closed_form(), rtol=1e-6)
    # The top face moves down by δ.
    top = upper.nodes[:, 2] == 1.0
    np.testing.assert_allclose(upper.displacement[top, 2], -0.001, rtol=1e-12)
    # Gmsh's order of a 10-node tetrahedron: node 8 mid-edge of 2-3, node 9 of 1-3.
    x, t = upper.nodes, upper.tetrahedra
    for node, (a, b) in zip(range(4, 10), [(0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3)]):
        np.testing.assert_allclose(x[t[:, node]], (x[t[:, a]] + x[t[:, b]]) / 2, atol=1e-14)


def test_the_reference_agrees(blocks, solved):
    reference = space.monolithic(blocks)
    assert reference.converged and reference.solver == MONOLITHIC
    d, m = by_point(solved), by_point(reference)
    for key in ["pair", "body", "node"]:
        np.testing.assert_array_equal(d[key], m[key])
    peak = d["pressure"].max()
    np.testing.assert_allclose(m["pressure"], d["pressure"], rtol=0, atol=1e-8 * peak)
    np.testing.assert_allclose(m["pressure"], closed_form(), rtol=1e-8)
    for a, b in zip(solved.bodies, reference.bodies):
        scale = np.abs(a.displacement).max()
        np.testing.assert_allclose(b.displacement, a.displacement, rtol=0, atol=1e-8 * scale)


def test_threads_give_the_same_bits(blocks):
    one, two = space.solve(blocks, threads=1), space.solve(blocks, threads=2)
    for key, values in one.contact.items():
        np.testing.assert_array_equal(values, two.contact[key])
    for a, b in zip(one.bodies, two.bodies):
        assert a.displacement.tobytes() == b.displacement.tobytes()
        assert a.stress.tobytes() == b.stress.tobytes()


def test_summary_is_the_summary_json(blocks, solved, tmp_path):
    result = space.solve(blocks, out=tmp_path / "out")
    names = sorted(p.name for p in (tmp_path / "out").iterdir())
    assert names == ["contact.csv", "lower.vtu", "summary.json", "upper.vtu"]
    written = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert sorted(written.pop("files")) == names
    summary = result.summary()
    assert summary["dimension"] == 3 and summary["solver"] == DECOMPOSITION
    for d in (written, summary):
        d.pop("timings")
    assert written == summary
    paths = solved.write(tmp_path / "again")
    assert sorted(p.rsplit("/", 1)[-1] for p in paths) == names
    csv = (tmp_path / "again" / "contact.csv").read_text().splitlines()
    assert csv[0] == "pair,body,node,x,y,z,weight,gap,pressure"
    assert len(csv) == 1 + len(solved.contact["pressure"])


def assert_same(a, b):
    """Two results in space with the same fields, bit for bit."""
    assert (a.converged, a.reason, a.solver, a.newton_steps) == (
        b.converged, b.reason, b.solver, b.newton_steps)
    assert a.balance == b.balance
    assert a.contact.keys() == b.contact.keys()
    for key, values in a.contact.items():
        np.testing.assert_array_equal(values, b.contact[key], err_msg=key)
    assert len(a.bodies) == len(b.bodies)
    for x, y in zip(a.bodies, b.bodies):
        assert (x.name, x.order, x.imbalance) == (y.name, y.order, y.imbalance)
        for field in ["nodes", "tetrahedra", "displacement", "stress", "von_mises"]:
            u, v = getattr(x, field), getattr(y, field)
            assert u.shape == v.shape and u.dtype == v.dtype, field
            np.testing.assert_array_equal(u, v, err_msg=f"{x.name}.{field}")


@pytest.mark.parametrize("output", ["", '[output]\nvtu = "ascii"\nvtu-layout = "collection"\n',
                                    '[output]\nvtu = "binary"\n'])
def test_load_results_reads_the_folder_back(blocks_file, tmp_path, output):
    problem = space.Problem.from_toml_str(blocks_file.read_text() + output)
    result = space.solve(problem, out=tmp_path)
    loaded = contactdd.load_results(tmp_path)
    assert isinstance(loaded, space.Result)
    assert_same(result, loaded)
    expected = result.summary()
    got = loaded.summary()
    assert got == json.loads(json.dumps(expected))
    with pytest.raises(contactdd.ContactddError, match="read from a result folder"):
        loaded.write(tmp_path / "again")


def test_load_results_of_the_reference(blocks, tmp_path):
    result = space.monolithic(blocks, out=tmp_path)
    loaded = contactdd.load_results(tmp_path)
    assert loaded.solver == MONOLITHIC
    assert_same(result, loaded)


def test_pickle(solved):
    again = pickle.loads(pickle.dumps(solved))
    assert type(again) is space.Result
    assert_same(solved, again)
    assert again.summary() == solved.summary()


def test_meshio_reads_the_tetrahedra(solved, tmp_path):
    meshio = pytest.importorskip("meshio")
    solved.write(tmp_path)
    for body, kind in zip(solved.bodies, ["tetra", "tetra10"]):
        mesh = meshio.read(tmp_path / f"{body.name}.vtu")
        np.testing.assert_array_equal(mesh.points, body.nodes)
        assert [block.type for block in mesh.cells] == [kind]
        cells = mesh.cells[0].data
        if kind == "tetra10":
            # VTK's quadratic tetrahedron: the mid-edge nodes of 1-3 and 2-3 in that order.
            cells = cells[:, [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]]
        np.testing.assert_array_equal(cells, body.tetrahedra)
        u = mesh.point_data["displacement"]
        assert u.shape == (len(body.nodes), 3)
        np.testing.assert_array_equal(u, body.displacement)
        np.testing.assert_array_equal(np.ravel(mesh.point_data["von_mises"]), body.von_mises)
        stress = mesh.point_data["stress"].reshape(-1, 3, 3)
        np.testing.assert_array_equal(stress[:, 2, 2], body.stress[:, 2])
        np.testing.assert_array_equal(stress[:, 0, 1], body.stress[:, 5])


def test_a_file_that_cannot_be_read(tmp_path):
    with pytest.raises(contactdd.ContactddIOError, match="cannot read") as e:
        space.Problem.from_toml(tmp_path / "missing.toml")
    assert e.value.errno == 2


def test_a_bad_file(blocks_file, tmp_path):
    text = blocks_file.read_text().replace('material = "aluminium"', 'material = "brass"')
    bad = tmp_path / "bad.toml"
    bad.write_text(text)
    with pytest.raises(contactdd.ContactddError, match="body 'upper': no material 'brass'"):
        space.Problem.from_toml(bad)
    with pytest.raises(contactdd.ContactddError, match="^<string>: "):
        space.Problem.from_toml_str(blocks_file.read_text().replace("nx = 6", "nx = -6"))
    with pytest.raises(contactdd.ContactddError, match="not a problem in space"):
        space.Problem.from_toml(REPO / "examples" / "notch.toml")


def test_an_unheld_body_is_named(blocks_file):
    text = blocks_file.read_text()
    upper = text.index('name = "upper"')
    head, tail = text[:upper], text[upper:]
    tail = re.sub(r'    \{ boundary = "[xy]-", component = "[xy]" \},\n', "", tail, count=2)
    problem = space.Problem.from_toml_str(head + tail)
    with pytest.raises(contactdd.ContactddError, match="body 'upper' is not held") as e:
        space.solve(problem)
    assert not isinstance(e.value, contactdd.ConvergenceError)
    assert "leave 3 of its 6 rigid motions free" in str(e.value)


def test_bad_arguments(blocks):
    with pytest.raises(contactdd.ContactddError, match="threads: must be at least 1"):
        space.solve(blocks, threads=0)
    with pytest.raises(contactdd.ContactddError, match="balance_tol: must be positive"):
        space.monolithic(blocks, balance_tol=-1.0)
    with pytest.raises(contactdd.ContactddError, match="threads: expected a whole number"):
        space.solve(blocks, threads=-2)
    with pytest.raises(contactdd.ContactddError, match="problem: expected"):
        space.solve("examples/space/blocks.toml")


def test_the_planar_reader_points_to_space(blocks_file):
    with pytest.raises(contactdd.ContactddError, match="contactdd.space.Problem.from_toml"):
        contactdd.Problem.from_toml(blocks_file)
    with pytest.raises(contactdd.ContactddError, match="^<string>: a problem in space"):
        contactdd.Problem.from_toml_str(blocks_file.read_text())


def test_the_system_reproduces_the_solution(blocks):
    """space.system's matrices and rows, applied to the result's displacements: every pressure
    is max(0, a·u − gap)/θ, and K u − f + the contact forces vanish off the prescribed DOFs."""

    def csr_times(data, indices, indptr, x):
        return np.array([data[s:e] @ x[indices[s:e]] for s, e in zip(indptr[:-1], indptr[1:])])

    result = space.solve(blocks)
    system = space.system(blocks)
    u = np.concatenate([b.displacement.ravel() for b in result.bodies])
    assert len(u) == system["dofs"]
    rows = system["rows"]
    assert not rows["exact"].any()
    a = (rows["data"], rows["indices"], rows["indptr"])
    law = np.maximum(csr_times(*a, u) - rows["gap"], 0.0) / rows["theta"]
    pressure = result.contact["pressure"]
    np.testing.assert_allclose(law, pressure, rtol=0, atol=1e-9 * pressure.max())
    contact = np.zeros(len(u))
    forces = rows["weight"] * pressure
    for j, (s, e) in enumerate(zip(rows["indptr"][:-1], rows["indptr"][1:])):
        np.subtract.at(contact, rows["indices"][s:e], forces[j] * rows["data"][s:e])
    for at, body in zip(system["offsets"], system["bodies"]):
        data, indices, indptr = body["stiffness"]
        n = len(indptr) - 1
        # K is symmetric: its CSC arrays are the CSR arrays of the same matrix.
        r = csr_times(data, indices, indptr, u[at:at + n]) - body["load"] - contact[at:at + n]
        free = np.setdiff1d(np.arange(n), body["prescribed_dofs"])
        assert np.abs(r[free]).max() < 1e-9 * np.abs(contact).max()


def test_exact_contact_carries_the_pressure_without_the_overlap(blocks):
    """enforcement="augmented": the Signorini conditions exactly, p = δ / (h₁/E₁ + h₂/E₂)."""
    exact = 0.001 / (0.5 / 2.1e5 + 0.5 / 7e4)
    result = space.solve(blocks, enforcement="augmented")
    p = result.contact["pressure"]
    assert np.all(np.abs(p / exact - 1.0) < 1e-10)
    assert result.summary()["balance"]["gap_violation"] < 1e-15
    assert result.summary()["contact"][0]["enforcement"] == "augmented"
    reference = space.monolithic(blocks, enforcement="augmented")
    np.testing.assert_allclose(by_point(reference)["pressure"], by_point(result)["pressure"],
                               rtol=1e-10, atol=0)
    with pytest.raises(contactdd.ContactddError, match="enforcement"):
        space.solve(blocks, enforcement="exact")


FRICTION_BLOCK = REPO / "examples" / "space" / "friction_block.toml"


def test_friction_holds_the_block_within_the_coulomb_disc(tmp_path):
    """examples/space/friction_block.toml: friction alone holds a sheared block. The contact
    table carries the tractions; each is within μp, on its edge where the point slips; their
    resultant is the shear on the block's top (the area is 1); the reference agrees; the folder
    reads back."""
    if not FRICTION_BLOCK.is_file():
        pytest.skip(f"{FRICTION_BLOCK} does not exist")
    problem = space.Problem.from_toml(FRICTION_BLOCK)
    result = space.solve(problem, out=tmp_path)
    c = result.contact
    traction = np.stack([c["traction_x"], c["traction_y"], c["traction_z"]])
    size = np.linalg.norm(traction, axis=0)
    bound = 0.3 * c["pressure"]
    assert np.all(size <= bound * (1 + 1e-12))
    slip = c["status"] == "slip"
    assert slip.any() and (c["status"] == "stick").any()
    np.testing.assert_allclose(size[slip], bound[slip], rtol=1e-10)
    resultant = (traction * c["weight"]).sum(axis=1)
    np.testing.assert_allclose(resultant, [5.942416, 4.065426, 0.0], atol=1e-8 * 40)
    assert result.balance["friction_law"] < 1e-8
    pair = result.summary()["contact"][0]
    assert pair["friction"] == {"law": "coulomb", "mu": 0.3}
    assert pair["stick"] + pair["slip"] == pair["closed"]
    reference = space.monolithic(problem)
    for key in ("pressure", "traction_x", "traction_y"):
        np.testing.assert_allclose(by_point(reference)[key], by_point(result)[key],
                                   rtol=0, atol=1e-8 * 40)
    assert_same(result, contactdd.load_results(tmp_path))
    # The same law from the keyword, as text and as a dict, and from add_contact.
    plain = space.Problem.from_toml_str(FRICTION_BLOCK.read_text().replace(
        'friction = { law = "coulomb", mu = 0.3 }', ""))
    for friction in ("coulomb:0.3", {"law": "coulomb", "mu": 0.3}):
        again = space.solve(plain, friction=friction)
        np.testing.assert_array_equal(again.contact["traction_x"], c["traction_x"])
    with pytest.raises(contactdd.ContactddError, match="friction"):
        space.solve(plain, friction="coulomb:-1")
    with pytest.raises(contactdd.ContactddError, match="slides"):
        space.solve(plain, friction="coulomb:0.1")
