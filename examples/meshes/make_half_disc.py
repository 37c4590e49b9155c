#!/usr/bin/env python3
"""Writes a graded triangle mesh of a half disc as a Gmsh MSH 4.1 ASCII file (no gmsh needed).

The body is the lower half of the disc of radius R centred at (0, R + gap): its curved
boundary touches the line y = gap at the contact point (0, gap), and its flat side is the line
y = R + gap. Elements are small near the contact point (longest edge `--h-contact`, R/200 by
default) and grow linearly with the distance to it (`--grading`) up to `--h-max`.

Method: a coarse polar mesh of the right quarter (x >= 0) is refined by Rivara's longest-edge
bisection (LEPP), which keeps the mesh conforming and the angles bounded away from zero; new
nodes on the arc are projected onto the circle. The quarter is then mirrored in x = 0, so the
mesh is symmetric and the contact point is a node.

With `--order 2` the triangles are curved 6-node triangles (Gmsh's `SetOrder(2)`): the mid-side
nodes of the arc lie on the circle, the others at their edges' midpoints.

Physical groups: lines "arc" (curved lower boundary) and "top" (flat side), surface "disc".

Usage: python3 make_half_disc.py [-o half_disc.msh] [--radius 1] [--gap 0] ...
"""

import argparse
import math


def coarse_quarter(radius, rings):
    """Polar mesh of the quarter disc x >= 0, y <= R around the centre O = (0, R).

    Returns (nodes, triangles); ring k (radius k R / rings) has 2k + 1 nodes from the bottom
    ray (angle -pi/2, the symmetry line) to the top line (angle 0).
    """
    nodes = [(0.0, radius)]
    ring_ids = [[0]]
    for k in range(1, rings + 1):
        r = radius * k / rings
        ids = []
        for j in range(2 * k + 1):
            theta = -0.5 * math.pi + 0.5 * math.pi * j / (2 * k)
            x, y = r * math.cos(theta), radius + r * math.sin(theta)
            # Exact coordinates on the symmetry line and on the top line.
            if j == 0:
                x = 0.0
            if j == 2 * k:
                y = radius
            ids.append(len(nodes))
            nodes.append((x, y))
        ring_ids.append(ids)
    triangles = []
    for k in range(1, rings + 1):
        inner, outer = ring_ids[k - 1], ring_ids[k]
        # Stitch two consecutive rings by angle: advance on the ring whose next node comes first.
        i, j = 0, 0
        while i < len(inner) - 1 or j < len(outer) - 1:
            next_inner = (i + 1) / (len(inner) - 1) if i < len(inner) - 1 else 2.0
            next_outer = (j + 1) / (len(outer) - 1) if j < len(outer) - 1 else 2.0
            if next_outer <= next_inner:
                triangles.append((inner[i], outer[j], outer[j + 1]))
                j += 1
            else:
                triangles.append((inner[i], outer[j], inner[i + 1]))
                i += 1
    return nodes, [orient(nodes, t) for t in triangles]


def area2(nodes, t):
    (x0, y0), (x1, y1), (x2, y2) = (nodes[v] for v in t)
    return (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)


def orient(nodes, t):
    """The triangle in counter-clockwise order."""
    return t if area2(nodes, t) > 0 else (t[0], t[2], t[1])


class Refiner:
    """Longest-edge (LEPP) bisection of a conforming triangle mesh."""

    def __init__(self, nodes, triangles, radius):
        self.nodes = list(nodes)
        self.radius = radius
        self.tris = {}
        self.edge_tris = {}
        self.next_id = 0
        for t in triangles:
            self.add(t)
        # Boundary edges lie on exactly one triangle; remember which boundary they belong to.
        self.kind = {}
        for e, owners in self.edge_tris.items():
            if len(owners) == 1:
                self.kind[e] = self.classify(e)

    def classify(self, e):
        (xa, ya), (xb, yb) = self.nodes[e[0]], self.nodes[e[1]]
        eps = 1e-12 * self.radius
        if abs(xa) < eps and abs(xb) < eps:
            return "symmetry"
        if abs(ya - self.radius) < eps and abs(yb - self.radius) < eps:
            return "top"
        return "arc"

    def add(self, t):
        tid = self.next_id
        self.next_id += 1
        self.tris[tid] = t
        for e in edges(t):
            self.edge_tris.setdefault(e, set()).add(tid)
        return tid

    def remove(self, tid):
        t = self.tris.pop(tid)
        for e in edges(t):
            self.edge_tris[e].discard(tid)
            if not self.edge_tris[e]:
                del self.edge_tris[e]
        return t

    def length(self, e):
        (xa, ya), (xb, yb) = self.nodes[e[0]], self.nodes[e[1]]
        return math.hypot(xb - xa, yb - ya)

    def longest(self, tid):
        # Ties are broken by node numbers, the same way in both triangles of an edge.
        return max(edges(self.tris[tid]), key=lambda e: (self.length(e), e))

    def neighbour(self, tid, e):
        others = self.edge_tris[e] - {tid}
        return next(iter(others)) if others else None

    def split_edge(self, e):
        """Bisects edge e and the one or two triangles on it."""
        (xa, ya), (xb, yb) = self.nodes[e[0]], self.nodes[e[1]]
        mx, my = 0.5 * (xa + xb), 0.5 * (ya + yb)
        kind = self.kind.pop(e, None)
        if kind == "arc":
            # Project onto the circle: outwards, so the children keep a positive area.
            dx, dy = mx, my - self.radius
            scale = self.radius / math.hypot(dx, dy)
            mx, my = dx * scale, self.radius + dy * scale
        m = len(self.nodes)
        self.nodes.append((mx, my))
        for tid in list(self.edge_tris[e]):
            t = self.remove(tid)
            # Rotate so that e = (t[0], t[1]) in the triangle's own (counter-clockwise) order.
            while {t[0], t[1]} != set(e):
                t = (t[1], t[2], t[0])
            self.add((t[0], m, t[2]))
            self.add((m, t[1], t[2]))
        if kind is not None:
            self.kind[edge_key(e[0], m)] = kind
            self.kind[edge_key(m, e[1])] = kind

    def bisect(self, tid):
        """Rivara's LEPP bisection: refines along the longest-edge propagation path of tid."""
        while tid in self.tris:
            path = [tid]
            while True:
                t = path[-1]
                e = self.longest(t)
                n = self.neighbour(t, e)
                if n is None or self.longest(n) == e:
                    self.split_edge(e)
                    break
                path.append(n)

    def refine(self, size):
        """Bisects until every triangle's longest edge is at most size(x, y) at its vertices."""
        changed = True
        while changed:
            changed = False
            for tid in list(self.tris):
                if tid not in self.tris:
                    continue
                t = self.tris[tid]
                h = min(size(*self.nodes[v]) for v in t)
                if self.length(self.longest(tid)) > h:
                    self.bisect(tid)
                    changed = True


def edge_key(a, b):
    return (a, b) if a < b else (b, a)


def edges(t):
    return [edge_key(t[0], t[1]), edge_key(t[1], t[2]), edge_key(t[2], t[0])]


def half_disc(radius, h_contact, grading, h_max, rings):
    """The mirrored, refined mesh: (nodes, triangles, arc edges, top edges), contact at (0, 0)."""
    nodes, triangles = coarse_quarter(radius, rings)
    refiner = Refiner(nodes, triangles, radius)
    refiner.refine(lambda x, y: min(h_max, h_contact + grading * math.hypot(x, y)))

    # Keep the nodes in use, numbered from 0, then mirror the quarter in x = 0.
    quarter = sorted(refiner.tris.values())
    used = sorted({v for t in quarter for v in t})
    eps = 1e-12 * radius
    out_nodes, index, mirror = [], {}, {}
    for v in used:
        index[v] = len(out_nodes)
        out_nodes.append(refiner.nodes[v])
    for v in used:
        x, y = refiner.nodes[v]
        if abs(x) < eps:
            mirror[v] = index[v]
        else:
            mirror[v] = len(out_nodes)
            out_nodes.append((-x, y))
    tris = [tuple(index[v] for v in t) for t in quarter]
    tris += [(mirror[t[0]], mirror[t[2]], mirror[t[1]]) for t in quarter]

    boundary = {"arc": [], "top": []}
    for e, kind in sorted(refiner.kind.items()):
        if kind in boundary:
            boundary[kind].append((index[e[0]], index[e[1]]))
            boundary[kind].append((mirror[e[0]], mirror[e[1]]))
    return out_nodes, tris, boundary["arc"], boundary["top"]


def promote(nodes, tris, arc, top, radius):
    """The curved P2 mesh of the same triangles: a node at the middle of every edge, on the
    circle (on the bisector of its vertices' radii from the centre (0, R)) for the arc's edges,
    on the chord elsewhere. Triangles list their vertices, then the mid-side nodes of (0, 1),
    (1, 2), (2, 0); edges their vertices, then their mid-side node (Gmsh's 6-node triangle and
    3-node line)."""
    nodes = list(nodes)
    on_arc = {edge_key(*e) for e in arc}
    mid = {}

    def middle(a, b):
        key = edge_key(a, b)
        if key not in mid:
            (xa, ya), (xb, yb) = nodes[a], nodes[b]
            if key in on_arc:
                # The bisector of the two radii: no wrap-around at the angle ±π.
                ux, uy = xa + xb, (ya - radius) + (yb - radius)
                scale = radius / math.hypot(ux, uy)
                nodes.append((scale * ux, radius + scale * uy))
            else:
                nodes.append((0.5 * (xa + xb), 0.5 * (ya + yb)))
            mid[key] = len(nodes) - 1
        return mid[key]

    tris6 = [t + (middle(t[0], t[1]), middle(t[1], t[2]), middle(t[2], t[0])) for t in tris]
    arc3 = [e + (middle(*e),) for e in arc]
    top3 = [e + (middle(*e),) for e in top]
    return nodes, tris6, arc3, top3


def write_msh(path, nodes, tris, arc, top, radius, gap):
    """Writes MSH 4.1 ASCII: points A (left) and C (right), curves arc (A to C) and top (C to A)."""
    a_node = min(range(len(nodes)), key=lambda v: (nodes[v][0], -nodes[v][1]))
    c_node = max(range(len(nodes)), key=lambda v: (nodes[v][0], nodes[v][1]))
    arc_nodes = {v for e in arc for v in e} - {a_node, c_node}
    top_nodes = {v for e in top for v in e} - {a_node, c_node} - arc_nodes
    inner = [v for v in range(len(nodes)) if v not in arc_nodes | top_nodes | {a_node, c_node}]
    # Node tags are 1-based: tag = index + 1. Nodes are listed by the entity they lie on.
    blocks = [
        (0, 1, [a_node]),
        (0, 2, [c_node]),
        (1, 1, sorted(arc_nodes, key=lambda v: nodes[v][0])),
        (1, 2, sorted(top_nodes, key=lambda v: -nodes[v][0])),
        (2, 1, inner),
    ]
    xs = [p[0] for p in nodes]
    ys = [p[1] + gap for p in nodes]
    xmin, xmax, ymin, ymax = min(xs), max(xs), min(ys), max(ys)

    def xyz(v):
        return f"{nodes[v][0]!r} {nodes[v][1] + gap!r} 0"

    lines = [
        "$MeshFormat",
        "4.1 0 8",
        "$EndMeshFormat",
        "$PhysicalNames",
        "3",
        '1 1 "arc"',
        '1 2 "top"',
        '2 3 "disc"',
        "$EndPhysicalNames",
        "$Entities",
        "2 2 1 0",
        f"1 {xyz(a_node)} 0",
        f"2 {xyz(c_node)} 0",
        f"1 {xmin!r} {ymin!r} 0 {xmax!r} {ymax!r} 0 1 1 2 1 -2",
        f"2 {xmin!r} {ymax!r} 0 {xmax!r} {ymax!r} 0 1 2 2 2 -1",
        f"1 {xmin!r} {ymin!r} 0 {xmax!r} {ymax!r} 0 1 3 2 1 2",
        "$EndEntities",
        "$Nodes",
        f"{len(blocks)} {len(nodes)} 1 {len(nodes)}",
    ]
    for dim, tag, ids in blocks:
        lines.append(f"{dim} {tag} 0 {len(ids)}")
        lines.extend(str(v + 1) for v in ids)
        lines.extend(xyz(v) for v in ids)
    lines.append("$EndNodes")

    def along(edge_list, key):
        return sorted(edge_list, key=lambda e: key(0.5 * (nodes[e[0]][0] + nodes[e[1]][0])))

    # Gmsh types: 2-node line 1, 3-node triangle 2; 3-node line 8, 6-node triangle 9.
    line, triangle = (1, 2) if len(tris[0]) == 3 else (8, 9)
    element_blocks = [
        (1, 1, line, along(arc, lambda x: x)),
        (1, 2, line, along(top, lambda x: -x)),
        (2, 1, triangle, tris),
    ]
    count = sum(len(b[3]) for b in element_blocks)
    lines += ["$Elements", f"{len(element_blocks)} {count} 1 {count}"]
    tag = 1
    for dim, entity, etype, elements in element_blocks:
        lines.append(f"{dim} {entity} {etype} {len(elements)}")
        for element in elements:
            lines.append(f"{tag} " + " ".join(str(v + 1) for v in element))
            tag += 1
    lines.append("$EndElements")
    with open(path, "w", encoding="ascii") as f:
        f.write("\n".join(lines) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("-o", "--output", default="half_disc.msh", help="output .msh file")
    parser.add_argument("--radius", type=float, default=1.0, help="disc radius R")
    parser.add_argument("--gap", type=float, default=0.0, help="height of the contact point")
    parser.add_argument("--h-contact", type=float, help="element size at the contact (R/200)")
    parser.add_argument("--grading", type=float, default=0.1, help="size growth per unit length")
    parser.add_argument("--h-max", type=float, help="largest element size (R/10)")
    parser.add_argument("--rings", type=int, default=5, help="rings of the coarse polar mesh")
    parser.add_argument("--order", type=int, choices=(1, 2), default=1,
                        help="2: curved 6-node triangles, the arc's mid-side nodes on the circle")
    args = parser.parse_args()
    radius = args.radius
    if not (radius > 0 and math.isfinite(radius)):
        parser.error("the radius must be positive")
    h_contact = args.h_contact if args.h_contact is not None else radius / 200
    h_max = args.h_max if args.h_max is not None else radius / 10
    if not (0 < h_contact <= h_max and args.grading >= 0 and args.rings >= 1):
        parser.error("need 0 < h-contact <= h-max, grading >= 0 and rings >= 1")

    nodes, tris, arc, top = half_disc(radius, h_contact, args.grading, h_max, args.rings)
    for t in tris:
        assert area2(nodes, t) > 0, "inverted triangle"
    if args.order == 2:
        nodes, tris, arc, top = promote(nodes, tris, arc, top, radius)
    write_msh(args.output, nodes, tris, arc, top, radius, args.gap)
    print(
        f"{args.output}: {len(nodes)} nodes, {len(tris)} triangles, "
        f"{len(arc)} arc edges, {len(top)} top edges"
    )


if __name__ == "__main__":
    main()
