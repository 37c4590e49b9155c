"""The plots render to PNG with the Agg backend."""

import pytest

import contactdd

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
    assert ax.get_xlabel() == "x"
    check_png(ax, tmp_path / "pressure.png")
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
