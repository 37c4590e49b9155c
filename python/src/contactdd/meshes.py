"""Bodies from a ``meshio.Mesh`` or from the live Gmsh model: :func:`add_meshio_body` and
:func:`add_gmsh_body`.

Both hand the mesh to :meth:`Problem.add_msh_body` as the text of a ``.msh`` file, so it is read
by the one Gmsh reader of contactdd with the rules of a ``kind = "gmsh"`` mesh in a problem file:
the physical surface ``surface`` picks the body, the physical curves and points that touch it are
its boundaries and node sets, clockwise triangles are reordered, curved P2 triangles are used
isoparametrically (folded ones are refused). meshio and gmsh are optional; each is imported only when its function is
called.
"""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Any, Optional, Sequence

from ._contactdd import Problem

__all__ = ["add_gmsh_body", "add_meshio_body"]


def _meshio() -> Any:
    try:
        import meshio
    except ImportError as e:
        raise ImportError(
            "contactdd.add_meshio_body needs meshio: pip install meshio"
        ) from e
    return meshio


def _gmsh() -> Any:
    try:
        import gmsh
    except ImportError as e:  # also an OSError-like ImportError when libGLU etc. are missing
        raise ImportError(
            "contactdd.add_gmsh_body needs the Gmsh Python API: pip install gmsh (which also "
            f"needs system libraries such as libGLU and libXcursor); the import failed: {e}"
        ) from e
    return gmsh


def add_meshio_body(
    problem: Problem,
    name: str,
    mesh: Any,
    material: str,
    surface: Optional[str] = None,
    order: Optional[str] = None,
    supports: Optional[Sequence[dict]] = None,
    loads: Optional[Sequence[dict]] = None,
) -> None:
    """Adds a body on a ``meshio.Mesh`` that carries Gmsh physical groups.

    The mesh needs the cell data ``gmsh:physical`` and ``gmsh:geometrical`` and the physical
    names in ``field_data``, as ``meshio.read`` gives for a ``.msh`` file (see the module docs for
    how the body and its boundaries are picked).

    Args:
        problem: the :class:`Problem` to add to.
        name: unique body name.
        mesh: the ``meshio.Mesh``.
        material: name of a material of the problem.
        surface: the body's physical surface (default: the mesh's only one).
        order: ``"p2"`` promotes P1 triangles to P2; default: as in the mesh.
        supports, loads: as for :meth:`Problem.add_body`.

    Raises:
        ImportError: meshio is not installed.
        ContactddError: the mesh cannot be used (the message of the Gmsh reader).
    """
    meshio = _meshio()
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "mesh.msh"
        meshio.write(path, mesh, file_format="gmsh22", binary=False)
        text = path.read_text()
    problem.add_msh_body(name, text, material, surface=surface, order=order,
                         supports=supports, loads=loads, source="the meshio mesh")


def add_gmsh_body(
    problem: Problem,
    name: str,
    material: str,
    surface: Optional[str] = None,
    order: Optional[str] = None,
    supports: Optional[Sequence[dict]] = None,
    loads: Optional[Sequence[dict]] = None,
) -> None:
    """Adds a body on the mesh of the current Gmsh model (``gmsh`` initialised, the mesh
    generated), without writing a file of one's own.

    Gmsh saves only the elements of physical groups once a model has some, as when writing a
    ``.msh`` file.

    Args:
        problem: the :class:`Problem` to add to.
        name: unique body name.
        material: name of a material of the problem.
        surface: the body's physical surface (default: the model's only one).
        order: ``"p2"`` promotes P1 triangles to P2; default: as meshed.
        supports, loads: as for :meth:`Problem.add_body`.

    Raises:
        ImportError: the gmsh package is not installed or cannot be loaded.
        ContactddError: the mesh cannot be used (the message of the Gmsh reader).
    """
    gmsh = _gmsh()
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "model.msh"
        # The reader reads ASCII 4.1; the user's format options are restored afterwards.
        saved = {key: gmsh.option.getNumber(key) for key in ["Mesh.MshFileVersion", "Mesh.Binary"]}
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.option.setNumber("Mesh.Binary", 0)
        try:
            gmsh.write(str(path))
        finally:
            for key, value in saved.items():
                gmsh.option.setNumber(key, value)
        text = path.read_text()
    problem.add_msh_body(name, text, material, surface=surface, order=order,
                         supports=supports, loads=loads, source="the gmsh model")
