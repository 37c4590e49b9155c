"""Balanced contact pairs from Python: on non-matching meshes the default `forces="balanced"`
gives equal and opposite forces on the two sides, `forces="own-side"` (the paper's formulation)
does not, and a misspelt choice is refused with the pair's name."""

import math

import numpy as np
import pytest

import contactdd
from contactdd import ContactddError

from test_inclined import block


def pressed_blocks(forces=None):
    """A block (11 × 5 cells) pressed onto another (8 × 4): non-matching contact edges."""
    p = contactdd.Problem(name="pressed blocks")
    p.add_material("steel", 2.1e5, 0.3)
    for name, y0, (nx, ny), supports, loads in [
        ("lower", 0.0, (8, 4), [{"boundary": "bottom", "component": "both"}], []),
        ("upper", 1.0, (11, 5), [{"boundary": "left", "component": "x"}],
         [{"kind": "pressure", "boundary": "top", "value": 100.0}]),
    ]:
        nodes, triangles, edges = block(y0, nx, ny)
        p.add_body(name, nodes, triangles, edges, "steel", supports=supports, loads=loads)
    p.add_contact(("lower", "upper"), ("top", "bottom"), theta=1e-5, name="pair", forces=forces)
    return p


def imbalance(result):
    (a, b) = result.contact[0].forces
    return math.hypot(a[0] + b[0], a[1] + b[1]) / math.hypot(*a)


def test_balanced_sides_carry_equal_and_opposite_forces():
    default = contactdd.solve(pressed_blocks())
    # Own-side sides differ, so the problem's loads and reactions do not balance: refused by
    # default, a result when balance_tol accepts the difference.
    with pytest.raises(contactdd.ConvergenceError, match="own-side"):
        contactdd.solve(pressed_blocks("own-side"))
    own = contactdd.solve(pressed_blocks("own-side"), balance_tol=1e-2)
    assert default.converged and own.converged
    assert imbalance(default) <= 1e-10
    assert imbalance(own) > 1e-6
    # Both carry the applied load 100 · 2 on the loaded body's side, the sum of the nodal forces.
    contact = default.contact[0]
    assert contact.forces[1][1] == pytest.approx(200.0, rel=1e-8)
    upper = contact.side == 1
    assert contact.nodal_force[upper].sum(axis=0) == pytest.approx(contact.forces[1], abs=1e-9)
    assert np.all(np.asarray(default.contact[0].nodal_traction) <= 1e-9 * 100.0)
    assert np.all(np.asarray(default.contact[0].pressure) >= 0.0)


def test_an_unknown_choice_is_refused():
    with pytest.raises(ContactddError, match="pair"):
        pressed_blocks("both-sides")
