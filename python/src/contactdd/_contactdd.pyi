"""Type stubs of the contactdd extension module (``contactdd._contactdd``)."""

from os import PathLike
from typing import Any, Callable, Literal, Mapping, Optional, Sequence, Tuple, TypedDict, Union, final

import numpy as np
import numpy.typing as npt

__version__: str
__all__ = [
    "Problem",
    "Result",
    "Body",
    "Contact",
    "MonolithicResult",
    "solve",
    "solve_steps",
    "sweep",
    "monolithic",
    "notch_benchmark",
    "SpaceProblem",
    "SpaceResult",
    "SpaceBody",
    "space_solve",
    "space_monolithic",
    "space_system",
    "ContactddError",
    "ContactddIOError",
    "ConvergenceError",
    "METHODS",
    "__version__",
]
METHODS: list[str]
"""The method names: neumann, robin, active-set, newton-chord, newton-kurchatov."""

# One of METHODS: "neumann", "robin", "active-set", "newton-chord", "newton-kurchatov".
_MethodName = str
_GammaValue = Union[float, Literal["auto"]]
_AcceleratorName = Literal["newton", "none", "anderson"]
_CoarseName = Literal["off", "chains", "all"]
_CondensationName = Literal["auto", "dense", "sparse"]
_EnforcementName = Literal["penalty", "augmented"]
_LoadSteps = Union[int, Sequence[float]]
_StrPath = Union[str, "PathLike[str]"]
_ArrayLikeFloat = npt.ArrayLike
_ArrayLikeInt = npt.ArrayLike

class ContactddError(ValueError):
    """Bad input: a problem file, array, name or setting that contactdd cannot use."""

class ContactddIOError(ContactddError, OSError):
    """A problem file or a mesh file it names cannot be read (``errno`` as the system gave it)."""

class ConvergenceError(ContactddError, RuntimeError):
    """The domain decomposition iteration did not converge; ``result`` holds the partial result
    (a ``SpaceResult`` for a problem in space)."""

    result: Union[Result, SpaceResult]

class _SupportDict(TypedDict, total=False):
    boundary: str
    component: Literal["x", "y", "both", "normal"]
    value: float

class _LoadDict(TypedDict, total=False):
    kind: Literal["pressure", "traction", "body-force"]
    boundary: str
    value: Union[float, Sequence[float]]

class _SpaceSupportDict(TypedDict, total=False):
    boundary: str
    component: Literal["x", "y", "z", "all"]
    value: float

class _SpaceLoadDict(TypedDict, total=False):
    kind: Literal["pressure", "traction", "body-force"]
    boundary: str
    value: Union[float, Sequence[float]]

class _GapDict(TypedDict, total=False):
    kind: Literal["notch", "uniform"]
    r0: float
    b: float
    centre: float
    power: float
    along: Literal["x", "y"]
    value: float

class _FrictionDict(TypedDict, total=False):
    law: Literal["none", "coulomb", "tresca"]
    mu: float
    bound: float

# The friction of every pair: "coulomb:MU", "tresca:BOUND" or "none" (as --friction), or a dict.
_Friction = Union[str, _FrictionDict]

class _MonitorDict(TypedDict):
    body: str
    boundary: str

# A monitored boundary: {"body": ..., "boundary": ...} (the problem file's table) or (body, boundary).
_Monitor = Union[_MonitorDict, Tuple[str, str]]

class _SettingsDict(TypedDict):
    method: str
    gamma: _GammaValue
    tol: float
    max_iter: int
    u0: float
    u_prev: float
    threads: Optional[int]
    accelerator: str
    coarse: str
    equilibrium_tol: float
    balance_tol: Optional[float]
    gap_tol: Optional[float]
    max_updates: int
    load_steps: Optional[Union[int, list[float]]]
    monitor: Optional[_MonitorDict]
    condensation: str

class _SweepRecord(TypedDict):
    method: str
    gamma: _GammaValue
    iterations: int
    converged: bool
    reason: str

class _MaterialDict(TypedDict):
    young: float
    poisson: float

@final
class Problem:
    """A contact problem: materials, bodies, contact pairs and default solver settings."""

    def __new__(cls, name: str = "problem", plane: Literal["strain", "stress"] = "strain") -> Problem:
        """An empty problem."""
    @staticmethod
    def from_toml(path: _StrPath) -> Problem:
        """Reads a TOML problem file (the format of the command line tool).

        Raises ContactddIOError (an OSError) if the file or a mesh file it names cannot be read,
        ContactddError if it is not a valid problem.
        """
    @staticmethod
    def from_toml_str(text: str, base_dir: Optional[_StrPath] = None, source: str = "<string>") -> Problem:
        """Parses the text of a TOML problem file."""
    def to_toml(self) -> str:
        """The problem as the text of a problem file, which from_toml_str reads back to the same
        problem (every solver setting explicit, Gmsh paths absolute, array bodies inline)."""
    def add_msh_body(
        self,
        name: str,
        text: str,
        material: str,
        surface: Optional[str] = None,
        order: Optional[Literal["p1", "p2"]] = None,
        supports: Optional[Sequence[_SupportDict]] = None,
        loads: Optional[Sequence[_LoadDict]] = None,
        source: str = "<msh text>",
    ) -> None:
        """Adds a body on a mesh given as the text of a Gmsh .msh file (the rules of a
        kind = "gmsh" mesh); the mesh is kept inline."""
    def add_material(self, name: str, young: float, poisson: float) -> None:
        """Defines a linear elastic isotropic material."""
    def add_body(
        self,
        name: str,
        nodes: _ArrayLikeFloat,
        triangles: _ArrayLikeInt,
        boundaries: Mapping[str, _ArrayLikeInt],
        material: str,
        supports: Optional[Sequence[_SupportDict]] = None,
        loads: Optional[Sequence[_LoadDict]] = None,
        node_sets: Optional[Mapping[str, _ArrayLikeInt]] = None,
    ) -> None:
        """Adds a body on a triangle mesh given as arrays ((n, 2) nodes, (m, 3|6) triangles).

        Node indices may be integers or floats with integer values; a fraction raises
        ContactddError."""
    def add_rectangle_body(
        self,
        name: str,
        x: Tuple[float, float],
        y: Tuple[float, float],
        nx: int,
        ny: int,
        material: str,
        diagonal: Literal["right", "left", "alternate"] = "right",
        mirror: bool = False,
        order: Literal["p1", "p2"] = "p1",
        supports: Optional[Sequence[_SupportDict]] = None,
        loads: Optional[Sequence[_LoadDict]] = None,
    ) -> None:
        """Adds a body meshed as a structured rectangle (boundaries left, right, bottom, top)."""
    def add_contact(
        self,
        bodies: Tuple[str, str],
        boundaries: Tuple[str, str],
        c: Optional[float] = None,
        h: Optional[float] = None,
        theta: Optional[float] = None,
        gap: Optional[_GapDict] = None,
        name: Optional[str] = None,
        enforcement: Optional[Literal["penalty", "augmented"]] = None,
        forces: Optional[Literal["balanced", "own-side"]] = None,
        friction: Optional[_FrictionDict] = None,
    ) -> None:
        """Adds a contact pair; penalty by the rod model (c, h) or theta directly;
        enforcement "augmented" gives the exact unilateral contact for any penalty; forces
        "balanced" (default) loads both sides equally and oppositely, "own-side" is the paper's;
        friction {"law": "coulomb", "mu": mu} or {"law": "tresca", "bound": b} (default none)."""
    def solver(
        self,
        method: Optional[_MethodName] = None,
        gamma: Optional[_GammaValue] = None,
        tol: Optional[float] = None,
        max_iter: Optional[int] = None,
        u0: Optional[float] = None,
        u_prev: Optional[float] = None,
        threads: Optional[int] = None,
        accelerator: Optional[_AcceleratorName] = None,
        coarse: Optional[_CoarseName] = None,
        equilibrium_tol: Optional[float] = None,
        balance_tol: Optional[float] = None,
        gap_tol: Optional[float] = None,
        max_updates: Optional[int] = None,
        load_steps: Optional[_LoadSteps] = None,
        monitor: Optional[_Monitor] = None,
        condensation: Optional[_CondensationName] = None,
    ) -> None:
        """Sets the default solver settings, one keyword per key of a [solver] table (None
        keeps a value)."""
    def boundaries(self, body: str) -> list[str]:
        """The names of the boundaries (and node sets) of a body."""
    @property
    def name(self) -> str: ...
    @property
    def plane(self) -> str: ...
    @property
    def materials(self) -> dict[str, _MaterialDict]: ...
    @property
    def bodies(self) -> list[str]: ...
    @property
    def contacts(self) -> list[str]: ...
    @property
    def settings(self) -> _SettingsDict: ...

@final
class Body:
    """The fields of one body."""

    @property
    def name(self) -> str: ...
    @property
    def order(self) -> Literal["p1", "p2"]: ...
    @property
    def condensation(self) -> Literal["dense", "sparse"] | None:
        """How the solve condensed the body on its contact points (the cost model's choice
        under condensation = "auto"); None for the monolithic reference."""
    @property
    def nodes(self) -> npt.NDArray[np.float64]:
        """(n, 2) node coordinates (undeformed)."""
    @property
    def triangles(self) -> npt.NDArray[np.int64]:
        """(m, 3) or (m, 6) node indices."""
    @property
    def displacement(self) -> npt.NDArray[np.float64]:
        """(n, 2) displacement."""
    @property
    def stress(self) -> npt.NDArray[np.float64]:
        """(n, 4) nodal stress [σ_xx, σ_yy, σ_xy, σ_zz]."""
    @property
    def von_mises(self) -> npt.NDArray[np.float64]:
        """(n,) nodal von Mises stress."""
    @property
    def contact_pressure(self) -> npt.NDArray[np.float64]:
        """(n,) contact pressure σ_n ≤ 0 at contact nodes, 0 elsewhere."""

@final
class Contact:
    """The contact quantities of one pair, one entry per contact point of either side."""

    @property
    def name(self) -> str: ...
    @property
    def bodies(self) -> Tuple[str, str]: ...
    @property
    def side(self) -> npt.NDArray[np.int64]: ...
    @property
    def node(self) -> npt.NDArray[np.int64]: ...
    @property
    def x(self) -> npt.NDArray[np.float64]: ...
    @property
    def y(self) -> npt.NDArray[np.float64]: ...
    @property
    def gap(self) -> npt.NDArray[np.float64]: ...
    @property
    def pressure(self) -> npt.NDArray[np.float64]:
        """Contact pressure p >= 0 (0 where open), as contact.csv's pressure."""
    @property
    def nodal_traction(self) -> npt.NDArray[np.float64]:
        """The point's own sigma_n <= 0, or a following point's nodal traction F/w."""
    @property
    def closed(self) -> npt.NDArray[np.bool_]: ...
    @property
    def status(self) -> list[Literal["closed", "open", "no-partner"]]: ...
    @property
    def weight(self) -> npt.NDArray[np.float64]: ...
    @property
    def normal(self) -> npt.NDArray[np.float64]: ...
    @property
    def nodal_force(self) -> npt.NDArray[np.float64]:
        """(k, 2) contact force on each point's node."""
    @property
    def forces(self) -> Tuple[Tuple[float, float], Tuple[float, float]]:
        """Total contact force (fx, fy) on side 0 and on side 1."""
    @property
    def max_penetration(self) -> float:
        """Largest penetration max (s - d)+ (a length; 0 for exact contact)."""
    @property
    def complementarity(self) -> float:
        """Largest gap |d - s| where the contact presses (a length; 0 for exact contact)."""
    @property
    def tangential(self) -> npt.NDArray[np.float64]:
        """Tangential traction sigma_t along t = n turned by +90 degrees (0 without friction)."""
    @property
    def slip(self) -> npt.NDArray[np.float64]:
        """Slip g - g0 of this solve (load step)."""
    @property
    def total_slip(self) -> npt.NDArray[np.float64]:
        """Accumulated tangential relative displacement g."""
    @property
    def friction_status(self) -> list[Literal["open", "stick", "slip"]]: ...
    @property
    def tangential_force(self) -> float:
        """Resultant tangential force sum w sigma_t (0 without friction)."""
    @property
    def stick_length(self) -> float:
        """Length sum w of the points that stick."""
    @property
    def slip_length(self) -> float:
        """Length sum w of the points that slip."""

@final
class Result:
    """The result of a domain decomposition solve."""

    @property
    def converged(self) -> bool: ...
    @property
    def stop(
        self,
    ) -> Literal["converged", "max-iterations", "diverged", "interrupted", "stalled", "unenforced"]: ...
    @property
    def iterations(self) -> int: ...
    @property
    def message(self) -> Optional[str]: ...
    @property
    def iteration(self) -> Literal["interface-newton", "robin-sweeps"]:
        """The iteration that ran."""
    @property
    def solver(self) -> str:
        """The solver settings in words, as contactdd solve and contactdd check print them."""
    @property
    def method(self) -> str:
        """The Robin sweeps' method (unused by the interface Newton method)."""
    @property
    def gamma(self) -> _GammaValue: ...
    @property
    def theta(self) -> list[float]: ...
    @property
    def history(self) -> dict[str, npt.NDArray[Any]]:
        """k, gamma (the sweeps' γ, the Newton method's step length), measure (what the stopping
        test compares with the tolerance), all (m,); rel_change, active, normal_force (m, number
        of bodies)."""
    @property
    def bodies(self) -> list[Body]: ...
    @property
    def contact(self) -> list[Contact]: ...
    @property
    def timing(self) -> dict[str, float]: ...
    @property
    def updates(self) -> int:
        """Augmented Lagrangian multiplier updates (0 for the penalty formulation)."""
    @property
    def gap_tol(self) -> Optional[float]:
        """The gap tolerance of the augmented Lagrangian pairs (a length), or None."""
    @property
    def load_factor(self) -> float:
        """The load factor (1.0 unless a step of solve_steps)."""
    @property
    def monitor(self) -> Optional[Tuple[float, float]]:
        """The mean displacement (ux, uy) of the monitored boundary, or None without one."""
    def write_vtu(self, directory: _StrPath, format: Literal["zlib", "binary", "ascii"] = "zlib", layout: Literal["per-body", "collection"] = "per-body") -> list[str]:
        """Writes summary.json, contact.csv, history.csv and one VTU file per body (layout
        "collection": one file, bodies.vtu, with a piece per body), encoded as format (not for a
        result unpickled or read by load_results: ContactddError)."""
    def summary(self) -> dict[str, Any]:
        """The content of the summary.json file the command line writes."""

@final
class MonolithicResult:
    """The monolithic reference solution."""

    @property
    def newton_steps(self) -> int: ...
    @property
    def rigid_modes(self) -> list[str]: ...
    @property
    def bodies(self) -> list[Body]: ...
    @property
    def contact(self) -> list[Contact]: ...
    @property
    def seconds(self) -> float: ...
    def write_vtu(self, directory: _StrPath, format: Literal["zlib", "binary", "ascii"] = "zlib", layout: Literal["per-body", "collection"] = "per-body") -> list[str]:
        """Writes summary.json, contact.csv and one VTU file per body (layout "collection": one
        file, bodies.vtu, with a piece per body), encoded as format."""
    def summary(self) -> dict[str, Any]:
        """The summary.json of a monolithic solve."""

def solve(
    problem: Problem,
    method: Optional[_MethodName] = None,
    gamma: Optional[_GammaValue] = None,
    tol: Optional[float] = None,
    max_iter: Optional[int] = None,
    u0: Optional[float] = None,
    u_prev: Optional[float] = None,
    threads: Optional[int] = None,
    check: bool = True,
    accelerator: Optional[_AcceleratorName] = None,
    coarse: Optional[_CoarseName] = None,
    enforcement: Optional[_EnforcementName] = None,
    friction: Optional[_Friction] = None,
    gap_tol: Optional[float] = None,
    progress: Optional[Callable[[dict[str, Any]], object]] = None,
    equilibrium_tol: Optional[float] = None,
    balance_tol: Optional[float] = None,
    max_updates: Optional[int] = None,
    condensation: Optional[_CondensationName] = None,
    monitor: Optional[_Monitor] = None,
    out: Optional[_StrPath] = None,
) -> Result:
    """Solves a contact problem by the penalty Robin domain decomposition, once at the full load
    (GIL released); progress(record) is called after every iteration. A problem with load steps
    raises ContactddError: run them with solve_steps."""

def solve_steps(
    problem: Problem,
    load_steps: Optional[_LoadSteps] = None,
    tol: Optional[float] = None,
    max_iter: Optional[int] = None,
    threads: Optional[int] = None,
    check: bool = True,
    accelerator: Optional[_AcceleratorName] = None,
    enforcement: Optional[_EnforcementName] = None,
    friction: Optional[_Friction] = None,
    gap_tol: Optional[float] = None,
    method: Optional[_MethodName] = None,
    gamma: Optional[_GammaValue] = None,
    coarse: Optional[_CoarseName] = None,
    u0: Optional[float] = None,
    u_prev: Optional[float] = None,
    equilibrium_tol: Optional[float] = None,
    balance_tol: Optional[float] = None,
    max_updates: Optional[int] = None,
    condensation: Optional[_CondensationName] = None,
    monitor: Optional[_Monitor] = None,
    out: Optional[_StrPath] = None,
    progress: Optional[Callable[[dict[str, Any]], object]] = None,
) -> list[Result]:
    """Solves at increasing load factors (default: the problem's load steps), each step from the
    last; one Result per step."""

def sweep(
    problem: Problem,
    methods: Optional[Sequence[_MethodName]] = None,
    gammas: Optional[Sequence[_GammaValue]] = None,
    tol: Optional[float] = None,
    max_iter: Optional[int] = None,
    u0: Optional[float] = None,
    u_prev: Optional[float] = None,
    threads: Optional[int] = None,
    progress: Optional[Callable[[_SweepRecord], object]] = None,
) -> list[_SweepRecord]:
    """Runs every method with every γ on one preparation of the problem, in parallel (GIL
    released; Ctrl-C raises KeyboardInterrupt); progress(record) is called as each run ends."""

def monolithic(
    problem: Problem,
    threads: Optional[int] = None,
    max_steps: Optional[int] = None,
    enforcement: Optional[_EnforcementName] = None,
    friction: Optional[_Friction] = None,
    gap_tol: Optional[float] = None,
    out: Optional[_StrPath] = None,
) -> MonolithicResult:
    """Solves the same problem monolithically (semismooth Newton), with the options of
    contactdd monolithic."""

def notch_benchmark(nx: int = 32, ny: int = 16, order: Literal["p1", "p2"] = "p1") -> Problem:
    """The paper's two-body notch benchmark as a Problem (at most 4 000 000 cells per block)."""

# Problems in space (dimension = 3); contactdd.space exports them as Problem, Result, Body,
# solve and monolithic.

@final
class SpaceProblem:
    """A contact problem in space (a problem file with dimension = 3, or built in code), every
    body meshed."""

    def __new__(cls, name: str = "problem", units: Optional[str] = None) -> SpaceProblem:
        """An empty problem in space."""
    @staticmethod
    def from_toml(path: _StrPath) -> SpaceProblem: ...
    @staticmethod
    def from_toml_str(text: str, base_dir: Optional[_StrPath] = None, source: str = "<string>") -> SpaceProblem: ...
    def to_toml(self) -> str:
        """The problem as the text of a problem file in space, which from_toml_str reads back
        to the same problem (Gmsh paths absolute, array and msh-text bodies inline)."""
    def add_material(self, name: str, young: float, poisson: float) -> None:
        """Defines a linear elastic isotropic material."""
    def add_body(
        self,
        name: str,
        nodes: _ArrayLikeFloat,
        tetrahedra: _ArrayLikeInt,
        faces: Mapping[str, _ArrayLikeInt],
        material: str,
        supports: Optional[Sequence[_SpaceSupportDict]] = None,
        loads: Optional[Sequence[_SpaceLoadDict]] = None,
    ) -> None:
        """Adds a body on a tetrahedral mesh given as arrays ((n, 3) nodes, (m, 4|10)
        tetrahedra, faces {name: (k, 3|6) triangles})."""
    def add_box_body(
        self,
        name: str,
        x: Tuple[float, float],
        y: Tuple[float, float],
        z: Tuple[float, float],
        nx: int,
        ny: int,
        nz: int,
        material: str,
        order: Literal["p1", "p2"] = "p1",
        supports: Optional[Sequence[_SpaceSupportDict]] = None,
        loads: Optional[Sequence[_SpaceLoadDict]] = None,
    ) -> None:
        """Adds a body meshed as a structured box (faces x-, x+, y-, y+, z-, z+)."""
    def add_msh_body(
        self,
        name: str,
        text: str,
        material: str,
        volume: Optional[str] = None,
        supports: Optional[Sequence[_SpaceSupportDict]] = None,
        loads: Optional[Sequence[_SpaceLoadDict]] = None,
        source: str = "<msh text>",
    ) -> None:
        """Adds a body on the tetrahedra of the text of a Gmsh .msh file (the rules of a
        kind = "gmsh" mesh); the mesh is kept inline."""
    def add_contact(
        self,
        bodies: Tuple[str, str],
        boundaries: Tuple[str, str],
        c: Optional[float] = None,
        h: Optional[float] = None,
        theta: Optional[float] = None,
        search: Optional[float] = None,
        name: Optional[str] = None,
        enforcement: Optional[str] = None,
        friction: Optional[_FrictionDict] = None,
    ) -> None:
        """Adds a contact pair; penalty by the rod model (c, h) or theta directly;
        enforcement "penalty" (default) or "augmented" (exact contact); friction
        {"law": "coulomb", "mu": mu} or {"law": "tresca", "bound": b} (default none)."""
    def solver(
        self,
        balance_tol: Optional[float] = None,
        threads: Optional[int] = None,
        load_steps: Optional[_LoadSteps] = None,
        monitor: Optional[Tuple[str, str]] = None,
    ) -> None:
        """Sets the [solver] table (None keeps a value)."""
    def boundaries(self, body: str) -> list[str]:
        """The names of the faces of a body."""
    @property
    def name(self) -> str: ...
    @property
    def units(self) -> Optional[str]: ...
    @property
    def materials(self) -> dict[str, _MaterialDict]: ...
    @property
    def bodies(self) -> list[str]: ...
    @property
    def contacts(self) -> list[str]: ...
    @property
    def balance_tol(self) -> float: ...
    @property
    def threads(self) -> Optional[int]: ...

@final
class SpaceBody:
    """The fields of one tetrahedral body."""

    @property
    def name(self) -> str: ...
    @property
    def order(self) -> Literal["p1", "p2"]: ...
    @property
    def nodes(self) -> npt.NDArray[np.float64]:
        """(n, 3) node coordinates."""
    @property
    def tetrahedra(self) -> npt.NDArray[np.int64]:
        """(m, 4) or (m, 10) node indices, in Gmsh's order."""
    @property
    def displacement(self) -> npt.NDArray[np.float64]:
        """(n, 3) displacement."""
    @property
    def stress(self) -> npt.NDArray[np.float64]:
        """(n, 6) nodal stress [xx, yy, zz, yz, xz, xy]."""
    @property
    def von_mises(self) -> npt.NDArray[np.float64]: ...
    @property
    def imbalance(self) -> float: ...

@final
class SpaceResult:
    """The result of a solve in space."""

    @property
    def converged(self) -> bool: ...
    @property
    def reason(self) -> Optional[str]: ...
    @property
    def solver(self) -> str: ...
    @property
    def newton_steps(self) -> int: ...
    @property
    def bodies(self) -> list[SpaceBody]: ...
    @property
    def contact(self) -> dict[str, npt.NDArray[Any]]:
        """pair, body, node, x, y, z, weight, gap, pressure: one entry per contact point."""
    @property
    def balance(self) -> dict[str, float]:
        """worst, tol, contact_law."""
    @property
    def timing(self) -> dict[str, float]: ...
    def summary(self) -> dict[str, Any]: ...
    def write(self, directory: _StrPath) -> list[str]: ...

def space_solve(
    problem: SpaceProblem,
    threads: Optional[int] = None,
    balance_tol: Optional[float] = None,
    enforcement: Optional[str] = None,
    friction: Optional[_Friction] = None,
    out: Optional[_StrPath] = None,
    check: bool = True,
) -> SpaceResult: ...
def space_monolithic(
    problem: SpaceProblem,
    threads: Optional[int] = None,
    balance_tol: Optional[float] = None,
    enforcement: Optional[str] = None,
    friction: Optional[_Friction] = None,
    out: Optional[_StrPath] = None,
    check: bool = True,
) -> SpaceResult: ...
def space_system(problem: SpaceProblem) -> dict[str, Any]: ...
