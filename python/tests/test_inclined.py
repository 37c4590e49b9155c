"""Normal supports on inclined straight boundaries, from Python: a block pressed on another by a
pressure, both held by symmetry lines, built axis-parallel and turned as a whole by 30°. The
contact pressures are the same, the contact forces turn with the model, and a kinked boundary
is refused."""

import math

import numpy as np
import pytest

import contactdd
from contactdd import ContactddError


def block(y0, nx, ny):
    """A 2 × 1 block [0, 2] × [y0, y0 + 1] of P1 triangles, its boundaries as edge lists."""
    xs, ys = np.linspace(0.0, 2.0, nx + 1), np.linspace(y0, y0 + 1.0, ny + 1)
    nodes = np.array([[x, y] for y in ys for x in xs])

    def idx(i, j):
        return j * (nx + 1) + i

    triangles = []
    for j in range(ny):
        for i in range(nx):
            a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
            triangles += [[a, b, c], [a, c, d]]
    edges = {
        "bottom": [[idx(i, 0), idx(i + 1, 0)] for i in range(nx)],
        "right": [[idx(nx, j), idx(nx, j + 1)] for j in range(ny)],
        "top": [[idx(i + 1, ny), idx(i, ny)] for i in range(nx)],
        "left": [[idx(0, j + 1), idx(0, j)] for j in range(ny)],
    }
    return nodes, np.array(triangles), edges


def pressed_blocks(angle):
    """The lower block sits on a sliding floor, both blocks slide along the symmetry line x = 0;
    the upper one (a finer mesh: non-matching) is pressed down on its top."""
    c, s = math.cos(angle), math.sin(angle)
    turn = np.array([[c, -s], [s, c]])
    p = contactdd.Problem(name="pressed blocks")
    p.add_material("steel", 2.1e5, 0.3)
    for name, y0, (nx, ny), supports, loads in [
        ("lower", 0.0, (8, 4), ["bottom", "left"], []),
        ("upper", 1.0, (11, 5), ["left"], [{"kind": "pressure", "boundary": "top",
                                             "value": 100.0}]),
    ]:
        nodes, triangles, edges = block(y0, nx, ny)
        p.add_body(name, nodes @ turn.T, triangles, edges, "steel",
                   supports=[{"boundary": b, "component": "normal"} for b in supports],
                   loads=loads)
    p.add_contact(("lower", "upper"), ("top", "bottom"), theta=1e-5, name="pair")
    return p, turn


def test_a_turned_model_gives_the_same_pressures_and_turned_forces():
    straight, _ = pressed_blocks(0.0)
    turned, turn = pressed_blocks(math.radians(30.0))
    a, b = contactdd.solve(straight), contactdd.solve(turned)
    assert a.converged and b.converged, (a.message, b.message)
    pa, pb = a.contact[0].pressure, b.contact[0].pressure
    assert np.abs(pa).max() > 50.0
    assert np.abs(pa - pb).max() <= 1e-8 * np.abs(pa).max()
    for side in range(2):
        fa, fb = np.array(a.contact[0].forces[side]), np.array(b.contact[0].forces[side])
        assert np.abs(turn @ fa - fb).max() <= 1e-8 * np.abs(fa).max()
    # The lower block's contact force balances the load (200 on a 2-wide top), pointing down
    # in the block's own frame.
    assert np.allclose(a.contact[0].forces[0], [0.0, -200.0], rtol=0.0, atol=0.05 * 200.0)


def test_a_kinked_boundary_is_refused_for_a_normal_support():
    nodes, triangles, edges = block(0.0, 4, 2)
    p = contactdd.Problem()
    p.add_material("steel", 2.1e5, 0.3)
    kinked = edges["bottom"] + edges["right"]
    with pytest.raises(ContactddError, match="'corner': a 'normal' support needs a straight"):
        p.add_body("b", nodes, triangles, {"corner": kinked}, "steel",
                   supports=[{"boundary": "corner", "component": "normal"}])
    assert p.bodies == []
