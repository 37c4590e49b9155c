#!/usr/bin/env python3
"""Writes examples/meshes/cylinder_plates.msh with the Gmsh Python API: a cylinder pressed
between two plates, three bodies in one file, triangles graded towards the two contact points.

Bodies (physical surfaces) and their boundaries (physical curves and points):
- "cylinder": the disc of radius R centred at (0, 0); "cyl-bottom" (the lower half of its
  circle), "cyl-top" (the upper half), "cyl-centre" (its centre, a mesh node);
- "lower": the plate [-W, W] x [-R - H, -R]; "lower-top", "lower-bottom";
- "upper": the plate [-W, W] x [R, R + H]; "upper-bottom", "upper-top", "upper-mid" (the
  midpoint of its top, a mesh node).
The bodies share no node: the cylinder touches each plate at one point, where both have a node.

Usage: python3 make_cylinder_plates.py [-o cylinder_plates.msh] [--h-contact 0.004]
(needs `pip install gmsh`; the committed .msh was written with gmsh 4.15.2 and the defaults).
`build()` meshes the model in the current Gmsh session without writing it, for Python's
`contactdd.add_gmsh_body` (python/tests/test_meshes.py).
"""

import argparse

import gmsh

R, W, H = 1.0, 2.0, 1.0


def plate(occ, y0, y1):
    """A rectangle [-W, W] x [y0, y1] with a point at the middle of its bottom and of its top;
    returns its surface, its bottom lines, its top lines and the two middle points."""
    p = [occ.addPoint(-W, y0, 0), occ.addPoint(0, y0, 0), occ.addPoint(W, y0, 0),
         occ.addPoint(W, y1, 0), occ.addPoint(0, y1, 0), occ.addPoint(-W, y1, 0)]
    lines = [occ.addLine(p[i], p[(i + 1) % 6]) for i in range(6)]
    surface = occ.addPlaneSurface([occ.addCurveLoop(lines)])
    return surface, lines[0:2], lines[3:5], (p[1], p[4])


def build(h_contact=0.004, h_max=0.1, growth=0.05):
    """Meshes the three bodies in the current Gmsh session (gmsh initialised)."""
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("cylinder_plates")
    occ = gmsh.model.occ
    # The cylinder: its centre (embedded as a mesh node) and four points of its circle.
    c = occ.addPoint(0, 0, 0)
    bottom, right = occ.addPoint(0, -R, 0), occ.addPoint(R, 0, 0)
    top, left = occ.addPoint(0, R, 0), occ.addPoint(-R, 0, 0)
    arcs = [occ.addCircleArc(a, c, b) for a, b in [(bottom, right), (right, top), (top, left), (left, bottom)]]
    cylinder = occ.addPlaneSurface([occ.addCurveLoop(arcs)])
    lower, lower_bottom, lower_top, _ = plate(occ, -R - H, -R)
    upper, upper_bottom, upper_top, (_, upper_mid) = plate(occ, R, R + H)
    occ.synchronize()
    gmsh.model.mesh.embed(0, [c], 2, cylinder)

    groups = {
        "cylinder": (2, [cylinder]), "cyl-bottom": (1, [arcs[3], arcs[0]]),
        "cyl-top": (1, [arcs[1], arcs[2]]), "cyl-centre": (0, [c]),
        "lower": (2, [lower]), "lower-top": (1, lower_top), "lower-bottom": (1, lower_bottom),
        "upper": (2, [upper]), "upper-bottom": (1, upper_bottom), "upper-top": (1, upper_top),
        "upper-mid": (0, [upper_mid]),
    }
    for name, (dim, tags) in groups.items():
        gmsh.model.addPhysicalGroup(dim, tags, name=name)

    # Size field: h_contact at the contact points, growing linearly with the distance.
    field = gmsh.model.mesh.field
    dist = field.add("Distance")
    field.setNumbers(dist, "PointsList", [bottom, top])
    grow = field.add("MathEval")
    field.setString(grow, "F", f"min({h_max}, {h_contact} + {growth} * F{dist})")
    field.setAsBackgroundMesh(grow)
    for option in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
        gmsh.option.setNumber(f"Mesh.{option}", 0)
    gmsh.model.mesh.generate(2)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", default="cylinder_plates.msh")
    parser.add_argument("--h-contact", type=float, default=0.004, help="element size at the contacts")
    parser.add_argument("--h-max", type=float, default=0.1, help="largest element size")
    parser.add_argument("--growth", type=float, default=0.05, help="size growth per unit distance")
    args = parser.parse_args()

    gmsh.initialize()
    build(args.h_contact, args.h_max, args.growth)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.write(args.output)
    gmsh.finalize()


if __name__ == "__main__":
    main()
