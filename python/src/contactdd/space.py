"""Contact problems in space: tetrahedral bodies (``dimension = 3``).

A problem in space is read from a problem file with ``dimension = 3`` (``docs/three-d.md``,
"Problem files and results"; ``examples/space/``) or built in code, and solved by the
decomposition (:func:`solve`, every body factorised once, Newton on the contact points:
``contactdd solve``) or by the monolithic reference (:func:`monolithic`, semismooth Newton on the
coupled system: ``contactdd monolithic``). Either result counts as converged only after the
independent force balance. The conventions are those of the planar API: a bad file, array or
argument raises :class:`contactdd.ContactddError` with the command line's message (a file that
cannot be read :class:`contactdd.ContactddIOError`), a result that does not converge raises
:class:`contactdd.ConvergenceError` holding it (``check=False`` returns it), and
:func:`contactdd.load_results` reads a result folder in space back into a :class:`Result`::

    from contactdd import space

    problem = space.Problem.from_toml("examples/space/blocks.toml")
    result = space.solve(problem, out="blocks-out")
    print(result.newton_steps, result.contact["pressure"].max())
    lower = result.bodies[0]
    print(lower.nodes.shape, lower.tetrahedra.shape, lower.displacement.shape)

The same problem built in code: a box mesh by :meth:`Problem.add_box_body`, a mesh of one's own
by :meth:`Problem.add_body` (numpy arrays: nodes, tetrahedra, named faces),
:func:`add_meshio_body` (a ``meshio.Mesh``), :func:`add_gmsh_body` (the live Gmsh model) or
:meth:`Problem.add_msh_body` (the text of a ``.msh`` file); supports and loads are dicts with the
keys of the problem file's tables, and :meth:`Problem.to_toml` writes the problem file::

    problem = space.Problem(name="blocks", units="m, MPa")
    problem.add_material("steel", young=2.1e5, poisson=0.3)
    problem.add_material("aluminium", young=7e4, poisson=0.33)
    held = [{"boundary": "x-", "component": "x"}, {"boundary": "y-", "component": "y"}]
    problem.add_box_body("lower", x=(0, 1), y=(0, 1), z=(0, 0.5), nx=6, ny=6, nz=3,
                         material="steel",
                         supports=[{"boundary": "z-", "component": "z"}, *held])
    problem.add_box_body("upper", x=(0, 1), y=(0, 1), z=(0.5, 1), nx=5, ny=5, nz=3,
                         material="aluminium", order="p2",
                         supports=[{"boundary": "z+", "component": "z", "value": -0.001},
                                   *held])
    problem.add_contact(bodies=("upper", "lower"), boundaries=("z-", "z+"), theta=1e-7)
    result = space.solve(problem)
"""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Any, Optional, Sequence

from . import _arguments
from ._contactdd import ContactddError
from ._contactdd import SpaceBody as Body
from ._contactdd import SpaceProblem as Problem
from ._contactdd import SpaceResult as Result
from ._contactdd import space_monolithic, space_solve, space_system
from .meshes import _gmsh, _meshio

__all__ = [
    "Body",
    "Problem",
    "Result",
    "add_gmsh_body",
    "add_meshio_body",
    "monolithic",
    "solve",
    "system",
]

# Arguments that do not convert raise ContactddError naming the argument (see _arguments).
solve = _arguments.checked(space_solve)
monolithic = _arguments.checked(space_monolithic)
system = _arguments.checked(space_system)
for _function, _name in ((solve, "solve"), (monolithic, "monolithic"), (system, "system")):
    _function.__name__ = _function.__qualname__ = _name
    _function.__module__ = __name__
del _function, _name
_arguments.install_methods(Problem)

#: The meshio cell types a body in space is read from, with their dimension.
_CELL_DIMENSIONS = {"tetra": 3, "tetra10": 3, "triangle": 2, "triangle6": 2}


def add_meshio_body(
    problem: Problem,
    name: str,
    mesh: Any,
    material: str,
    volume: Optional[str] = None,
    supports: Optional[Sequence[dict]] = None,
    loads: Optional[Sequence[dict]] = None,
) -> None:
    """Adds a body on the tetrahedra (``tetra`` or ``tetra10`` cells) of a ``meshio.Mesh``.

    The faces are named triangles (``triangle`` or ``triangle6`` cells): either Gmsh physical
    groups (the cell data ``gmsh:physical`` with the names in ``field_data``, as ``meshio.read``
    gives for a ``.msh`` file) or, for a mesh without them, the mesh's ``cell_sets`` (a set of
    triangles is a face, a set of tetrahedra a volume). The mesh is handed to
    :meth:`Problem.add_msh_body` as the text of a ``.msh`` file, so the rules of a
    ``kind = "gmsh"`` mesh apply: the physical volume ``volume`` is the body (default: every
    tetrahedron of a mesh with at most one volume), the triangles of another body are left out,
    negatively oriented tetrahedra are reoriented; meshio's ``tetra10`` node order (VTK's) is
    Gmsh's once written.

    Args:
        problem: the :class:`Problem` to add to.
        name: unique body name.
        mesh: the ``meshio.Mesh``.
        material: name of a material of the problem.
        volume: the body's physical volume or cell set of tetrahedra (default: the mesh's only
            one).
        supports, loads: as for :meth:`Problem.add_body`.

    Raises:
        ImportError: meshio is not installed.
        ContactddError: the mesh cannot be used (the message of the Gmsh reader, naming the
            body).
    """
    meshio = _meshio()
    if "gmsh:physical" not in mesh.cell_data:
        mesh = _physical_groups_of_sets(meshio, name, mesh)
    elif "gmsh:geometrical" not in mesh.cell_data:
        # The writer needs both tags; the physical ones serve as geometrical entities.
        data = dict(mesh.cell_data)
        data["gmsh:geometrical"] = data["gmsh:physical"]
        mesh = meshio.Mesh(mesh.points, mesh.cells, cell_data=data, field_data=mesh.field_data)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "mesh.msh"
        meshio.write(path, mesh, file_format="gmsh22", binary=False)
        text = path.read_text()
    problem.add_msh_body(name, text, material, volume=volume, supports=supports, loads=loads,
                         source="the meshio mesh")


def _physical_groups_of_sets(meshio: Any, body: str, mesh: Any) -> Any:
    """`mesh` with its cell sets as Gmsh physical groups: each set one tag (in set order), each
    triangle once per set that holds it, each tetrahedron with its first set's tag (0, none,
    outside every set); other cells left out."""
    import numpy as np

    tags = {set_name: k + 1 for k, set_name in enumerate(mesh.cell_sets)}
    dims: dict = {}
    cells, physical = [], []
    for j, block in enumerate(mesh.cells):
        dim = _CELL_DIMENSIONS.get(block.type)
        if dim is None:
            continue
        members = [
            (set_name, np.asarray(ids[j], dtype=np.int64))
            for set_name, ids in mesh.cell_sets.items()
            if j < len(ids) and ids[j] is not None and len(ids[j]) > 0
        ]
        for set_name, _ in members:
            if dims.setdefault(set_name, dim) != dim:
                raise ContactddError(
                    f"body '{body}': mesh: the cell set '{set_name}' holds both tetrahedra and "
                    "triangles"
                )
        if dim == 3:
            tag = np.zeros(len(block.data), dtype=np.int64)
            for set_name, ids in reversed(members):
                tag[ids] = tags[set_name]
            cells.append((block.type, block.data))
            physical.append(tag)
        else:
            for set_name, ids in members:
                cells.append((block.type, block.data[ids]))
                physical.append(np.full(len(ids), tags[set_name], dtype=np.int64))
    field_data = {s: np.array([tags[s], d]) for s, d in dims.items()}
    return meshio.Mesh(
        mesh.points,
        cells,
        cell_data={"gmsh:physical": physical, "gmsh:geometrical": physical},
        field_data=field_data,
    )


def add_gmsh_body(
    problem: Problem,
    name: str,
    material: str,
    volume: Optional[str] = None,
    supports: Optional[Sequence[dict]] = None,
    loads: Optional[Sequence[dict]] = None,
    model: Optional[str] = None,
) -> None:
    """Adds a body on the tetrahedral mesh of a Gmsh model (``gmsh`` initialised, the 3D mesh
    generated), without writing a file of one's own.

    The model is written as a ``.msh`` text and read by :meth:`Problem.add_msh_body` (the
    rules of a ``kind = "gmsh"`` mesh: its physical surfaces are the faces). Gmsh saves only the
    elements of physical groups once a model has some, as when writing a ``.msh`` file.

    Args:
        problem: the :class:`Problem` to add to.
        name: unique body name.
        material: name of a material of the problem.
        volume: the body's physical volume (default: the model's only one).
        supports, loads: as for :meth:`Problem.add_body`.
        model: the name of the Gmsh model (default: the current one, which stays current).

    Raises:
        ImportError: the gmsh package is not installed or cannot be loaded.
        ContactddError: the mesh cannot be used (the message of the Gmsh reader, naming the
            body).
    """
    gmsh = _gmsh()
    current = gmsh.model.getCurrent()
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "model.msh"
        # The reader reads ASCII 4.1; the user's format options and model are restored
        # afterwards.
        saved = {key: gmsh.option.getNumber(key) for key in ["Mesh.MshFileVersion", "Mesh.Binary"]}
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.option.setNumber("Mesh.Binary", 0)
        try:
            if model is not None:
                gmsh.model.setCurrent(model)
            gmsh.write(str(path))
        finally:
            for key, value in saved.items():
                gmsh.option.setNumber(key, value)
            gmsh.model.setCurrent(current)
        text = path.read_text()
    problem.add_msh_body(name, text, material, volume=volume, supports=supports, loads=loads,
                         source="the gmsh model")
