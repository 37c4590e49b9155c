"""Friction from Python: Problem.add_contact(friction=...) builds the problem of
examples/friction_block.toml to the bit, solve's friction= overrides every pair as
`contactdd solve --friction` does, bad values raise ContactddError, and the friction attributes of
a Contact agree with Coulomb's law, with the block's force balance, with pickling and with
load_results."""

import math
import pickle

import numpy as np
import pytest

import contactdd
from conftest import REPO

BLOCK_TOML = REPO / "examples" / "friction_block.toml"
MU = 0.3


def block(friction=None, forces=None):
    """The problem of examples/friction_block.toml, built in code."""
    p = contactdd.Problem("friction_block", plane="strain")
    p.add_material("soft", 1000.0, 0.3)
    p.add_rectangle_body("foundation", (0.0, 4.0), (0.0, 1.0), 11, 4, "soft",
                         supports=[{"boundary": "bottom", "component": "both"}])
    p.add_rectangle_body("block", (1.0, 3.0), (1.0, 2.0), 16, 4, "soft", loads=[
        {"kind": "pressure", "boundary": "top", "value": 10.0},
        {"kind": "traction", "boundary": "left", "value": [4.0, 0.0]},
    ])
    p.add_contact(("foundation", "block"), ("top", "bottom"), c=0.05, h=1.0, name="joint",
                  friction=friction, forces=forces)
    return p


@pytest.fixture(scope="module")
def from_file():
    if not BLOCK_TOML.is_file():
        pytest.skip(f"{BLOCK_TOML} does not exist")
    return contactdd.solve(contactdd.Problem.from_toml(BLOCK_TOML))


def test_add_contact_friction_is_the_problem_files(from_file):
    built = block({"law": "coulomb", "mu": MU})
    # A file's u0 and u-prev default to values from its model's size; a problem built in code
    # starts from the settings' defaults.
    settings = contactdd.Problem.from_toml(BLOCK_TOML).settings
    built.solver(u0=settings["u0"], u_prev=settings["u_prev"])
    built = contactdd.solve(built)
    a, b = from_file.contact[0], built.contact[0]
    for key in ["tangential", "slip", "total_slip", "pressure", "nodal_force"]:
        np.testing.assert_array_equal(getattr(a, key), getattr(b, key), err_msg=key)
    assert a.friction_status == b.friction_status
    assert (a.tangential_force, a.stick_length, a.slip_length) == \
        (b.tangential_force, b.stick_length, b.slip_length)
    # The problem file text of the built problem holds the same table.
    assert '[contact.friction]\nlaw = "coulomb"\nmu = 0.3' in block({"law": "coulomb", "mu": MU}).to_toml()


def test_the_contact_keeps_coulombs_law_and_balances_the_block(from_file):
    c = from_file.contact[0]
    n = len(c.x)
    assert c.tangential.shape == c.slip.shape == c.total_slip.shape == (n,)
    assert set(c.friction_status) <= {"open", "stick", "slip"}
    bound = MU * c.pressure
    assert np.all(np.abs(c.tangential) <= bound * (1 + 1e-12))
    slipping = np.array([s == "slip" for s in c.friction_status])
    sticking = np.array([s == "stick" for s in c.friction_status])
    np.testing.assert_allclose(np.abs(c.tangential[slipping]), bound[slipping], rtol=1e-9)
    assert slipping.any() and sticking.any()
    assert math.isclose(c.slip_length, c.weight[slipping].sum(), rel_tol=1e-12)
    assert math.isclose(c.stick_length, c.weight[sticking].sum(), rel_tol=1e-12)
    # Σ w σ_t is the resultant, and the contact forces on the block balance its loads.
    assert math.isclose(c.tangential_force, float(np.sum(c.weight * c.tangential)), rel_tol=1e-12)
    assert math.isclose(c.tangential_force, -4.0, rel_tol=1e-8)
    fx, fy = c.forces[1]
    assert math.isclose(fx, -4.0, rel_tol=1e-8) and math.isclose(fy, 20.0, rel_tol=1e-8)


def test_solve_friction_overrides_every_pair(from_file):
    frictionless = block()
    settings = contactdd.Problem.from_toml(BLOCK_TOML).settings
    frictionless.solver(u0=settings["u0"], u_prev=settings["u_prev"])
    # The text of --friction and the dict of add_contact give the same solve as the pair's own.
    for friction in ["coulomb:0.3", {"law": "coulomb", "mu": 0.3}]:
        r = contactdd.solve(frictionless, friction=friction)
        np.testing.assert_array_equal(r.contact[0].tangential, from_file.contact[0].tangential)
    tresca = contactdd.solve(frictionless, friction="tresca:3")
    c = tresca.contact[0]
    assert np.all(np.abs(c.tangential) <= 3.0 * (1 + 1e-12))
    assert math.isclose(c.tangential_force, -4.0, rel_tol=1e-8)
    # "none" makes the pair frictionless: nothing holds the block sideways any more.
    with pytest.raises(contactdd.ContactddError):
        contactdd.solve(block({"law": "coulomb", "mu": MU}), friction="none")


@pytest.mark.parametrize("bad, says", [
    ({"law": "coulomb"}, "friction.mu: Coulomb friction needs mu"),
    ({"law": "coulomb", "mu": -0.1}, "friction.mu: must be a finite number at least 0"),
    ({"law": "coulomb", "mu": float("nan")}, "friction"),
    ({"law": "tresca", "bound": -1.0}, "friction.bound"),
    ({"law": "tresca", "mu": 0.3}, "Tresca friction takes bound, not mu"),
    ({"law": "stick"}, "unknown variant `stick`"),
    ({"mu": 0.3}, "missing field `law`"),
    ({"law": "coulomb", "mu": 0.3, "m": 1}, "unknown field `m`"),
    ({"law": "coulomb", "mu": "x"}, "friction"),
    ("coulomb:0.3", "expected a friction table"),
    (0.3, "expected a friction table"),
])
def test_bad_friction_dicts_raise_contactdd_error(bad, says):
    with pytest.raises(contactdd.ContactddError, match="contact pair 'joint'") as e:
        block(bad)
    assert says in str(e.value)


@pytest.mark.parametrize("bad, says", [
    ("coulomb", "coulomb:VALUE"),
    ("coulomb:-1", "at least 0"),
    ("tresca:nan", "finite"),
    ("stick", "unknown friction"),
    ({"law": "tresca"}, "Tresca friction needs bound"),
    (5, "expected a friction table"),
])
def test_bad_friction_options_raise_contactdd_error(bad, says):
    p = block()
    for fn in (contactdd.solve, contactdd.solve_steps, contactdd.monolithic):
        with pytest.raises(contactdd.ContactddError, match="friction") as e:
            if fn is contactdd.solve_steps:
                fn(p, load_steps=2, friction=bad)
            else:
                fn(p, friction=bad)
        assert says in str(e.value), fn.__name__


def test_own_side_friction_is_refused_and_the_monolithic_reference_agrees():
    with pytest.raises(contactdd.ContactddError, match='friction needs forces = "balanced"'):
        block({"law": "coulomb", "mu": MU}, forces="own-side")
    with pytest.raises(contactdd.ContactddError, match='friction needs forces = "balanced"'):
        contactdd.solve(block(forces="own-side"), friction="coulomb:0.3")
    problem = block({"law": "coulomb", "mu": MU})
    dd, mono = contactdd.solve(problem), contactdd.monolithic(problem)
    a, b = dd.contact[0], mono.contact[0]
    assert list(a.friction_status) == list(b.friction_status)
    scale = np.abs(a.tangential).max()
    assert np.abs(np.asarray(a.tangential) - np.asarray(b.tangential)).max() <= 1e-8 * scale


def test_friction_attributes_pickle_and_read_back(from_file, tmp_path):
    c = from_file.contact[0]
    again = pickle.loads(pickle.dumps(c))
    for key in ["tangential", "slip", "total_slip"]:
        np.testing.assert_array_equal(getattr(again, key), getattr(c, key))
    assert again.friction_status == c.friction_status
    assert again.tangential_force == c.tangential_force
    contactdd.solve(contactdd.Problem.from_toml(BLOCK_TOML), out=tmp_path / "block")
    loaded = contactdd.load_results(tmp_path / "block").contact[0]
    np.testing.assert_array_equal(loaded.tangential, c.tangential)
    np.testing.assert_array_equal(loaded.total_slip, c.total_slip)
    assert loaded.friction_status == c.friction_status
    assert (loaded.tangential_force, loaded.stick_length, loaded.slip_length) == \
        (c.tangential_force, c.stick_length, c.slip_length)


def test_a_frictionless_contact_has_zero_friction(notch, tmp_path):
    r = contactdd.solve(notch, out=tmp_path / "notch")
    for c in [r.contact[0], contactdd.load_results(tmp_path / "notch").contact[0]]:
        assert not c.tangential.any() and not c.slip.any() and not c.total_slip.any()
        assert set(c.friction_status) == {"open"}
        assert (c.tangential_force, c.stick_length, c.slip_length) == (0.0, 0.0, 0.0)
    header = (tmp_path / "notch" / "contact.csv").read_text().splitlines()[0]
    assert header == "pair,body,x,y,gap,pressure,nodal_traction,status"
