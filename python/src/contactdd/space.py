"""Contact problems in space: tetrahedral bodies (``dimension = 3``).

A problem in space is read from a problem file with ``dimension = 3`` (``docs/three-d.md``,
"Problem files and results"; ``examples/space/``) and solved by the decomposition
(:func:`solve`, every body factorised once, Newton on the contact points: ``contactdd solve``)
or by the monolithic reference (:func:`monolithic`, semismooth Newton on the coupled system:
``contactdd monolithic``). Either result counts as converged only after the independent force
balance. The conventions are those of the planar API: a bad file or argument raises
:class:`contactdd.ContactddError` with the command line's message (a file that cannot be read
:class:`contactdd.ContactddIOError`), a result that does not converge raises
:class:`contactdd.ConvergenceError` holding it (``check=False`` returns it), and
:func:`contactdd.load_results` reads a result folder in space back into a :class:`Result`::

    from contactdd import space

    problem = space.Problem.from_toml("examples/space/blocks.toml")
    result = space.solve(problem, out="blocks-out")
    print(result.newton_steps, result.contact["pressure"].max())
    lower = result.bodies[0]
    print(lower.nodes.shape, lower.tetrahedra.shape, lower.displacement.shape)

Bodies in space come from problem files only (box meshes or tetrahedral Gmsh meshes); a body
built from numpy arrays is planar (:meth:`contactdd.Problem.add_body`).
"""

from __future__ import annotations

from . import _arguments
from ._contactdd import SpaceBody as Body
from ._contactdd import SpaceProblem as Problem
from ._contactdd import SpaceResult as Result
from ._contactdd import space_monolithic, space_solve

__all__ = ["Body", "Problem", "Result", "monolithic", "solve"]

# Arguments that do not convert raise ContactddError naming the argument (see _arguments).
solve = _arguments.checked(space_solve)
monolithic = _arguments.checked(space_monolithic)
for _function, _name in ((solve, "solve"), (monolithic, "monolithic")):
    _function.__name__ = _function.__qualname__ = _name
    _function.__module__ = __name__
del _function, _name
_arguments.install_methods(Problem)
