"""Python tells the command line's story about the solver: for every shipped example, the result
of ``contactdd.solve`` (or ``solve_steps`` for a file with load steps) names the solver as
``contactdd check`` does, names the iteration that ran, and a converged result ends with its
stopping test's measure at or below the tolerance."""

import subprocess

import pytest

import contactdd
from conftest import REPO
from test_tutorial import cli

EXAMPLES = sorted((REPO / "examples").glob("*.toml"))


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_python_and_check_name_the_same_solver(path):
    check = subprocess.run([str(cli()), "check", str(path)], capture_output=True, text=True)
    assert check.returncode == 0, check.stderr
    line = next(l for l in check.stdout.splitlines() if l.startswith("solver: "))
    problem = contactdd.Problem.from_toml(str(path))
    steps = problem.settings["load_steps"]
    result = contactdd.solve_steps(problem)[-1] if steps else contactdd.solve(problem)
    assert line.startswith(f"solver: {result.solver}, u0 "), (line, result.solver)
    assert result.summary()["solver"] == result.solver
    newton = result.solver.startswith("interface newton")
    assert result.iteration == ("interface-newton" if newton else "robin-sweeps")
    assert result.converged
    assert result.history["measure"][-1] <= result.summary()["tol"]
