"""Bodies from a meshio.Mesh and from the live Gmsh model read as the problem file's Gmsh meshes
are: examples/cylinder_plates.toml built from meshio.read(its .msh) and from its mesh script's
live model solves to the same result, bit for bit, as the file."""

import importlib.util
import sys

import numpy as np
import pytest

import contactdd
from compare import assert_same_result
from conftest import REPO

EXAMPLE = REPO / "examples" / "cylinder_plates.toml"
MSH = REPO / "examples" / "meshes" / "cylinder_plates.msh"
SCRIPT = REPO / "examples" / "meshes" / "make_cylinder_plates.py"

# The bodies of examples/cylinder_plates.toml: (name, supports, loads).
BODIES = [
    ("lower", [{"boundary": "lower-bottom", "component": "both"}], None),
    ("cylinder", [{"boundary": "cyl-centre", "component": "x"}], None),
    ("upper", [{"boundary": "upper-mid", "component": "x"}],
     [{"kind": "pressure", "boundary": "upper-top", "value": 225.0}]),
]


def cylinder_plates(add_body, reference):
    """The example built in code, each body added by ``add_body(problem, name, supports,
    loads)``; the starting values u0, u_prev (from the model's size) as the file's."""
    p = contactdd.Problem(name="cylinder_plates")
    p.add_material("steel", young=2.1e5, poisson=0.3)
    for name, supports, loads in BODIES:
        add_body(p, name, supports, loads)
    p.add_contact(("lower", "cylinder"), ("lower-top", "cyl-bottom"), theta=8e-9,
                  name="lower-cylinder")
    p.add_contact(("cylinder", "upper"), ("cyl-top", "upper-bottom"), theta=8e-9,
                  name="cylinder-upper")
    p.solver(u0=reference.settings["u0"], u_prev=reference.settings["u_prev"],
             monitor=reference.settings["monitor"])
    return p


@pytest.fixture(scope="module")
def from_file():
    if not EXAMPLE.is_file():
        pytest.skip(f"{EXAMPLE} does not exist")
    problem = contactdd.Problem.from_toml(EXAMPLE)
    problem.solver(load_steps=1)  # one solve at the full load instead of the file's 5 steps
    return problem, contactdd.solve(problem)


def test_meshio_mesh_solves_as_the_file(from_file):
    meshio = pytest.importorskip("meshio")
    mesh = meshio.read(MSH)
    problem = cylinder_plates(
        lambda p, name, supports, loads: contactdd.add_meshio_body(
            p, name, mesh, "steel", surface=name, order="p2", supports=supports, loads=loads),
        from_file[0])
    assert_same_result(from_file[1], contactdd.solve(problem), timing=False)


def test_live_gmsh_model_solves_as_the_file(from_file):
    try:
        import gmsh
    except (ImportError, OSError) as e:
        pytest.skip(f"the gmsh package cannot be imported here: {e}")
    spec = importlib.util.spec_from_file_location("make_cylinder_plates", SCRIPT)
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    gmsh.initialize(interruptible=False)
    try:
        script.build()
        problem = cylinder_plates(
            lambda p, name, supports, loads: contactdd.add_gmsh_body(
                p, name, "steel", surface=name, order="p2", supports=supports, loads=loads),
            from_file[0])
    finally:
        gmsh.finalize()
    assert_same_result(from_file[1], contactdd.solve(problem), timing=False)


def test_live_gmsh_order_2_mesh_is_curved_and_matches_hertz():
    """Gmsh's SetOrder(2) on a half disc gives curved 6-node triangles, read isoparametrically:
    the arc's nodes (mid-side ones too) lie on the circle, and the half disc pressed on a block
    (examples/hertz.toml's problem) has Hertz's peak pressure to 1 %."""
    try:
        import gmsh
    except (ImportError, OSError) as e:
        pytest.skip(f"the gmsh package cannot be imported here: {e}")
    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        occ = gmsh.model.occ
        centre, left, right, low = (occ.addPoint(x, y, 0) for x, y in
                                    [(0, 1), (-1, 1), (1, 1), (0, 0)])
        arcs = [occ.addCircleArc(left, centre, low), occ.addCircleArc(low, centre, right)]
        top = occ.addLine(right, left)
        disc = occ.addPlaneSurface([occ.addCurveLoop(arcs + [top])])
        occ.synchronize()
        gmsh.model.addPhysicalGroup(1, arcs, name="arc")
        gmsh.model.addPhysicalGroup(1, [top], name="top")
        gmsh.model.addPhysicalGroup(2, [disc], name="disc")
        near = gmsh.model.mesh.field.add("Distance")
        gmsh.model.mesh.field.setNumbers(near, "PointsList", [low])
        size = gmsh.model.mesh.field.add("Threshold")
        for key, value in [("InField", near), ("SizeMin", 0.01), ("SizeMax", 0.1),
                           ("DistMin", 0.05), ("DistMax", 1.0)]:
            gmsh.model.mesh.field.setNumber(size, key, value)
        gmsh.model.mesh.field.setAsBackgroundMesh(size)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(2)
        p = contactdd.Problem(name="hertz")
        p.add_material("steel", young=2.1e5, poisson=0.3)
        contactdd.add_gmsh_body(p, "disc", "steel", surface="disc",
                                supports=[{"boundary": "top", "component": "both"}])
    finally:
        gmsh.finalize()
    p.add_rectangle_body("block", (-1.0, 1.0), (-1.0, 0.0), 200, 100, "steel", order="p2",
                         supports=[{"boundary": "bottom", "component": "x"}],
                         loads=[{"kind": "pressure", "boundary": "bottom", "value": 450.0}])
    p.add_contact(("disc", "block"), ("arc", "top"), theta=8e-9)
    result = contactdd.solve(p)
    assert result.converged
    contact = result.contact[0]
    on_disc = np.asarray(contact.side) == 0
    x, y = np.asarray(contact.x)[on_disc], np.asarray(contact.y)[on_disc]
    assert np.abs(np.hypot(x, y - 1.0) - 1.0).max() < 1e-12
    e_star = 2.1e5 / (2 * (1 - 0.3 ** 2))
    a = np.sqrt(4 * 900.0 / (np.pi * e_star))
    p0 = 2 * 900.0 / (np.pi * a)
    assert abs(np.asarray(contact.pressure).max() / p0 - 1) < 0.01


def square(meshio, points, cells, mid=None):
    """A unit square of two triangles as a meshio mesh with physical groups: surface "block"
    (tag 1), curve "bottom" (tag 2)."""
    cell_type, line_type = ("triangle6", "line3") if mid is not None else ("triangle", "line")
    bottom = [0, 1] + ([mid] if mid is not None else [])
    return meshio.Mesh(
        points, [(cell_type, np.array(cells)), (line_type, np.array([bottom]))],
        cell_data={"gmsh:physical": [np.array([1, 1]), np.array([2])],
                   "gmsh:geometrical": [np.array([1, 1]), np.array([1])]},
        field_data={"block": np.array([1, 2]), "bottom": np.array([2, 1])},
    )


def block(add):
    p = contactdd.Problem()
    p.add_material("steel", 1.0, 0.3)
    add(p)
    return p


def test_meshio_rules_clockwise_curved_and_folded_p2():
    meshio = pytest.importorskip("meshio")
    corners = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    ccw, cw = [[0, 1, 2], [0, 2, 3]], [[0, 2, 1], [0, 3, 2]]
    held = [{"boundary": "bottom", "component": "both"}]
    texts = []
    for cells in [ccw, cw]:
        p = block(lambda p: contactdd.add_meshio_body(p, "b", square(meshio, corners, cells),
                                                      "steel", supports=held))
        assert p.boundaries("b") == ["bottom"]
        texts.append(p.to_toml())
    # The clockwise triangles were reordered into the counter-clockwise ones.
    assert texts[0] == texts[1]
    assert "triangles = [[0, 1, 2], [0, 2, 3]]" in texts[0]
    # P2 with the mid-side node of edge (0, 1) off the edge: a curved (isoparametric) triangle.
    mids = [[0.5, -0.1], [1.0, 0.5], [0.5, 0.5], [0.5, 1.0], [0.0, 0.5]]
    p2 = [[0, 1, 2, 4, 5, 6], [0, 2, 3, 6, 7, 8]]
    mesh = square(meshio, corners + mids, p2, mid=4)
    curved = block(lambda p: contactdd.add_meshio_body(p, "b", mesh, "steel", supports=held))
    assert "-0.1" in curved.to_toml()
    # Pulled deep into its triangle, the node folds it: refused, saying where.
    folded = square(meshio, corners + [[0.5, 0.45]] + mids[1:], p2, mid=4)
    with pytest.raises(contactdd.ContactddError, match="folded") as info:
        block(lambda p: contactdd.add_meshio_body(p, "b", folded, "steel", supports=held))
    assert "the meshio mesh" in str(info.value)


def test_clear_import_errors(monkeypatch):
    monkeypatch.setitem(sys.modules, "gmsh", None)
    monkeypatch.setitem(sys.modules, "meshio", None)
    p = contactdd.Problem()
    with pytest.raises(ImportError, match="pip install gmsh"):
        contactdd.add_gmsh_body(p, "b", "steel")
    with pytest.raises(ImportError, match="pip install meshio"):
        contactdd.add_meshio_body(p, "b", object(), "steel")
