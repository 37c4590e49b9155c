"""contactdd.space.Problem built in code: add_material, add_box_body, add_body (arrays),
add_msh_body, add_contact, to_toml, and contactdd.space.add_meshio_body / add_gmsh_body.

Checked against independent answers: examples/space/blocks.toml built in code (box meshes, and
the same boxes as arrays whose faces are found here from the geometry) solves to the file's
pressures bit for bit and to the closed form of the file's header; the problem file written by
to_toml reads back to the same answer; a meshio mesh of the same arrays (VTK's node order,
through a written .msh text) gives the same answer; a block under a uniform pressure meshed by
Gmsh shortens by the closed form p h / E."""

import pickle

import numpy as np
import pytest

import contactdd
from contactdd import space
from conftest import REPO

BLOCKS = REPO / "examples" / "space" / "blocks.toml"
DELTA = 0.001
HELD = [{"boundary": "x-", "component": "x"}, {"boundary": "y-", "component": "y"}]
LOWER = {"name": "lower", "material": "steel",
         "supports": [{"boundary": "z-", "component": "z"}, *HELD]}
UPPER = {"name": "upper", "material": "aluminium",
         "supports": [{"boundary": "z+", "component": "z", "value": -DELTA}, *HELD]}
BOXES = {"lower": dict(x=(0, 1), y=(0, 1), z=(0, 0.5), nx=6, ny=6, nz=3),
         "upper": dict(x=(0, 1), y=(0, 1), z=(0.5, 1), nx=5, ny=5, nz=3, order="p2")}
#: Gmsh's 10-node tetrahedron: the local vertices of the mid-edge nodes 4..9.
TET_EDGES = [(0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3)]
FACE_NAMES = [("x-", "x+"), ("y-", "y+"), ("z-", "z+")]


def closed_form():
    """p = δ / (h₁/E₁ + h₂/E₂ + θ): the file header's uniform pressure."""
    h1, h2, e1, e2, theta = 0.5, 0.5, 2.1e5, 7e4, 1e-7
    return DELTA / (h1 / e1 + h2 / e2 + theta)


@pytest.fixture(scope="module")
def from_file():
    if not BLOCKS.is_file():
        pytest.skip(f"{BLOCKS} does not exist (run the tests from a repository checkout)")
    return space.solve(space.Problem.from_toml(BLOCKS))


def empty():
    p = space.Problem(name="blocks", units="m, MPa")
    p.add_material("steel", young=2.1e5, poisson=0.3)
    p.add_material("aluminium", young=7e4, poisson=0.33)
    return p


def contact(p):
    p.add_contact(bodies=("upper", "lower"), boundaries=("z-", "z+"), theta=1e-7)
    return p


def boxes():
    p = empty()
    for body in (LOWER, UPPER):
        p.add_box_body(**body, **BOXES[body["name"]])
    return contact(p)


def box_faces(nodes, tetrahedra):
    """The faces x-, ..., z+ of a box mesh from its arrays: every tetrahedron face whose
    vertices lie on one of the box's planes, tetrahedron by tetrahedron, the face opposite local
    vertex 0, 1, 2, 3 in turn (with the mid-edge nodes of its edges t0-t1, t1-t2, t2-t0 on P2)."""
    lo, hi = nodes.min(axis=0), nodes.max(axis=0)
    p2 = tetrahedra.shape[1] == 10
    mid = {frozenset(e): 4 + k for k, e in enumerate(TET_EDGES)}
    faces = {name: [] for pair in FACE_NAMES for name in pair}
    for tet in tetrahedra:
        for opposite in range(4):
            tri = [v for v in range(4) if v != opposite]
            for axis in range(3):
                for end, value in enumerate((lo[axis], hi[axis])):
                    if all(nodes[tet[v], axis] == value for v in tri):
                        face = [tet[v] for v in tri]
                        if p2:
                            face += [tet[mid[frozenset((tri[a], tri[(a + 1) % 3]))]]
                                     for a in range(3)]
                        faces[FACE_NAMES[axis][end]].append(face)
    return {name: np.array(f, dtype=np.int64) for name, f in faces.items()}


@pytest.fixture(scope="module")
def arrays(from_file):
    """(nodes, tetrahedra, faces) of each body of the file, from its result."""
    return {b.name: (b.nodes, b.tetrahedra, box_faces(b.nodes, b.tetrahedra))
            for b in from_file.bodies}


def array_bodies(arrays):
    p = empty()
    for body in (LOWER, UPPER):
        nodes, tets, faces = arrays[body["name"]]
        p.add_body(nodes=nodes, tetrahedra=tets, faces=faces, **body)
    return contact(p)


def assert_same(result, reference):
    """Bit for bit: the contact table and every displacement."""
    for key in ("pair", "node", "x", "y", "z", "pressure", "gap"):
        np.testing.assert_array_equal(result.contact[key], reference.contact[key], err_msg=key)
    for b, r in zip(result.bodies, reference.bodies):
        np.testing.assert_array_equal(b.displacement, r.displacement)
    assert result.newton_steps == reference.newton_steps


def test_box_bodies_solve_as_the_file(from_file):
    p = boxes()
    assert p.bodies == ["lower", "upper"] and p.contacts == ["upper-lower"]
    assert p.boundaries("upper") == ["x+", "x-", "y+", "y-", "z+", "z-"]
    assert p.units == "m, MPa" and p.materials["steel"] == {"young": 2.1e5, "poisson": 0.3}
    result = space.solve(p)
    assert result.converged
    assert_same(result, from_file)
    np.testing.assert_allclose(result.contact["pressure"], closed_form(), rtol=1e-8)


def test_array_bodies_solve_as_the_file(from_file, arrays):
    nodes, tets, faces = arrays["upper"]
    assert tets.shape[1] == 10 and {f.shape[1] for f in faces.values()} == {6}
    # Each face of the 5 × 5 × 3 upper box: two triangles per cube face.
    assert [len(faces[n]) for n in ("x-", "z+")] == [2 * 5 * 3, 2 * 5 * 5]
    result = space.solve(array_bodies(arrays))
    assert_same(result, from_file)
    np.testing.assert_allclose(result.contact["pressure"], closed_form(), rtol=1e-8)


def test_the_monolithic_reference_of_a_built_problem(from_file):
    result = space.monolithic(boxes())
    np.testing.assert_allclose(result.contact["pressure"], closed_form(), rtol=1e-8)


@pytest.mark.parametrize("build", ["boxes", "arrays"])
def test_to_toml_reads_back_to_the_same_problem(build, from_file, arrays):
    p = boxes() if build == "boxes" else array_bodies(arrays)
    text = p.to_toml()
    assert "dimension = 3" in text and 'units = "m, MPa"' in text
    assert ('kind = "inline"' in text) == (build == "arrays")
    again = space.Problem.from_toml_str(text)
    assert again.to_toml() == text
    assert (again.name, again.bodies, again.contacts) == (p.name, p.bodies, p.contacts)
    assert_same(space.solve(again), from_file)
    restored = pickle.loads(pickle.dumps(p))
    assert restored.to_toml() == text


def test_solver_settings_are_written(from_file):
    p = boxes()
    p.solver(balance_tol=1e-7, threads=2)
    assert (p.balance_tol, p.threads) == (1e-7, 2)
    again = space.Problem.from_toml_str(p.to_toml())
    assert (again.balance_tol, again.threads) == (1e-7, 2)
    with pytest.raises(contactdd.ContactddError, match="balance-tol"):
        p.solver(balance_tol=-1.0)
    with pytest.raises(contactdd.ContactddError, match="threads"):
        p.solver(threads=0)
    assert (p.balance_tol, p.threads) == (1e-7, 2)


def meshio_mesh(meshio, arrays, name, physical):
    """A meshio.Mesh of body `name`'s arrays: tetra10 in VTK's order (the last two mid-edge
    nodes swapped), one triangle block per face, named by Gmsh physical groups or cell sets."""
    nodes, tets, faces = arrays[name]
    p2 = tets.shape[1] == 10
    cells = [("tetra10", tets[:, [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]]) if p2 else ("tetra", tets)]
    kind = "triangle6" if p2 else "triangle"
    cells += [(kind, f) for f in faces.values()]
    if not physical:
        sets = {n: [np.array([], dtype=int)] * len(cells) for n in faces}
        for k, n in enumerate(faces):
            sets[n][k + 1] = np.arange(len(faces[n]))
        return meshio.Mesh(nodes, cells, cell_sets=sets)
    tags = [np.full(len(c[1]), k + 1) for k, c in enumerate(cells)]
    field = {n: np.array([k + 2, 2]) for k, n in enumerate(faces)}
    field["solid"] = np.array([1, 3])
    return meshio.Mesh(nodes, cells, cell_data={"gmsh:physical": tags}, field_data=field)


@pytest.mark.parametrize("physical", [True, False], ids=["physical-groups", "cell-sets"])
def test_meshio_bodies_solve_as_the_file(physical, from_file, arrays):
    meshio = pytest.importorskip("meshio")
    p = empty()
    for body in (LOWER, UPPER):
        mesh = meshio_mesh(meshio, arrays, body["name"], physical)
        space.add_meshio_body(p, mesh=mesh, volume="solid" if physical else None, **body)
    assert p.boundaries("lower") == ["x+", "x-", "y+", "y-", "z+", "z-"]
    assert_same(space.solve(contact(p)), from_file)


def test_meshio_cell_set_of_two_kinds(arrays):
    meshio = pytest.importorskip("meshio")
    nodes, tets, faces = arrays["lower"]
    mesh = meshio.Mesh(nodes, [("tetra", tets), ("triangle", faces["z-"])],
                       cell_sets={"both": [np.array([0]), np.array([0])]})
    with pytest.raises(contactdd.ContactddError, match="body 'lower'.*'both'"):
        space.add_meshio_body(empty(), "lower", mesh, "steel")


def test_msh_text_body(arrays, tmp_path):
    meshio = pytest.importorskip("meshio")
    path = tmp_path / "upper.msh"
    meshio.write(path, meshio_mesh(meshio, arrays, "upper", True), file_format="gmsh22",
                 binary=False)
    p = empty()
    p.add_msh_body("upper", path.read_text(), "aluminium", volume="solid")
    assert p.boundaries("upper") == ["x+", "x-", "y+", "y-", "z+", "z-"]
    with pytest.raises(contactdd.ContactddError, match="body 'other'.*no physical volume named"):
        p.add_msh_body("other", path.read_text(), "aluminium", volume="nothing")
    with pytest.raises(contactdd.ContactddError, match="body 'bad': mesh: <msh text>"):
        p.add_msh_body("bad", "not a mesh", "aluminium")
    assert p.bodies == ["upper"]


def one_block(arrays):
    """The lower block's arrays, P1."""
    return arrays["lower"]


@pytest.mark.parametrize(
    "change, message",
    [
        (lambda n, t, f: (n[:, :2], t, f), r"body 'lower': mesh: nodes must have shape \(n, 3\)"),
        (lambda n, t, f: (n, t[:, :3], f), "body 'lower': mesh: tetrahedra must have 4"),
        (lambda n, t, f: (n, np.where(t == 5, len(n), t), f),
         "body 'lower': mesh: node index .* out of range|body 'lower': mesh: .*node"),
        (lambda n, t, f: (n, t - 1, f), "body 'lower': mesh: tetrahedra: node index -1 is negative"),
        (lambda n, t, f: (n, t, {**f, "inner": t[:1, 1:4]}),
         "body 'lower': mesh: face 'inner': triangle 0 is not a boundary face"),
        (lambda n, t, f: (n, t, {**f, "z-": f["z-"][:, :2]}),
         r"body 'lower': mesh: faces\['z-'\] must have 3 columns"),
        (lambda n, t, f: (n, t, {**f, "z-": f["z-"] + 0.5}),
         r"body 'lower': mesh: faces\['z-'\]: node index 0.5 is not an integer"),
        (lambda n, t, f: (n, t, [f["z-"]]), "body 'lower': mesh: faces: expected a dict"),
        (lambda n, t, f: (n, t[:, [1, 0, 2, 3]], f), "body 'lower': mesh: .*inverted"),
        (lambda n, t, f: ("nodes", t, f), "body 'lower': mesh: nodes: expected a 2-D array"),
    ],
)
def test_bad_arrays_name_the_body(change, message, arrays):
    p = empty()
    nodes, tets, faces = change(*one_block(arrays))
    with pytest.raises(contactdd.ContactddError, match=message):
        p.add_body("lower", nodes, tets, faces, "steel")
    assert p.bodies == []


def test_bad_entries_leave_the_problem_as_it_was(arrays):
    p = boxes()
    text = p.to_toml()
    nodes, tets, faces = one_block(arrays)
    cases = [
        (lambda: p.add_body("lower", nodes, tets, faces, "steel"), "two bodies are called 'lower'"),
        (lambda: p.add_body("third", nodes, tets, faces, "wood"),
         "body 'third': no material 'wood'"),
        (lambda: p.add_box_body("third", (0, 1), (0, 1), (2, 3), 1, 1, 1, "steel",
                                supports=[{"boundary": "top", "component": "z"}]),
         "body 'third': support: .*top"),
        (lambda: p.add_box_body("third", (0, 1), (0, 1), (2, 3), 1, 1, 1, "steel",
                                supports=[{"boundary": "z-", "component": "both"}]),
         r"body 'third': supports\[0\]"),
        (lambda: p.add_box_body("third", (0, 1), (0, 1), (2, 3), 1, 1, 1, "steel",
                                loads=[{"kind": "pressure", "boundary": "z+"}]),
         r"body 'third': loads\[0\]"),
        (lambda: p.add_box_body("third", (0, 1), (0, 1), (3, 2), 1, 1, 1, "steel"),
         "body 'third': mesh: the z range"),
        (lambda: p.add_box_body("third", (0, 1), (0, 1), (2, 3), 1, 1, 1, "steel", order="p3"),
         "body 'third': mesh.order"),
        (lambda: p.add_contact(("upper", "lower"), ("z-", "top"), theta=1e-7, name="again"),
         "contact 'again': body 'lower': .*top"),
        (lambda: p.add_contact(("upper", "nobody"), ("z-", "z+"), theta=1e-7),
         "contact 'upper-nobody': no body 'nobody'"),
        (lambda: p.add_contact(("upper", "lower"), ("z-", "z+"), c=1.0, name="again"),
         "contact 'again': penalty"),
        (lambda: p.add_contact(("upper", "lower"), ("z-", "z+"), theta=1e-7),
         "two contact pairs are called 'upper-lower'"),
        (lambda: p.add_contact(("upper", "lower"), ("z-", "z+"), theta=1e-7, name="again",
                               enforcement="exact"),
         "enforcement: unknown variant"),
        (lambda: p.add_material("steel", 1.0, 0.3), "material 'steel': is already defined"),
        (lambda: p.add_material("glass", -1.0, 0.3), "material 'glass'"),
    ]
    for add, message in cases:
        with pytest.raises(contactdd.ContactddError, match=message):
            add()
        assert p.to_toml() == text


def test_arguments_of_the_wrong_type():
    with pytest.raises(contactdd.ContactddError, match="name: expected a string"):
        space.Problem(name=3)
    p = empty()
    with pytest.raises(contactdd.ContactddError, match="nx"):
        p.add_box_body("b", (0, 1), (0, 1), (0, 1), -1, 1, 1, "steel")


def test_an_empty_problem_does_not_solve():
    p = empty()
    assert p.bodies == [] and "0 bodies" in repr(p)
    with pytest.raises(contactdd.ContactddError, match="no body"):
        space.solve(p)
    with pytest.raises(contactdd.ContactddError, match="no body named 'lower'"):
        p.boundaries("lower")


def test_a_gmsh_block_shortens_by_the_closed_form():
    """A block [0, 1] × [0, 1] × [0, h] meshed by Gmsh, held on z = 0 (and on the symmetry
    planes x = 0, y = 0) under a pressure p on z = h: uniaxial stress, the top moves by
    -p h / E (linear tetrahedra reproduce it exactly)."""
    gmsh = pytest.importorskip("gmsh")
    h, young, pressure = 0.5, 2.1e5, 100.0
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("block")
        volume = gmsh.model.occ.addBox(0, 0, 0, 1, 1, h)
        gmsh.model.occ.synchronize()
        named = {}
        for dim, tag in gmsh.model.getBoundary([(3, volume)], oriented=False):
            centre = gmsh.model.occ.getCenterOfMass(dim, tag)
            for axis, name in enumerate("xyz"):
                if abs(centre[axis]) < 1e-9:
                    named[f"{name}-"] = tag
                elif abs(centre[axis] - (1, 1, h)[axis]) < 1e-9:
                    named[f"{name}+"] = tag
        for name, tag in named.items():
            gmsh.model.addPhysicalGroup(2, [tag], name=name)
        gmsh.model.addPhysicalGroup(3, [volume], name="block")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.25)
        gmsh.model.mesh.generate(3)
        gmsh.model.add("other")  # the block's model is named, not current
        p = space.Problem()
        p.add_material("steel", young, 0.3)
        space.add_gmsh_body(
            p, "block", "steel", volume="block", model="block",
            supports=[{"boundary": "z-", "component": "z"}, *HELD],
            loads=[{"kind": "pressure", "boundary": "z+", "value": pressure}])
        assert gmsh.model.getCurrent() == "other"
    finally:
        gmsh.finalize()
    assert p.boundaries("block") == sorted(named)
    result = space.solve(p)
    body = result.bodies[0]
    top = np.isclose(body.nodes[:, 2], h, rtol=0, atol=1e-12)
    assert top.sum() > 4
    np.testing.assert_allclose(body.displacement[top, 2], -pressure * h / young, rtol=1e-9)


def test_an_augmented_pair_in_the_file():
    p = empty()
    for body in (LOWER, UPPER):
        p.add_box_body(**body, **BOXES[body["name"]])
    p.add_contact(("upper", "lower"), ("z-", "z+"), theta=1e-7, enforcement="augmented")
    assert 'enforcement = "augmented"' in p.to_toml()
    again = space.Problem.from_toml_str(p.to_toml())
    assert space.system(again)["rows"]["exact"].all()
    result = space.solve(again)
    assert result.summary()["contact"][0]["enforcement"] == "augmented"
    exact = 0.001 / (0.5 / 2.1e5 + 0.5 / 7e4)
    assert np.all(np.abs(result.contact["pressure"] / exact - 1.0) < 1e-10)


def test_load_steps_set_in_code():
    """Problem.solver(load_steps=, monitor=) is the file's [solver] load-steps and monitor: the
    blocks pushed in two steps carry half the pressure, then all of it (linear, touching)."""
    p = boxes()
    p.solver(load_steps=[0.5, 1.0], monitor=("upper", "z+"))
    assert "load-steps = [0.5, 1.0]" in p.to_toml()
    steps = space.solve(p).summary()["load_steps"]
    assert [s["factor"] for s in steps] == [0.5, 1.0]
    assert steps[0]["normal_forces"][0] == pytest.approx(0.5 * steps[1]["normal_forces"][0],
                                                         rel=1e-12)
    assert steps[1]["monitor"][2] == pytest.approx(-0.001, rel=1e-12)
    for bad, message in [("two", "load_steps"), (0, "load-steps")]:
        with pytest.raises(contactdd.ContactddError, match=message):
            p.solver(load_steps=bad)
    with pytest.raises(contactdd.ContactddError, match="monitor"):
        p.solver(monitor=("nobody", "z+"))
