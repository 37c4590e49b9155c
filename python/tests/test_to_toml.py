"""Problem.to_toml() writes a problem back out: read again by Problem.from_toml_str() it solves
to the same result, bit for bit, for every shipped example (from another folder than the
file's: Gmsh paths are written absolute), for the built-in benchmark and for bodies added from
arrays (written inline)."""

import pytest

import contactdd
from compare import assert_same_result
from conftest import REPO
from test_notch import notch_from_arrays

EXAMPLES = sorted((REPO / "examples").glob("*.toml"))


def assert_round_trip(problem, base_dir):
    """to_toml → from_toml_str from `base_dir`: the same text again and the same solve."""
    text = problem.to_toml()
    again = contactdd.Problem.from_toml_str(text, base_dir=base_dir)
    assert again.to_toml() == text
    assert again.settings == problem.settings
    assert again.name == problem.name and again.bodies == problem.bodies
    if problem.settings["load_steps"] is None:
        assert_same_result(contactdd.solve(problem), contactdd.solve(again), timing=False)
    else:
        # A problem with load steps: solve refuses it, solve_steps runs its steps.
        steps, steps_again = contactdd.solve_steps(problem), contactdd.solve_steps(again)
        assert len(steps) == len(steps_again)
        for a, b in zip(steps, steps_again):
            assert_same_result(a, b, timing=False)
    return text


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_every_example_round_trips(path, tmp_path):
    assert_round_trip(contactdd.Problem.from_toml(path), tmp_path)


def test_builtin_benchmark_is_the_example_file(notch, notch_toml):
    """notch_benchmark() is written as the same problem as examples/notch.toml."""
    from_file = contactdd.Problem.from_toml(notch_toml)
    assert notch.to_toml() == from_file.to_toml()
    assert_same_result(contactdd.solve(notch), contactdd.solve(from_file), timing=False)


@pytest.mark.parametrize("clockwise", [False, True])
def test_bodies_from_arrays_are_written_inline(clockwise, tmp_path):
    text = assert_round_trip(notch_from_arrays(clockwise=clockwise), tmp_path)
    assert text.count('kind = "inline"') == 2


def test_settings_set_in_code_round_trip(notch, tmp_path):
    notch.solver(accelerator="anderson", gamma="auto", max_iter=40, threads=1)
    assert assert_round_trip(notch, tmp_path).count('accelerator = "anderson"') == 1


INLINE = """
plane = "strain"
[materials.steel]
young = 1.0
poisson = 0.3
[[bodies]]
name = "block"
material = "steel"
supports = [{ boundary = "bottom", component = "both" }]
[bodies.mesh]
kind = "inline"
nodes = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
triangles = TRIANGLES
boundaries = { bottom = [[0, 1]] }
"""


def test_inline_mesh_is_read_and_checked():
    ok = contactdd.Problem.from_toml_str(INLINE.replace("TRIANGLES", "[[0, 1, 2], [0, 2, 3]]"))
    assert ok.boundaries("block") == ["bottom"]
    bad = INLINE.replace("TRIANGLES", "[[0, 1, 2], [0, 2]]")
    with pytest.raises(contactdd.ContactddError, match="mesh.triangles: triangle 1 has 2 nodes"):
        contactdd.Problem.from_toml_str(bad)


def test_condensation_is_kept_and_solves_alike(notch_toml, tmp_path):
    """[solver] condensation reaches the solve and the written file; both paths agree."""
    text = notch_toml.read_text()
    dense = contactdd.Problem.from_toml_str(text, base_dir=notch_toml.parent)
    forced = text.replace("[solver]", '[solver]\ncondensation = "sparse"', 1)
    sparse = contactdd.Problem.from_toml_str(forced, base_dir=notch_toml.parent)
    written = assert_round_trip(sparse, tmp_path)
    assert written.count('condensation = "sparse"') == 1
    a, b = contactdd.solve(dense), contactdd.solve(sparse)
    assert a.iterations == b.iterations
    # Each result says which path its bodies took, also when read back from its folder.
    assert [x.condensation for x in a.bodies] == ["dense", "dense"]
    assert [x.condensation for x in b.bodies] == ["sparse", "sparse"]
    b.write_vtu(tmp_path / "out")
    back = contactdd.load_results(tmp_path / "out")
    assert [x.condensation for x in back.bodies] == ["sparse", "sparse"]
    for ca, cb in zip(a.contact, b.contact):
        scale = abs(ca.pressure).max()
        assert abs(ca.pressure - cb.pressure).max() <= 1e-9 * scale
