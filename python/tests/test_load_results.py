"""load_results reads a result folder back into the result object the solve returned: every
attribute identical, the summary the same, and the plots draw from it. An incomplete folder is
refused."""

import errno
import shutil
import subprocess

import pytest

import contactdd
from compare import assert_same_result
from conftest import REPO

CLI = REPO / "target" / "release" / "contactdd"


def written_and_loaded(result, folder):
    result.write_vtu(folder)
    return contactdd.load_results(folder)


def assert_same_summary(loaded, result):
    """The folder's summary is the result's, with what the writer adds: the problem's units note
    (none here) and, for a monolithic solve, the reactions."""
    summary, expected = loaded.summary(), result.summary()
    assert set(summary) - set(expected) <= {"units", "reactions"}
    assert summary.get("units") is None
    assert {k: summary[k] for k in expected} == expected


def test_notch(notch, tmp_path):
    result = contactdd.solve(notch)
    loaded = written_and_loaded(result, tmp_path)
    assert_same_result(result, loaded)
    assert_same_summary(loaded, result)
    assert repr(loaded) == repr(result)


def test_p2_three_bodies_without_partners(tmp_path):
    """cylinder_plates: P2, three bodies, points without a partner (infinite gap)."""
    problem = contactdd.Problem.from_toml(REPO / "examples" / "cylinder_plates.toml")
    problem.solver(load_steps=1)  # one solve at the full load instead of the file's 5 steps
    result = contactdd.solve(problem)
    assert any("no-partner" in c.status for c in result.contact)
    assert_same_result(result, written_and_loaded(result, tmp_path))


def test_not_converged(notch, tmp_path):
    result = contactdd.solve(notch, max_iter=2, check=False)
    loaded = written_and_loaded(result, tmp_path)
    assert loaded.stop == "max-iterations" and loaded.message
    assert_same_result(result, loaded)


def test_monolithic(notch, tmp_path):
    result = contactdd.monolithic(notch)
    loaded = written_and_loaded(result, tmp_path)
    assert isinstance(loaded, contactdd.MonolithicResult)
    assert_same_result(result, loaded)
    assert_same_summary(loaded, result)


def test_cli_folder_of_load_steps(tmp_path):
    """A folder of the command line's load steps: the last step, as solve_steps gives it."""
    if not CLI.is_file():
        pytest.skip(f"{CLI} is not built (cargo build --release)")
    toml = REPO / "examples" / "recess_steps.toml"
    out = subprocess.run([str(CLI), "solve", str(toml), "--out", str(tmp_path)],
                         capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    loaded = contactdd.load_results(tmp_path)
    problem = contactdd.Problem.from_toml(toml)
    factors = [s["factor"] for s in loaded.summary()["steps"]]
    last = contactdd.solve_steps(problem, factors)[-1]
    assert loaded.load_factor == last.load_factor == 1.0
    assert_same_result(last, loaded, timing=False)


def test_plots_draw_a_loaded_result(notch, tmp_path):
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    loaded = written_and_loaded(contactdd.solve(notch), tmp_path / "run")
    for draw in [contactdd.plot.contact_pressure, contactdd.plot.deformed_mesh,
                 contactdd.plot.history]:
        ax = draw(loaded)
        ax.figure.savefig(tmp_path / f"{draw.__name__}.png")
        assert (tmp_path / f"{draw.__name__}.png").read_bytes()[:4] == b"\x89PNG"


def test_incomplete_folders_are_refused(notch, tmp_path):
    result = contactdd.solve(notch)
    result.write_vtu(tmp_path / "run")
    shutil.copytree(tmp_path / "run", tmp_path / "no-summary")
    (tmp_path / "no-summary" / "summary.json").unlink()
    with pytest.raises(contactdd.ContactddError, match="summary.json is missing"):
        contactdd.load_results(tmp_path / "no-summary")
    shutil.copytree(tmp_path / "run", tmp_path / "no-vtu")
    (tmp_path / "no-vtu" / "upper.vtu").unlink()
    with pytest.raises(contactdd.ContactddError, match="lists 'upper.vtu', which is missing"):
        contactdd.load_results(tmp_path / "no-vtu")
    shutil.copytree(tmp_path / "run", tmp_path / "bad-vtu")
    (tmp_path / "bad-vtu" / "lower.vtu").write_text("<VTKFile><Unstructured")
    with pytest.raises(contactdd.ContactddError, match="lower.vtu: not a VTU file of contactdd"):
        contactdd.load_results(tmp_path / "bad-vtu")
    with pytest.raises(contactdd.ContactddIOError) as info:
        contactdd.load_results(tmp_path / "nowhere")
    assert isinstance(info.value, OSError) and info.value.errno == errno.ENOENT
