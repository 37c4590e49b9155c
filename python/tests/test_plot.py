"""The plots render to PNG with the Agg backend."""

import json
from pathlib import Path

import numpy as np
import pytest

import contactdd

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


@pytest.fixture(scope="module")
def result():
    return contactdd.solve(contactdd.notch_benchmark())


def check_png(ax, path):
    ax.figure.savefig(path)
    plt.close(ax.figure)
    assert path.stat().st_size > 1000
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_contact_pressure(result, tmp_path):
    ax = contactdd.plot.contact_pressure(result)
    # notch_benchmark's result carries no units note: the labels say whose unit it is.
    assert ax.get_xlabel() == "x (length unit of the problem)"
    assert ax.get_ylabel() == "contact pressure −σₙ (stress unit of the problem)"
    check_png(ax, tmp_path / "pressure.png")
    ax = contactdd.plot.contact_pressure(result, units="cm, N/cm^2")
    assert ax.get_xlabel() == "x (cm)"
    assert ax.get_ylabel() == "contact pressure −σₙ (N/cm^2)"
    plt.close(ax.figure)
    ax = contactdd.plot.contact_pressure(result, pair="notch")
    check_png(ax, tmp_path / "pressure2.png")
    with pytest.raises(KeyError):
        contactdd.plot.contact_pressure(result, pair="nope")


def test_deformed_mesh(result, tmp_path):
    check_png(contactdd.plot.deformed_mesh(result, edges=True), tmp_path / "mesh.png")
    p2 = contactdd.solve(contactdd.notch_benchmark(nx=8, ny=4, order="p2"))
    check_png(contactdd.plot.deformed_mesh(p2, scale=10.0), tmp_path / "mesh_p2.png")


def test_history(result, tmp_path):
    check_png(contactdd.plot.history(result), tmp_path / "history.png")


def test_sweep_curves(tmp_path):
    records = contactdd.sweep(contactdd.notch_benchmark(), gammas=[0.1, 0.3, 0.5, 0.9])
    fig, ax = plt.subplots()
    assert contactdd.plot.sweep_curves(records, ax=ax) is ax
    assert len(ax.get_lines()) >= 3
    check_png(ax, tmp_path / "sweep.png")


def test_contact_pressure_shows_the_contact_zone(tmp_path):
    problem = contactdd.Problem.from_toml(EXAMPLES / "hertz.toml")
    hertz = contactdd.solve(problem)
    c = hertz.contact[0]
    x = np.asarray(c.x)
    closed = np.asarray(c.closed, dtype=bool)
    zone = x[closed].max() - x[closed].min()
    assert 0 < zone < 0.5 * np.ptp(x), "a Hertz zone is a small part of its boundary"
    ax = contactdd.plot.contact_pressure(hertz)
    lo, hi = ax.get_xlim()
    # Every closed point is shown, with half the zone again on either side, not the whole line.
    assert lo <= x[closed].min() and hi >= x[closed].max()
    assert hi - lo == pytest.approx(2 * zone)
    assert ax.get_ylim()[0] == 0
    check_png(ax, tmp_path / "hertz.png")
    ax = contactdd.plot.contact_pressure(hertz, whole=True)
    assert ax.get_xlim()[1] - ax.get_xlim()[0] >= np.ptp(x)
    plt.close(ax.figure)


def test_contact_pressure_units_of_a_results_folder(result, tmp_path):
    result.write_vtu(tmp_path / "out")
    summary = tmp_path / "out" / "summary.json"
    data = json.loads(summary.read_text())
    data["units"] = "mm, MPa"
    summary.write_text(json.dumps(data))
    loaded = contactdd.load_results(tmp_path / "out")
    ax = contactdd.plot.contact_pressure(loaded)
    assert ax.get_xlabel() == "x (mm)"
    assert ax.get_ylabel() == "contact pressure −σₙ (MPa)"
    plt.close(ax.figure)
