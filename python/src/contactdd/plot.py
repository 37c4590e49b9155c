"""Plots of contactdd results with matplotlib (optional: ``pip install contactdd[plot]``).

Every function draws into ``ax`` (a new figure's axes when ``None``) and returns the axes:

- :func:`contact_pressure`: the contact pressure along a contact zone;
- :func:`deformed_mesh`: the deformed bodies coloured by von Mises stress;
- :func:`history`: the relative change per iteration (semilog);
- :func:`sweep_curves`: iterations against γ per method, the paper's Fig. 3.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Iterable, Mapping, Optional, Union

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

    from ._contactdd import MonolithicResult, Result

__all__ = ["contact_pressure", "deformed_mesh", "history", "sweep_curves"]


def _pyplot() -> Any:
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError(
            "contactdd.plot needs matplotlib: pip install matplotlib "
            "(or pip install 'contactdd[plot]')"
        ) from e
    return plt


def _axes(ax: Optional["Axes"]) -> "Axes":
    if ax is not None:
        return ax
    _, ax = _pyplot().subplots()
    return ax


def _units(result: Any, units: Optional[str]) -> tuple[Optional[str], Optional[str]]:
    """(length, stress) from a units note ``"length, stress"``: ``units`` if given, else the
    ``units`` of the result's summary (a result read back from a folder the command line wrote);
    (None, None) for a note of another form (free text) or none."""
    if units is None:
        try:
            summary = result.summary()
        except Exception:  # pragma: no cover - a summary that cannot be made has no units
            summary = {}
        note = summary.get("units") if isinstance(summary, dict) else None
        units = note if isinstance(note, str) else None
    parts = [p.strip() for p in units.split(",")] if units else []
    if len(parts) == 2 and all(parts):
        return parts[0], parts[1]
    return None, None


def _contact_window(coord: np.ndarray, closed: np.ndarray) -> tuple[float, float]:
    """The stretch of the contact line to show: the closed points and half their extent again on
    either side (at least 5 % of the whole line), within the points' own extent; the whole line
    when no point is closed."""
    lo_all, hi_all = float(np.min(coord)), float(np.max(coord))
    if not closed.any():
        return lo_all, hi_all
    lo, hi = float(np.min(coord[closed])), float(np.max(coord[closed]))
    margin = max(0.5 * (hi - lo), 0.05 * (hi_all - lo_all))
    return max(lo - margin, lo_all), min(hi + margin, hi_all)


def contact_pressure(
    result: Union["Result", "MonolithicResult"],
    pair: Union[int, str] = 0,
    ax: Optional["Axes"] = None,
    along: Optional[str] = None,
    units: Optional[str] = None,
    whole: bool = False,
) -> "Axes":
    """Plots the contact pressure −σ_n (positive in compression) of one contact pair.

    The horizontal axis shows the contact zone (the closed points) and half its length again on
    either side, so that a small zone such as a Hertz contact is not a spike on a long boundary;
    ``whole=True`` shows the whole contact boundary.

    Args:
        result: a solve or monolithic result.
        pair: index or name of the contact pair.
        ax: axes to draw into (default: a new figure).
        along: coordinate on the horizontal axis, ``"x"`` or ``"y"`` (default: the one in which
            the contact boundary is longer).
        units: a units note ``"length, stress"`` (e.g. ``"mm, N/mm^2"``) for the axis labels
            (default: the ``units`` of ``result.summary()``, present in a result read back from a
            folder; a note of another form labels the axes "unit of the problem").
        whole: show the whole contact boundary rather than the contact zone.

    Returns:
        The axes.
    """
    contacts = list(result.contact)
    if isinstance(pair, str):
        matches = [c for c in contacts if c.name == pair]
        if not matches:
            names = ", ".join(c.name for c in contacts)
            raise KeyError(f"no contact pair named {pair!r} (known: {names})")
        c = matches[0]
    else:
        c = contacts[pair]
    ax = _axes(ax)
    x, y = np.asarray(c.x), np.asarray(c.y)
    if along is None:
        along = "x" if np.ptp(x) >= np.ptp(y) else "y"
    coord = x if along == "x" else y
    side = np.asarray(c.side)
    pressure = -np.asarray(c.pressure)
    markers = ("o-", "x--")
    for s, body in enumerate(c.bodies):
        mask = side == s
        order = np.argsort(coord[mask])
        ax.plot(
            coord[mask][order],
            pressure[mask][order],
            markers[s],
            markersize=3,
            label=f"{body}",
        )
    length, stress = _units(result, units)
    ax.set_xlabel(f"{along} ({length or 'length unit of the problem'})")
    ax.set_ylabel(f"contact pressure −σₙ ({stress or 'stress unit of the problem'})")
    if len(coord) and not whole:
        lo, hi = _contact_window(coord, np.asarray(c.closed, dtype=bool))
        if hi > lo:
            ax.set_xlim(lo, hi)
    ax.set_ylim(bottom=0.0)
    ax.set_title(f"contact pressure, pair '{c.name}'")
    ax.grid(True, alpha=0.3)
    ax.legend()
    return ax


def deformed_mesh(
    result: Union["Result", "MonolithicResult"],
    scale: Optional[float] = None,
    ax: Optional["Axes"] = None,
    edges: bool = False,
    colorbar: bool = True,
) -> "Axes":
    """Draws the deformed bodies coloured by their nodal von Mises stress.

    P2 bodies are drawn on their vertex triangles (the first three columns of
    ``Body.triangles``).

    Args:
        result: a solve or monolithic result.
        scale: displacement magnification (default: the largest displacement is drawn as 5 % of
            the model size).
        ax: axes to draw into (default: a new figure).
        edges: draw the triangle edges.
        colorbar: add a colour bar.

    Returns:
        The axes.
    """
    _pyplot()
    import matplotlib.tri as mtri
    bodies = list(result.bodies)
    if scale is None:
        nodes = np.vstack([np.asarray(b.nodes) for b in bodies])
        size = float(np.max(np.ptp(nodes, axis=0))) if len(nodes) else 1.0
        umax = max((float(np.max(np.abs(b.displacement))) for b in bodies), default=0.0)
        scale = 0.05 * size / umax if umax > 0 else 1.0
    ax = _axes(ax)
    vmax = max((float(np.max(b.von_mises)) for b in bodies), default=1.0)
    image = None
    for b in bodies:
        p = np.asarray(b.nodes) + scale * np.asarray(b.displacement)
        tri = mtri.Triangulation(p[:, 0], p[:, 1], np.asarray(b.triangles)[:, :3])
        image = ax.tripcolor(
            tri,
            np.asarray(b.von_mises),
            shading="gouraud",
            cmap="viridis",
            vmin=0.0,
            vmax=vmax,
        )
        if edges:
            ax.triplot(tri, color="k", linewidth=0.2, alpha=0.5)
    ax.set_aspect("equal")
    ax.set_title(f"von Mises stress, displacements × {scale:.3g}")
    if colorbar and image is not None:
        ax.figure.colorbar(image, ax=ax, label="von Mises stress")
    return ax


def history(result: "Result", ax: Optional["Axes"] = None) -> "Axes":
    """Plots what the stopping test measures (``history["measure"]``) against the tolerance, and
    every body's relative change ‖uₙᵏ⁺¹ − uₙᵏ‖ / ‖uₙᵏ⁺¹‖, per iteration (log scale); the title
    names the solver that ran.

    Args:
        result: a solve result.
        ax: axes to draw into (default: a new figure).

    Returns:
        The axes.
    """
    ax = _axes(ax)
    k = np.asarray(result.history["k"])
    measure = np.asarray(result.history["measure"])
    ax.semilogy(k, measure, "ks-", markersize=4, label="stop test")
    rel = np.asarray(result.history["rel_change"])
    for b, body in enumerate(result.bodies):
        ax.semilogy(k, rel[:, b], "o-", markersize=3, alpha=0.6, label=body.name)
    tol = result.summary().get("tol")
    if tol is not None:
        ax.axhline(tol, color="k", linestyle="--", label=f"tol = {tol:g}")
    ax.set_xlabel("iteration k")
    ax.set_ylabel("stop test and relative change")
    ax.set_title(result.solver)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    return ax


def sweep_curves(
    records: Iterable[Mapping[str, Any]],
    ax: Optional["Axes"] = None,
    show_failed: bool = True,
) -> "Axes":
    """Plots the number of iterations against γ for every method of a γ sweep (the paper's
    Fig. 3).

    Runs that did not converge are left out of the curves; with ``show_failed`` they are marked
    by a cross at the bottom of the plot.

    Args:
        records: the list :func:`contactdd.sweep` returns.
        ax: axes to draw into (default: a new figure).
        show_failed: mark non-converged runs.

    Returns:
        The axes.
    """
    ax = _axes(ax)
    records = [r for r in records if r["gamma"] != "auto"]
    methods = list(dict.fromkeys(r["method"] for r in records))
    failed_markers = ("x", "+", "1", "2", "3")
    for n, method in enumerate(methods):
        runs = sorted((r for r in records if r["method"] == method), key=lambda r: r["gamma"])
        ok = [r for r in runs if r["converged"]]
        (line,) = ax.plot(
            [r["gamma"] for r in ok],
            [r["iterations"] for r in ok],
            "o-",
            markersize=4,
            label=method,
        )
        failed = [r for r in runs if not r["converged"]]
        if show_failed and failed:
            ax.plot(
                [r["gamma"] for r in failed],
                [0] * len(failed),
                failed_markers[n % len(failed_markers)],
                color=line.get_color(),
                markersize=9,
                clip_on=False,
            )
    ax.set_xlabel("γ")
    ax.set_ylabel("iterations m")
    title = "iterations against γ"
    if show_failed and any(not r["converged"] for r in records):
        title += " (× on the axis: did not converge)"
    ax.set_title(title)
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax.legend()
    return ax
