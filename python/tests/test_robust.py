"""Inputs that must be refused rather than misread: fractional node indices, a benchmark too big
for the problem-file limit, a too-big problem, a contact pair whose boundaries face away; and the
place of ConvergenceError among the error classes."""

import numpy as np
import pytest

import contactdd
from contactdd import ContactddError, ConvergenceError


def triangle_problem():
    p = contactdd.Problem()
    p.add_material("steel", 2.1e5, 0.3)
    nodes = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    return p, nodes


def test_fractional_node_indices_are_refused_not_truncated():
    p, nodes = triangle_problem()
    with pytest.raises(ContactddError, match="node index 0.5 is not an integer"):
        p.add_body("t", nodes, np.array([[0.5, 1.0, 2.0]]), {}, "steel")
    with pytest.raises(ContactddError, match="not an integer"):
        p.add_body("t", nodes, np.array([[0.0, 1.0, np.nan]]), {}, "steel")
    with pytest.raises(ContactddError, match="boundaries\\['base'\\]: node index 1.25"):
        p.add_body("t", nodes, [[0, 1, 2]], {"base": np.array([[0.0, 1.25]])}, "steel")
    assert p.bodies == []


def test_integer_valued_float_indices_are_accepted():
    # Arrays read with numpy.loadtxt are floats: 2.0 names node 2.
    p, nodes = triangle_problem()
    p.add_body("t", nodes, np.array([[0.0, 1.0, 2.0]]), {"base": np.array([[0.0, 1.0]])},
               "steel", supports=[{"boundary": "base", "component": "both"}])
    assert p.boundaries("t") == ["base"]


def test_a_benchmark_beyond_the_cell_limit_raises_instead_of_aborting():
    with pytest.raises(ContactddError, match="more than the limit"):
        contactdd.notch_benchmark(nx=300000, ny=300000)
    with pytest.raises(ContactddError, match="more than the limit"):
        contactdd.notch_benchmark(nx=2**40, ny=2**40)  # nx · ny overflows


def test_a_contact_zone_too_long_for_the_dense_condensation_solves_on_the_sparse_path():
    # Two strips of 70000 × 1 cells in contact along their length: the dense condensation alone
    # would need 8 m² bytes per body with m = 70001 contact points, 78 GB for both. The cost model
    # takes the sparse path (docs/sparse-path.md), whose memory follows the bodies; the refusal of
    # the forced dense path is tested in tests/memory.rs.
    n = 70000
    p = contactdd.Problem()
    p.add_material("steel", 2.1e5, 0.3)
    p.add_rectangle_body("lower", (0, n), (0, 1), n, 1, "steel",
                         supports=[{"boundary": "bottom", "component": "both"}])
    p.add_rectangle_body("upper", (0, n), (1, 2), n, 1, "steel",
                         supports=[{"boundary": "left", "component": "x"}],
                         loads=[{"kind": "pressure", "boundary": "top", "value": 1.0}])
    p.add_contact(("lower", "upper"), ("top", "bottom"), c=0.5, h=1.0)
    result = contactdd.solve(p)
    assert result.converged
    assert [b.condensation for b in result.bodies] == ["sparse", "sparse"]
    # Away from the strips' ends the contact carries the applied pressure exactly.
    side = result.contact[0].pressure[: n + 1]
    assert all(abs(q - 1.0) < 1e-8 for q in side[100:-100])


def blocks(upper_y, boundaries):
    """Two 4 × 1 blocks, the upper one spanning ``upper_y``, paired by ``boundaries``."""
    p = contactdd.Problem()
    p.add_material("steel", 2.1e5, 0.3)
    p.add_rectangle_body("lower", (0, 4), (0, 1), 8, 2, "steel",
                         supports=[{"boundary": "bottom", "component": "both"}])
    p.add_rectangle_body("upper", (0, 4), upper_y, 8, 2, "steel",
                         supports=[{"boundary": "left", "component": "x"}],
                         loads=[{"kind": "pressure", "boundary": "top", "value": 100.0}])
    p.add_contact(("lower", "upper"), boundaries, c=0.5, h=1.0)
    return p


def test_boundaries_facing_away_are_refused():
    with pytest.raises(ContactddError, match="face away from each other"):
        contactdd.solve(blocks((1, 2), ("bottom", "top")))
    with pytest.raises(ContactddError, match="face away from each other"):
        contactdd.monolithic(blocks((1, 2), ("bottom", "top")))


def test_a_moderate_overlap_warns():
    # 5 % of the thickness: solved, with a UserWarning.
    with pytest.warns(UserWarning, match="overlapping by 5.0000e-2"):
        result = contactdd.solve(blocks((0.95, 1.95), ("top", "bottom")))
    assert result.converged


def test_convergence_error_is_a_contactdd_error(notch):
    assert issubclass(ConvergenceError, ContactddError)
    assert issubclass(ConvergenceError, RuntimeError)
    with pytest.raises(ContactddError) as e:
        contactdd.solve(notch, gamma=0.1, max_iter=3)
    assert isinstance(e.value, ConvergenceError) and e.value.result.iterations == 3
