#!/usr/bin/env python3
"""Writes punch.msh next to this script with the Gmsh Python API: a round punch pressed into a
block that rests on a base. Three bodies in one file, the mesh fine where the punch touches.

Bodies (physical surfaces) and their boundaries (physical curves and points), lengths in mm:
- "base":  the rectangle [-3, 3] x [-2, 0]; "base-top", "base-bottom";
- "block": the rectangle [-1.5, 1.5] x [0, 1]; "block-top", "block-bottom", and
           "block-centre", the point (0, 0.5) (a mesh node);
- "punch": the lower half of the disc of radius 1 centred at (0, 2); "punch-arc" (its round
           side, touching the block at (0, 1)), "punch-top" (its flat side, y = 2) and
           "punch-mid", the point (0, 2).
The bodies share no node: each is meshed on its own surface (no fragments), so touching bodies
have two nodes where they touch.

Usage: python3 punch.py [--h-contact 0.01]   (needs `pip install gmsh`; docs/tutorial.md).
The committed punch.msh was written with gmsh 4.15.2 and the defaults.
"""

import argparse
from pathlib import Path

import gmsh


def rectangle(occ, x0, x1, y0, y1):
    """A rectangle; returns its surface and its bottom, right, top and left lines."""
    p = [occ.addPoint(x0, y0, 0), occ.addPoint(x1, y0, 0),
         occ.addPoint(x1, y1, 0), occ.addPoint(x0, y1, 0)]
    lines = [occ.addLine(p[i], p[(i + 1) % 4]) for i in range(4)]
    return occ.addPlaneSurface([occ.addCurveLoop(lines)]), lines


def build(h_contact=0.01, h_max=0.2, growth=0.1):
    """Meshes the three bodies in the current Gmsh session (after gmsh.initialize())."""
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("punch")
    occ = gmsh.model.occ

    base, (base_bottom, _, base_top, _) = rectangle(occ, -3.0, 3.0, -2.0, 0.0)
    block, (block_bottom, _, block_top, _) = rectangle(occ, -1.5, 1.5, 0.0, 1.0)
    block_centre = occ.addPoint(0.0, 0.5, 0)

    # The punch: two quarter arcs meeting at its lowest point (0, 1), where it first touches the
    # block, and its flat top split at (0, 2).
    centre, tip = occ.addPoint(0.0, 2.0, 0), occ.addPoint(0.0, 1.0, 0)
    left, right = occ.addPoint(-1.0, 2.0, 0), occ.addPoint(1.0, 2.0, 0)
    arcs = [occ.addCircleArc(left, centre, tip), occ.addCircleArc(tip, centre, right)]
    top = [occ.addLine(right, centre), occ.addLine(centre, left)]
    punch = occ.addPlaneSurface([occ.addCurveLoop(arcs + top)])
    occ.synchronize()
    gmsh.model.mesh.embed(0, [block_centre], 2, block)

    groups = {
        "base": (2, [base]), "base-top": (1, [base_top]), "base-bottom": (1, [base_bottom]),
        "block": (2, [block]), "block-top": (1, [block_top]),
        "block-bottom": (1, [block_bottom]), "block-centre": (0, [block_centre]),
        "punch": (2, [punch]), "punch-arc": (1, arcs), "punch-top": (1, top),
        "punch-mid": (0, [centre]),
    }
    for name, (dim, tags) in groups.items():
        gmsh.model.addPhysicalGroup(dim, tags, name=name)

    # Element size: h_contact at the punch's tip (on the punch and on the block below it),
    # growing with the distance from it up to h_max.
    field = gmsh.model.mesh.field
    distance = field.add("Distance")
    field.setNumbers(distance, "PointsList", [tip])
    size = field.add("MathEval")
    field.setString(size, "F", f"min({h_max}, {h_contact} + {growth} * F{distance})")
    field.setAsBackgroundMesh(size)
    for option in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
        gmsh.option.setNumber(f"Mesh.{option}", 0)
    gmsh.model.mesh.generate(2)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--h-contact", type=float, default=0.01, help="element size at the tip")
    args = parser.parse_args()
    out = Path(__file__).resolve().with_name("punch.msh")
    gmsh.initialize()
    build(args.h_contact)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.write(str(out))
    gmsh.finalize()
    print(f"wrote {out.name}")


if __name__ == "__main__":
    main()
