"""Contact of elastic bodies, with or without friction, by penalty Robin domain decomposition.

contactdd solves two-dimensional (plane strain or plane stress) contact problems of several
linear elastic bodies with the penalty Robin–Robin domain decomposition methods of Prokopyshyn &
Shakhno: every body solves its own linear elasticity problem with a Robin condition on its
contact zones, the bodies in parallel, followed by a relaxation with parameter γ.

Quick start::

    import contactdd

    problem = contactdd.Problem.from_toml("examples/notch.toml")
    result = contactdd.solve(problem, method="active-set", gamma=0.5)
    print(result.iterations, result.contact[0].forces)

    records = contactdd.sweep(problem, gammas=[0.1, 0.3, 0.5])
    contactdd.plot.sweep_curves(records)

The numerics run in Rust (the ``contactdd._contactdd`` extension); this package is a thin layer
that converts numpy arrays and runs the solves with the GIL released.

Problems in space (tetrahedral bodies, problem files with ``dimension = 3``) are solved by
:mod:`contactdd.space`; :func:`load_results` reads their result folders too.
"""

from . import _arguments
from ._contactdd import (
    METHODS,
    Body,
    Contact,
    ContactddError,
    ContactddIOError,
    ConvergenceError,
    MonolithicResult,
    Problem,
    Result,
    __version__,
    monolithic,
    notch_benchmark,
    solve,
    solve_steps,
    sweep,
)
from .meshes import add_gmsh_body, add_meshio_body
from .results_folder import load_results
from . import _pickle, plot, space  # noqa: F401  (_pickle: ContactddIOError's pickling)

# Arguments that do not convert raise ContactddError naming the argument (see _arguments).
solve, solve_steps, sweep, monolithic, notch_benchmark = (
    _arguments.checked(f) for f in (solve, solve_steps, sweep, monolithic, notch_benchmark)
)
_arguments.install_methods(Problem)

__all__ = [
    "METHODS",
    "Body",
    "Contact",
    "ContactddError",
    "ContactddIOError",
    "ConvergenceError",
    "MonolithicResult",
    "Problem",
    "Result",
    "__version__",
    "add_gmsh_body",
    "add_meshio_body",
    "load_results",
    "monolithic",
    "notch_benchmark",
    "plot",
    "solve",
    "solve_steps",
    "space",
    "sweep",
]
