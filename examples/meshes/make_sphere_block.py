"""Writes the meshes of examples/space/sphere_block.toml and ball_between_plates.toml: a quarter
of a ball of radius 1 resting on a quarter block, both refined around the contact point (the
origin), and a whole quarter ball refined at both poles, as curved 10-node tetrahedra (Gmsh's
SetOrder(2)).

    pip install gmsh
    python3 examples/meshes/make_sphere_block.py [h_contact]

The ball (quarter_ball.msh) is the part of the sphere of centre (0, 0, 1) with x ≥ 0, y ≥ 0,
z ≤ 1; its faces are `x-` and `y-` (the symmetry planes), `top` (z = 1) and `surface` (the
sphere). The whole quarter ball (quarter_ball_whole.msh) has x ≥ 0, y ≥ 0 and faces `x-`, `y-`
and `surface`, with cells twice `h_contact` at both poles. The block is
[0, 2] × [0, 2] × [−2, 0]; its faces are `x-`, `y-`, `bottom` (z = −2) and `top` (z = 0), the
others unnamed. The cells are `h_contact` (default 0.02) within 0.12 of the origin and grow to
0.4 at 1.5 from it.
"""

import sys
from pathlib import Path

import gmsh

HERE = Path(__file__).resolve().parent


def refine(h_contact, poles=((0, 0, 0),)):
    """Cells of h_contact near the poles, growing away from them."""
    f = gmsh.model.mesh.field
    points = [gmsh.model.occ.addPoint(*x) for x in poles]
    gmsh.model.occ.synchronize()
    dist = f.add("Distance")
    f.setNumbers(dist, "PointsList", points)
    thr = f.add("Threshold")
    f.setNumber(thr, "InField", dist)
    f.setNumber(thr, "SizeMin", h_contact)
    f.setNumber(thr, "SizeMax", 0.4)
    f.setNumber(thr, "DistMin", 0.12)
    f.setNumber(thr, "DistMax", 1.5)
    f.setAsBackgroundMesh(thr)
    for key in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
        gmsh.option.setNumber("Mesh." + key, 0)


def name_faces(volume, rules):
    """Names every boundary face of `volume` by the first rule its centre of mass meets."""
    faces = gmsh.model.getBoundary([(3, volume)], oriented=False)
    named = {}
    for dim, tag in faces:
        c = gmsh.model.occ.getCenterOfMass(dim, tag)
        for name, test in rules:
            if test(c):
                named.setdefault(name, []).append(tag)
                break
    for name, tags in named.items():
        gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, tags), name)
    gmsh.model.addPhysicalGroup(3, [volume])


def write(name, build, rules, h_contact, poles=((0, 0, 0),)):
    gmsh.model.add(name)
    volume = build()
    gmsh.model.occ.synchronize()
    refine(h_contact, poles)
    name_faces(volume, rules)
    gmsh.model.mesh.generate(3)
    gmsh.model.mesh.setOrder(2)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.Binary", 0)
    gmsh.option.setNumber("Mesh.SaveAll", 0)
    gmsh.write(str(HERE / f"{name}.msh"))
    gmsh.model.remove()


def ball():
    occ = gmsh.model.occ
    s = occ.addSphere(0, 0, 1, 1)
    b = occ.addBox(0, 0, 0, 1, 1, 1)
    out, _ = occ.intersect([(3, s)], [(3, b)])
    return out[0][1]


def whole_ball():
    occ = gmsh.model.occ
    s = occ.addSphere(0, 0, 1, 1)
    b = occ.addBox(0, 0, 0, 1, 1, 2)
    out, _ = occ.intersect([(3, s)], [(3, b)])
    return out[0][1]


def block():
    return gmsh.model.occ.addBox(0, 0, -2, 2, 2, 2)


def main():
    h_contact = float(sys.argv[1]) if len(sys.argv) > 1 else 0.02
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    eps = 1e-9
    write(
        "quarter_ball",
        ball,
        [
            ("x-", lambda c: abs(c[0]) < eps),
            ("y-", lambda c: abs(c[1]) < eps),
            ("top", lambda c: abs(c[2] - 1) < eps),
            ("surface", lambda c: True),
        ],
        h_contact,
    )
    write(
        "quarter_block",
        block,
        [
            ("x-", lambda c: abs(c[0]) < eps),
            ("y-", lambda c: abs(c[1]) < eps),
            ("bottom", lambda c: abs(c[2] + 2) < eps),
            ("top", lambda c: abs(c[2]) < eps),
        ],
        h_contact,
    )
    write(
        "quarter_ball_whole",
        whole_ball,
        [
            ("x-", lambda c: abs(c[0]) < eps),
            ("y-", lambda c: abs(c[1]) < eps),
            ("surface", lambda c: True),
        ],
        2 * h_contact,
        poles=((0, 0, 0), (0, 0, 2)),
    )
    gmsh.finalize()


if __name__ == "__main__":
    main()
