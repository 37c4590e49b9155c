"""Writes two_blocks.msh: two bodies in one Gmsh MSH 4.1 ASCII file, for the tests.

The lower block [0, 2] x [0, 1] (physical surface "lower") and the upper block [0, 2] x [1, 2]
(physical surface "upper") touch along y = 1 without sharing nodes. Physical curves: "floor"
(bottom of lower), "lower-top", "upper-bottom", "load" (top of upper) and "left" (x = 0 of both
bodies: one group touching two surfaces). Physical point "origin" at (0, 0). Each block has
nx x ny cells of two triangles; the upper block's diagonals run the other way.

Run: python3 make_two_blocks.py > two_blocks.msh (no dependency: written by hand, as Gmsh would).
"""

NX, NY = 4, 2


def block(y0, first_tag, flip):
    """Nodes {(i, j): (tag, x, y)} and counter-clockwise triangles (node tags) of one block."""
    nodes = {}
    tag = first_tag
    for j in range(NY + 1):
        for i in range(NX + 1):
            nodes[(i, j)] = (tag, 2.0 * i / NX, y0 + float(j) / NY)
            tag += 1
    tris = []
    for j in range(NY):
        for i in range(NX):
            a, b, c, d = (nodes[k][0] for k in [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)])
            tris += [(a, b, d), (b, c, d)] if flip else [(a, b, c), (a, c, d)]
    return nodes, tris


def side(nodes, cells):
    """Line elements (pairs of node tags) through the node indices `cells`."""
    tags = [nodes[k][0] for k in cells]
    return list(zip(tags, tags[1:]))


lower, lower_tris = block(0.0, 1, False)
upper, upper_tris = block(1.0, 1 + len(lower), True)
row = lambda nodes, j: side(nodes, [(i, j) for i in range(NX + 1)])
col = lambda nodes, i: side(nodes, [(i, j) for j in range(NY + 1)])
# (curve entity, physical tag, line elements)
curves = [
    (1, 11, row(lower, 0)),
    (2, 12, row(lower, NY)),
    (3, 13, row(upper, 0)),
    (4, 14, row(upper, NY)),
    (5, 15, col(lower, 0)),
    (6, 15, col(upper, 0)),
]
out = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat", "$PhysicalNames", "8"]
out += ['0 30 "origin"', '1 11 "floor"', '1 12 "lower-top"', '1 13 "upper-bottom"']
out += ['1 14 "load"', '1 15 "left"', '2 21 "lower"', '2 22 "upper"', "$EndPhysicalNames"]
out += ["$Entities", "1 6 2 0", "1 0 0 0 1 30"]
for entity, physical, _ in curves:
    out.append(f"{entity} 0 0 0 2 2 0 1 {physical} 0")
out += ["1 0 0 0 2 1 0 1 21 0", "2 0 1 0 2 2 0 1 22 0", "$EndEntities"]
all_nodes = sorted(list(lower.values()) + list(upper.values()))
out += ["$Nodes", f"2 {len(all_nodes)} 1 {len(all_nodes)}"]
for entity, nodes in [(1, lower), (2, upper)]:
    block_nodes = sorted(nodes.values())
    out.append(f"2 {entity} 0 {len(block_nodes)}")
    out += [str(t) for t, _, _ in block_nodes]
    out += [f"{x:g} {y:g} 0" for _, x, y in block_nodes]
out.append("$EndNodes")
blocks = [(0, 1, 15, [(lower[(0, 0)][0],)])]
blocks += [(1, entity, 1, lines) for entity, _, lines in curves]
blocks += [(2, 1, 2, lower_tris), (2, 2, 2, upper_tris)]
total = sum(len(b[3]) for b in blocks)
out += ["$Elements", f"{len(blocks)} {total} 1 {total}"]
tag = 1
for dim, entity, ty, elements in blocks:
    out.append(f"{dim} {entity} {ty} {len(elements)}")
    for e in elements:
        out.append(" ".join(str(v) for v in (tag,) + tuple(e)))
        tag += 1
out.append("$EndElements")
print("\n".join(out))
