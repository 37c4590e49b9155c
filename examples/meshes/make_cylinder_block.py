"""Writes the meshes of examples/space/cylinder_block.toml: a slice of thickness 0.04 (along z) of
a quarter of a cylinder of radius 1 resting on a quarter block, both refined along the contact
line (x = y = 0), as curved 10-node tetrahedra (Gmsh's SetOrder(2)).

    pip install gmsh
    python3 examples/meshes/make_cylinder_block.py [h_contact]

The cylinder's cross-section is the part of the circle of centre (0, 1) and radius 1 with x ≥ 0,
y ≤ 1; its faces are `x-` (the symmetry plane), `top` (y = 1), `front` and `back` (z = 0 and
z = 0.04) and `arc`. The block is [0, 1] × [−1, 0] × [0, 0.04] with faces `x-`, `bottom`,
`top`, `front`, `back`. Cells are `h_contact` (default 0.01) within 0.12 of the contact line and
grow to 0.2 at 1 from it.
"""

import sys
from pathlib import Path

import gmsh

HERE = Path(__file__).resolve().parent
T = 0.04


def refine(h_contact):
    """Cells of h_contact near the contact line, growing away from it."""
    occ, f = gmsh.model.occ, gmsh.model.mesh.field
    a, b = occ.addPoint(0, 0, 0), occ.addPoint(0, 0, T)
    line = occ.addLine(a, b)
    occ.synchronize()
    dist = f.add("Distance")
    f.setNumbers(dist, "CurvesList", [line])
    f.setNumber(dist, "Sampling", 20)
    thr = f.add("Threshold")
    f.setNumber(thr, "InField", dist)
    f.setNumber(thr, "SizeMin", h_contact)
    f.setNumber(thr, "SizeMax", 0.2)
    f.setNumber(thr, "DistMin", 0.12)
    f.setNumber(thr, "DistMax", 1.0)
    f.setAsBackgroundMesh(thr)
    for key in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
        gmsh.option.setNumber("Mesh." + key, 0)


def write(name, build, rules, h_contact):
    gmsh.model.add(name)
    volume = build()
    gmsh.model.occ.synchronize()
    refine(h_contact)
    faces = gmsh.model.getBoundary([(3, volume)], oriented=False)
    named = {}
    for dim, tag in faces:
        c = gmsh.model.occ.getCenterOfMass(dim, tag)
        for face, test in rules:
            if test(c):
                named.setdefault(face, []).append(tag)
                break
    for face, tags in named.items():
        gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, tags), face)
    gmsh.model.addPhysicalGroup(3, [volume])
    gmsh.model.mesh.generate(3)
    gmsh.model.mesh.setOrder(2)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.Binary", 0)
    gmsh.option.setNumber("Mesh.SaveAll", 0)
    gmsh.write(str(HERE / f"{name}.msh"))
    gmsh.model.remove()


def cylinder():
    occ = gmsh.model.occ
    c = occ.addCylinder(0, 1, 0, 0, 0, T, 1)
    b = occ.addBox(0, 0, 0, 1, 1, T)
    out, _ = occ.intersect([(3, c)], [(3, b)])
    return out[0][1]


def block():
    return gmsh.model.occ.addBox(0, -1, 0, 1, 1, T)


def main():
    h_contact = float(sys.argv[1]) if len(sys.argv) > 1 else 0.01
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    eps = 1e-9
    ends = [("front", lambda c: abs(c[2]) < eps), ("back", lambda c: abs(c[2] - T) < eps)]
    write(
        "slice_cylinder",
        cylinder,
        [("x-", lambda c: abs(c[0]) < eps), ("top", lambda c: abs(c[1] - 1) < eps)]
        + ends
        + [("arc", lambda c: True)],
        h_contact,
    )
    write(
        "slice_block",
        block,
        [
            ("x-", lambda c: abs(c[0]) < eps),
            ("bottom", lambda c: abs(c[1] + 1) < eps),
            ("top", lambda c: abs(c[1]) < eps),
        ]
        + ends,
        h_contact,
    )
    gmsh.finalize()


if __name__ == "__main__":
    main()
