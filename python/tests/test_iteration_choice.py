"""Which iteration a Python solve runs: the interface Newton method unless a method or γ is
given, and the same answer either way."""

import pytest

import contactdd
from conftest import REPO

THREE_BODIES = REPO / "examples" / "three_bodies.toml"


@pytest.fixture
def three_bodies() -> contactdd.Problem:
    if not THREE_BODIES.is_file():
        pytest.skip(f"{THREE_BODIES} does not exist (run the tests from a repository checkout)")
    return contactdd.Problem.from_toml(str(THREE_BODIES))


def pressures(result):
    return [p for pair in result.contact for p in pair.pressure]


def test_default_is_the_interface_newton_method(three_bodies):
    newton = contactdd.solve(three_bodies)
    sweeps = contactdd.solve(three_bodies, method="newton-kurchatov")
    # The Robin sweeps contract slowly on this three-body stack; Newton takes a handful of steps.
    assert newton.iterations <= 10 < sweeps.iterations
    explicit = contactdd.solve(three_bodies, accelerator="newton")
    assert explicit.iterations == newton.iterations
    # Both reach the same penalty solution (the sweeps to their tolerance, 1e-8 in the file).
    scale = max(abs(p) for p in pressures(newton))
    for p, q in zip(pressures(newton), pressures(sweeps)):
        assert abs(p - q) <= 1e-5 * scale
