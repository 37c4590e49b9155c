"""Bad arguments raise ContactddError with a short message, in every interface: wrong types and
out-of-range integers, huge numbers shown compactly, the problem file's limits, a file given to
load_results, boundary edges that do not match the triangles' order."""

import re

import numpy as np
import pytest

import contactdd
from contactdd import ContactddError

from conftest import REPO


def max_load_steps() -> int:
    """The problem file's limit on load steps, read from the Rust source that defines it."""
    source = (REPO / "crates" / "io" / "src" / "load_steps.rs").read_text()
    m = re.search(r"pub const MAX_LOAD_STEPS: usize = ([0-9_]+);", source)
    assert m, "MAX_LOAD_STEPS not found"
    return int(m.group(1).replace("_", ""))


def short(e: pytest.ExceptionInfo) -> str:
    """The message, checked to be short and free of long digit runs."""
    message = str(e.value)
    assert len(message) < 300, message
    assert not re.search(r"[0-9]{21,}", message), message
    return message


@pytest.fixture
def problem():
    return contactdd.notch_benchmark(nx=4, ny=2)


@pytest.mark.parametrize("steps", [10**9, 2**62, "max+1", "factors"])
def test_load_steps_limit_holds_in_python(problem, steps):
    limit = max_load_steps()
    if steps == "max+1":
        steps = limit + 1
    elif steps == "factors":
        steps = [1.0] * (limit + 1)
    for call in (
        lambda: contactdd.solve_steps(problem, steps),
        lambda: problem.solver(load_steps=steps),
    ):
        with pytest.raises(ContactddError) as e:
            call()
        assert f"at most {limit} steps" in short(e)
    # The file key refuses the same count.
    count = steps if isinstance(steps, int) else len(steps)
    with pytest.raises(ContactddError) as e:
        contactdd.Problem.from_toml_str(
            problem.to_toml().replace("[solver]", f"[solver]\nload-steps = {count}", 1)
        )
    assert f"at most {limit}" in short(e)


@pytest.mark.parametrize(
    "call, expected",
    [
        (lambda p: contactdd.solve(p, max_iter=-1), "max_iter: expected a whole number ≥ 0, got -1"),
        (lambda p: contactdd.solve(p, max_iter=2**64), "max_iter: 18446744073709551616 is too large"),
        (lambda p: contactdd.solve(p, max_iter=10**300), "max_iter: <301-digit number> is too large"),
        (lambda p: contactdd.solve(p, tol="a"), "tol: expected a number, got 'a'"),
        (lambda p: contactdd.solve(p, threads=-1), "threads: expected a whole number ≥ 0, got -1"),
        (lambda p: contactdd.solve(p, check="yes"), "check: expected True or False, got 'yes'"),
        (lambda p: contactdd.solve(1), "problem: expected a contactdd.Problem, got 1"),
        (lambda p: contactdd.solve_steps(p, 3, gamma=[1]), 'gamma: expected a positive number or "auto"'),
        (lambda p: contactdd.sweep(p, gammas="x"), "gammas: expected a list, got 'x'"),
        (lambda p: contactdd.monolithic(p, max_steps=-1), "max_steps: expected a whole number ≥ 0"),
        (lambda p: contactdd.notch_benchmark(nx=-1), "nx: expected a whole number ≥ 0, got -1"),
        (lambda p: contactdd.notch_benchmark(order=2), "order: expected a string, got 2"),
        (lambda p: contactdd.Problem(name=1), "name: expected a string"),
        (lambda p: contactdd.Problem.from_toml(1), "path: expected a path, got 1"),
        (lambda p: contactdd.Problem.from_toml_str(1), "text: expected a string, got 1"),
        (lambda p: p.add_material("m", "x", 0.3), "young: expected a number, got 'x'"),
        (lambda p: p.add_rectangle_body("b", (0, 1), (0, 1), -2, 2, "m"), "nx: expected a whole"),
        (lambda p: p.add_contact(bodies=1, boundaries=("a", "b")), "bodies: expected a pair, got 1"),
        (lambda p: p.solver(max_iter=1e300), "max_iter: expected a whole number ≥ 0, got 1e+300"),
        (lambda p: p.solver(tol=10**400), "tol: <401-digit number> is too large"),
        (lambda p: p.boundaries(3), "body: expected a string, got 3"),
        (lambda p: contactdd.load_results(1), "directory: expected a path"),
    ],
)
def test_bad_arguments_raise_contactdd_error(problem, call, expected):
    with pytest.raises(ContactddError) as e:
        call(problem)
    assert expected in short(e)


def test_a_callback_error_is_not_translated(problem):
    def progress(record):
        raise TypeError("mine")

    with pytest.raises(TypeError, match="mine") as e:
        contactdd.solve(problem, progress=progress)
    assert not isinstance(e.value, ContactddError)


SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
P1 = np.array([[0, 1, 2], [1, 3, 2]])


def body(**kwargs):
    p = contactdd.Problem()
    p.add_material("m", young=1.0, poisson=0.3)
    args = dict(nodes=SQUARE, triangles=P1, boundaries={"bottom": [[0, 1]]}, material="m")
    args.update(kwargs)
    p.add_body("b", **args)
    return p


@pytest.mark.parametrize(
    "triangles, expected",
    [
        ([[0, 1, 2**62]], "refers to node 4611686018427387904, but the mesh has 4 nodes"),
        ([[0, 1, 2**70]], "node index 1.181e21 is too large"),
        ([[0, 1, 1e301]], "node index 1.000e301 is too large"),
        ([[0, 1, -1e301]], "node index -1.000e301 is negative"),
        ([[0, 1, 2.5]], "node index 2.5 is not an integer"),
        ("abc", "triangles: expected a 2-D array of numbers, got a value of type str"),
    ],
)
def test_node_indices_in_messages(triangles, expected):
    with pytest.raises(ContactddError) as e:
        body(triangles=triangles)
    assert expected in short(e)


def test_integer_indices_are_exact():
    # 2**53 + 1 is not a float: read as an integer it is out of range, not rounded.
    with pytest.raises(ContactddError, match="refers to node 9007199254740993"):
        body(triangles=np.array([[0, 1, 2**53 + 1]], dtype=np.int64))


def test_p1_mesh_refuses_three_node_edges():
    with pytest.raises(ContactddError) as e:
        body(boundaries={"bottom": np.array([[0, 1, 3]])})
    assert "has 3 nodes per edge, but the triangles are P1" in short(e)
    body(boundaries={"bottom": np.array([[0, 1]])})  # two nodes are fine


def test_p2_mesh_checks_the_mid_side_node():
    nodes = np.array([[0, 0], [1, 0], [0, 1], [0.5, 0], [0.5, 0.5], [0, 0.5]], float)
    tri = np.array([[0, 1, 2, 3, 4, 5]])
    sup = [{"boundary": "bottom", "component": "both"}]
    for edges in ([[0, 1]], [[0, 1, 3]], [[1, 0, 3]]):
        body(nodes=nodes, triangles=tri, boundaries={"bottom": edges}, supports=sup)
    with pytest.raises(ContactddError) as e:
        body(nodes=nodes, triangles=tri, boundaries={"bottom": [[0, 1, 4]]}, supports=sup)
    assert "the mid-side node of edge (0, 1) is 3 in the triangles, not 4" in short(e)


@pytest.mark.parametrize(
    "kwargs, expected",
    [
        (dict(boundaries=[[0, 1]]), "boundaries: expected a dict"),
        (dict(boundaries={1: [[0, 1]]}), "boundaries: the names must be strings"),
        (dict(node_sets={"a": [-1]}), "node_sets['a']: node index -1 is negative"),
        (dict(node_sets=[1]), "node_sets: expected a dict"),
        (dict(supports=1), "supports: expected a list of dicts, got a value of type int"),
        (dict(supports=[{"boundary": "bottom", "component": "x", "value": 10**400}]),
         "supports[0].value: the integer <401-digit number> is out of range"),
        (dict(supports=[{"boundary": "bottom", "component": "x", "value": object()}]),
         "supports[0].value: cannot use a value of type object"),
        (dict(supports=[{1: 2}]), "supports[0]: dictionary keys must be strings"),
    ],
)
def test_bad_body_arrays_and_dicts(kwargs, expected):
    with pytest.raises(ContactddError) as e:
        body(**kwargs)
    assert expected in short(e)


def test_load_results_of_a_file(tmp_path):
    f = tmp_path / "passwd"
    f.write_text("root:x:0:0\n")
    with pytest.raises(contactdd.ContactddIOError) as e:
        contactdd.load_results(f)
    assert str(e.value).startswith(f"'{f}' is not a results folder: it is a file")
    assert isinstance(e.value, ContactddError) and isinstance(e.value, NotADirectoryError) is False
    with pytest.raises(contactdd.ContactddIOError, match="No such file or directory"):
        contactdd.load_results(tmp_path / "missing")
