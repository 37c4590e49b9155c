"""Bad input raises ContactddError with the command line's message; non-convergence raises
ConvergenceError carrying the partial result."""

import numpy as np
import pytest

import contactdd
from contactdd import ContactddError, ConvergenceError


def test_exception_hierarchy():
    assert issubclass(ContactddError, ValueError)
    assert issubclass(ConvergenceError, RuntimeError)


def test_negative_young():
    p = contactdd.Problem()
    with pytest.raises(ContactddError, match="Young") as e:
        p.add_material("steel", young=-1.0, poisson=0.3)
    assert "material 'steel'" in str(e.value)
    with pytest.raises(ContactddError, match="Poisson"):
        p.add_material("rubber", young=1.0, poisson=0.5)


def body_problem():
    p = contactdd.Problem()
    p.add_material("steel", 2.1e5, 0.3)
    return p


def test_unknown_boundary():
    p = body_problem()
    with pytest.raises(ContactddError) as e:
        p.add_rectangle_body("block", (0, 1), (0, 1), 2, 2, "steel",
                             supports=[{"boundary": "rigth", "component": "x"}])
    assert str(e.value) == (
        "body 'block': supports[0]: no boundary named 'rigth' (known: bottom, left, right, top)"
    )
    assert p.bodies == []  # nothing was added
    p.add_rectangle_body("block", (0, 1), (0, 1), 2, 2, "steel")
    with pytest.raises(ContactddError, match="no boundary named 'side'"):
        p.add_rectangle_body("other", (0, 1), (1, 2), 2, 2, "steel",
                             loads=[{"kind": "pressure", "boundary": "side", "value": 1.0}])
    p.add_rectangle_body("other", (0, 1), (1, 2), 2, 2, "steel")
    with pytest.raises(ContactddError, match=r"contact pair 'block-other': boundaries\[1\]"):
        p.add_contact(("block", "other"), ("top", "botom"), c=0.05, h=1.0)


def test_bad_dicts_and_names():
    p = body_problem()
    with pytest.raises(ContactddError, match="unknown field `valu`"):
        p.add_rectangle_body("b", (0, 1), (0, 1), 2, 2, "steel",
                             supports=[{"boundary": "left", "component": "x", "valu": 0}])
    with pytest.raises(ContactddError, match="unknown variant `z`"):
        p.add_rectangle_body("b", (0, 1), (0, 1), 2, 2, "steel",
                             supports=[{"boundary": "left", "component": "z"}])
    with pytest.raises(ContactddError, match="unknown material 'iron'"):
        p.add_rectangle_body("b", (0, 1), (0, 1), 2, 2, "iron")
    with pytest.raises(ContactddError) as e:
        contactdd.Problem(plane="strian")
    assert str(e.value) == "plane: unknown variant `strian`, expected `strain` or `stress`"
    with pytest.raises(ContactddError) as e:
        p.add_rectangle_body("b", (0, 1), (0, 1), 2, 2, "steel", order="p3")
    assert str(e.value) == "body 'b': mesh.order: unknown variant `p3`, expected `p1` or `p2`"
    with pytest.raises(ContactddError) as e:
        p.add_rectangle_body("b", (0, 1), (0, 1), 2, 2, "steel",
                             supports=[{"boundary": "left", "component": "x",
                                        "value": np.float64("nan")}])
    assert str(e.value) == "body 'b': supports[0].value: must be finite, got NaN"
    with pytest.raises(ContactddError, match="list of dicts"):
        p.add_rectangle_body("b", (0, 1), (0, 1), 2, 2, "steel",
                             supports={"boundary": "left", "component": "x"})
    p.add_rectangle_body("b", (0, 1), (0, 1), 2, 2, "steel")
    with pytest.raises(ContactddError, match="the name is used by both"):
        p.add_rectangle_body("b", (0, 1), (0, 1), 2, 2, "steel")
    with pytest.raises(ContactddError, match="unknown body 'c'"):
        p.add_contact(("b", "c"), ("top", "bottom"), theta=1e-6)


def test_bad_arrays():
    p = body_problem()
    nodes = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    collinear = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    with pytest.raises(ContactddError, match="degenerate"):
        p.add_body("t", collinear, [[0, 1, 2]], {}, "steel")
    with pytest.raises(ContactddError, match="3 \\(P1\\) or 6 \\(P2\\) columns"):
        p.add_body("t", nodes, [[0, 1, 2, 0]], {}, "steel")
    with pytest.raises(ContactddError, match="refers to node 7"):
        p.add_body("t", nodes, [[0, 1, 7]], {}, "steel")
    with pytest.raises(ContactddError, match="not a boundary edge"):
        p.add_body("t", nodes, [[0, 1, 2]], {"diag": [[0, 5]]}, "steel")
    p.add_body("t", nodes, [[0, 1, 2]], {"base": [[0, 1]]}, "steel",
               supports=[{"boundary": "base", "component": "both"}])
    assert p.boundaries("t") == ["base"]


def test_settings_errors(notch):
    with pytest.raises(ContactddError, match="unknown method 'newton'"):
        contactdd.solve(notch, method="newton")
    with pytest.raises(ContactddError, match="gamma"):
        contactdd.solve(notch, gamma=-0.5)
    with pytest.raises(ContactddError, match="gamma"):
        contactdd.solve(notch, gamma="fast")
    with pytest.raises(ContactddError, match="tol"):
        notch.solver(tol=0.0)
    with pytest.raises(ContactddError, match="max-iter"):
        contactdd.solve(notch, max_iter=0)
    with pytest.raises(ContactddError, match="penalty"):
        p = contactdd.notch_benchmark()
        p.add_contact(("lower", "upper"), ("left", "left"), name="second")


def test_toml_errors(tmp_path):
    with pytest.raises(ContactddError, match="cannot read"):
        contactdd.Problem.from_toml(tmp_path / "missing.toml")
    with pytest.raises(ContactddError, match="bodies"):
        contactdd.Problem.from_toml_str('plane = "strain"\n', source="empty.toml")


def test_floating_body():
    p = body_problem()
    p.add_rectangle_body("loose", (0, 1), (0, 1), 2, 2, "steel")
    with pytest.raises(ContactddError, match="no supports and no contact pair"):
        contactdd.solve(p)
    with pytest.raises(ContactddError, match="no bodies"):
        contactdd.solve(contactdd.Problem())


def test_convergence_error(notch):
    with pytest.raises(ConvergenceError) as e:
        contactdd.solve(notch, method="neumann")
    result = e.value.result
    assert isinstance(result, contactdd.Result)
    assert result.converged is False and result.stop == "diverged"
    assert "neumann" in str(e.value) and str(e.value) == result.message
    unchecked = contactdd.solve(notch, method="neumann", check=False)
    assert unchecked.converged is False and unchecked.message == result.message


def test_max_iterations(notch):
    with pytest.raises(ConvergenceError, match="not converged after 3 iterations") as e:
        contactdd.solve(notch, gamma=0.1, max_iter=3)
    assert e.value.result.stop == "max-iterations" and e.value.result.iterations == 3


def test_io_errors_are_oserrors(tmp_path):
    assert issubclass(contactdd.ContactddIOError, ContactddError)
    assert issubclass(contactdd.ContactddIOError, OSError)
    missing = tmp_path / "missing.toml"
    with pytest.raises(OSError) as e:
        contactdd.Problem.from_toml(missing)
    assert isinstance(e.value, contactdd.ContactddIOError)
    assert str(e.value).startswith(f"cannot read '{missing}'")
    assert e.value.errno == 2  # ENOENT
    # A mesh file that a problem names and that does not exist is an I/O error too.
    text = """plane = "strain"
[materials.steel]
young = 1.0
poisson = 0.3
[[bodies]]
name = "b"
material = "steel"
mesh = { kind = "gmsh", file = "nowhere.msh" }
"""
    with pytest.raises(contactdd.ContactddIOError, match="nowhere.msh"):
        contactdd.Problem.from_toml_str(text, base_dir=tmp_path, source="p.toml")
    # A bad file is bad input, not an I/O error.
    with pytest.raises(ContactddError) as e:
        contactdd.Problem.from_toml_str('plane = "strain"\n', source="empty.toml")
    assert not isinstance(e.value, OSError)


TOML_HEAD = """plane = "strain"
[materials.steel]
young = 2.1e5
poisson = 0.3
"""


def toml_message(body_tables):
    """The message of a problem file with `body_tables`, without the file name."""
    with pytest.raises(ContactddError) as e:
        contactdd.Problem.from_toml_str(TOML_HEAD + body_tables, source="p.toml")
    message = str(e.value)
    assert message.startswith("p.toml: ")
    return message[len("p.toml: "):]


def code_message(build):
    p = body_problem()
    with pytest.raises(ContactddError) as e:
        build(p)
    return str(e.value)


RECT = 'mesh = { kind = "rectangle", x = [0.0, 1.0], y = [0.0, 1.0], nx = 2, ny = 2 }'


@pytest.mark.parametrize("toml, build", [
    (  # unknown material
        f'[[bodies]]\nname = "b"\nmaterial = "iron"\n{RECT}\n',
        lambda p: p.add_rectangle_body("b", (0, 1), (0, 1), 2, 2, "iron"),
    ),
    (  # empty rectangle
        '[[bodies]]\nname = "b"\nmaterial = "steel"\n'
        'mesh = { kind = "rectangle", x = [0.0, 1.0], y = [0.0, 1.0], nx = 0, ny = 2 }\n',
        lambda p: p.add_rectangle_body("b", (0, 1), (0, 1), 0, 2, "steel"),
    ),
    (  # unknown support boundary
        f'[[bodies]]\nname = "b"\nmaterial = "steel"\n{RECT}\n'
        'supports = [{ boundary = "rigth", component = "x" }]\n',
        lambda p: p.add_rectangle_body("b", (0, 1), (0, 1), 2, 2, "steel",
                                       supports=[{"boundary": "rigth", "component": "x"}]),
    ),
    (  # a body that floats
        f'[[bodies]]\nname = "b"\nmaterial = "steel"\n{RECT}\n',
        lambda p: (p.add_rectangle_body("b", (0, 1), (0, 1), 2, 2, "steel"), contactdd.solve(p)),
    ),
    (  # the same pair twice
        f'[[bodies]]\nname = "a"\nmaterial = "steel"\n{RECT}\n'
        '[[bodies]]\nname = "b"\nmaterial = "steel"\n'
        'mesh = { kind = "rectangle", x = [0.0, 1.0], y = [1.0, 2.0], nx = 2, ny = 2 }\n'
        '[[contact]]\nbodies = ["a", "b"]\nboundaries = ["top", "bottom"]\npenalty = { theta = 1e-6 }\n'
        '[[contact]]\nbodies = ["a", "b"]\nboundaries = ["top", "bottom"]\npenalty = { theta = 1e-6 }\n',
        lambda p: (p.add_rectangle_body("a", (0, 1), (0, 1), 2, 2, "steel"),
                   p.add_rectangle_body("b", (0, 1), (1, 2), 2, 2, "steel"),
                   p.add_contact(("a", "b"), ("top", "bottom"), theta=1e-6),
                   p.add_contact(("a", "b"), ("top", "bottom"), theta=1e-6)),
    ),
])
def test_same_message_as_a_file(toml, build):
    assert code_message(build) == toml_message(toml)


def test_add_body_messages_as_a_file():
    nodes = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    # add_body resolves its body like a [[bodies]] table: the same unknown-material message.
    assert code_message(lambda p: p.add_body("b", nodes, [[0, 1, 2]], {}, "iron")) == \
        toml_message(f'[[bodies]]\nname = "b"\nmaterial = "iron"\n{RECT}\n')
    # A bad mesh is a mesh error of the body, as for a rectangle or Gmsh mesh.
    collinear = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    message = code_message(lambda p: p.add_body("t", collinear, [[0, 1, 2]], {}, "steel"))
    assert message.startswith("body 't': mesh: ") and "degenerate" in message


def test_solver_names_use_the_schema():
    p = body_problem()
    with pytest.raises(ContactddError) as e:
        p.solver(accelerator="fast")
    assert str(e.value) == "solver: accelerator: unknown variant `fast`, expected one of `none`, `anderson`, `newton`"
    with pytest.raises(ContactddError) as e:
        p.solver(gamma="fast")
    assert str(e.value) == 'solver: gamma: expected a positive number or "auto", got "fast"'
