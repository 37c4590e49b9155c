"""load_results reads a result folder back into the result object the solve returned: every
attribute identical, the summary the same, and the plots draw from it. An incomplete folder is
refused."""

import errno
import json
import os
import re
import shutil
import subprocess
import threading
import time
from pathlib import Path

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


# The folder is untrusted: every file is read by the reader of `contactdd plot`, which follows no
# symbolic link, opens no FIFO or device and refuses a file over its limit. The limits are the
# Rust constants TEXT_LIMIT and VTU_LIMIT (crates/io/src/result_set.rs).
TEXT_LIMIT = 256 << 20
VTU_LIMIT = 1 << 30


@pytest.fixture
def run(tmp_path):
    """A small result folder and a folder outside it."""
    contactdd.solve(contactdd.notch_benchmark(8, 4)).write_vtu(tmp_path / "run")
    (tmp_path / "outside").mkdir()
    return tmp_path / "run"


def refused(folder, match, seconds=10.0):
    """load_results(folder) raises ContactddIOError matching `match` within `seconds` (run on a
    daemon thread, so that a read that blocks fails the test instead of hanging it)."""
    outcome = {}

    def target():
        try:
            contactdd.load_results(folder)
            outcome["error"] = None
        except BaseException as e:  # noqa: BLE001 - the test inspects it
            outcome["error"] = e

    thread = threading.Thread(target=target, daemon=True)
    start = time.monotonic()
    thread.start()
    thread.join(seconds)
    assert not thread.is_alive(), f"load_results({folder}) still runs after {seconds} s"
    error = outcome["error"]
    assert isinstance(error, contactdd.ContactddIOError), repr(error)
    assert isinstance(error, OSError)
    assert re.search(match, str(error)), str(error)
    return time.monotonic() - start


def test_a_link_to_a_file_outside_is_refused(run):
    outside = run.parent / "outside" / "lower.vtu"
    shutil.copy(run / "lower.vtu", outside)
    (run / "lower.vtu").unlink()
    (run / "lower.vtu").symlink_to(outside)
    refused(run, r"lower\.vtu' is a symbolic link, not a regular file")
    # The same for summary.json and history.csv, and a link inside the folder.
    shutil.copy(run / "summary.json", run.parent / "outside" / "summary.json")
    (run / "summary.json").unlink()
    (run / "summary.json").symlink_to(run.parent / "outside" / "summary.json")
    refused(run, r"summary\.json' is a symbolic link")
    (run / "summary.json").unlink()
    shutil.copy(run.parent / "outside" / "summary.json", run / "summary.json")
    (run / "lower.vtu").unlink()
    shutil.copy(outside, run / "lower.vtu")
    assert contactdd.load_results(run).bodies[0].name == "lower"
    (run / "history.csv").rename(run / "history-copy.csv")
    (run / "history.csv").symlink_to("history-copy.csv")
    refused(run, r"history\.csv' is a symbolic link")


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs on this system")
def test_a_fifo_is_refused_without_waiting_for_a_writer(run):
    (run / "history.csv").unlink()
    os.mkfifo(run / "history.csv")
    refused(run, r"history\.csv' is a special file")
    (run / "summary.json").unlink()
    os.mkfifo(run / "summary.json")
    refused(run, r"summary\.json' is a special file")


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="no /dev/zero")
def test_a_link_to_dev_zero_is_refused_at_once(run):
    (run / "upper.vtu").unlink()
    (run / "upper.vtu").symlink_to("/dev/zero")
    assert refused(run, r"upper\.vtu' is a symbolic link") < 5.0
    (run / "summary.json").unlink()
    (run / "summary.json").symlink_to("/dev/zero")
    assert refused(run, r"summary\.json' is a symbolic link") < 5.0


def test_a_file_over_its_limit_is_refused(run):
    # Sparse files: a size of limit + 1 bytes costs no disk and no memory.
    with open(run / "history.csv", "r+b") as f:
        f.truncate(TEXT_LIMIT + 1)
    assert refused(run, rf"history\.csv' is larger than {TEXT_LIMIT} bytes") < 5.0
    with open(run / "lower.vtu", "r+b") as f:
        f.truncate(VTU_LIMIT + 1)
    assert refused(run, rf"lower\.vtu' is larger than {VTU_LIMIT} bytes") < 5.0
    with open(run / "summary.json", "r+b") as f:
        f.truncate(TEXT_LIMIT + 1)
    assert refused(run, rf"summary\.json' is larger than {TEXT_LIMIT} bytes") < 5.0


def test_a_manifest_names_only_files_of_the_folder(run):
    shutil.copy(run / "lower.vtu", run.parent / "outside" / "lower.vtu")
    summary = json.loads((run / "summary.json").read_text())
    for name in ["../outside/lower.vtu", str(run.parent / "outside" / "lower.vtu"), "..", 3]:
        summary["files"] = [name if f == "lower.vtu" else f for f in summary["files"]]
        (run / "summary.json").write_text(json.dumps(summary))
        with pytest.raises(contactdd.ContactddError, match="not a file name of the folder"):
            contactdd.load_results(run)
        summary["files"] = ["lower.vtu" if f == name else f for f in summary["files"]]


@pytest.mark.parametrize("encoding", ["binary", "zlib"])
def test_a_binary_vtu_that_lies_or_is_cut_is_refused(tmp_path, encoding):
    contactdd.solve(contactdd.notch_benchmark(8, 4)).write_vtu(tmp_path / "run", format=encoding)
    path = tmp_path / "run" / "lower.vtu"
    data = path.read_bytes()
    start = data.index(b"_", data.index(b"<AppendedData")) + 1

    def lie(at, value, message):
        word = value.to_bytes(8, "little")
        path.write_bytes(data[:start + at] + word + data[start + at + 8:])
        with pytest.raises(contactdd.ContactddError, match=message):
            contactdd.load_results(tmp_path / "run")

    # The first block's byte count (binary) or block count (zlib) made huge: refused before
    # anything that size is allocated.
    lie(0, 1 << 62, "more than the file holds")
    if encoding == "zlib":
        # The displacement is one block: its sizes made to lie.
        assert int.from_bytes(data[start:start + 8], "little") == 1
        packed = int.from_bytes(data[start + 24:start + 32], "little")
        lie(8, 1 << 40, "bad sizes")
        lie(16, 1 << 20, "bad sizes")
        lie(24, 1, "more than zlib can expand")
        lie(24, packed - 1, "not one zlib stream")
        lie(24, 1 << 62, "past the end of the file")
        last = int.from_bytes(data[start + 16:start + 24], "little")
        lie(16, last + 8, "not one zlib stream")
        lie(16, last - 8, "not one zlib stream")
    # Cut short inside the appended data.
    path.write_bytes(data[:len(data) - 200])
    with pytest.raises(contactdd.ContactddError, match="lower.vtu: not a VTU file of contactdd"):
        contactdd.load_results(tmp_path / "run")
    path.write_bytes(data)
    assert contactdd.load_results(tmp_path / "run").bodies[0].name == "lower"


@pytest.mark.parametrize("encoding", ["zlib", "binary", "ascii"])
def test_one_file_for_all_bodies_loads_as_the_files_per_body(tmp_path, encoding):
    """layout="collection": one bodies.vtu with a piece per body reads back to the result of the
    per-body folder, every array bit for bit, and to the solve's own result. cylinder_plates: P2,
    three bodies, points without a partner (NaN and infinite arrays)."""
    problem = contactdd.Problem.from_toml(REPO / "examples" / "cylinder_plates.toml")
    problem.solver(load_steps=1)
    result = contactdd.solve(problem)
    result.write_vtu(tmp_path / "per-body", format=encoding)
    result.write_vtu(tmp_path / "collection", format=encoding, layout="collection")
    summary = json.loads((tmp_path / "collection" / "summary.json").read_text())
    assert summary["files"] == ["contact.csv", "history.csv", "bodies.vtu", "results.pvd"]
    per_body = contactdd.load_results(tmp_path / "per-body")
    collection = contactdd.load_results(tmp_path / "collection")
    assert_same_result(per_body, collection)
    assert_same_result(result, collection)
    assert per_body.summary() == collection.summary()
    for a, b in zip(per_body.bodies, collection.bodies):
        for name in ["nodes", "triangles", "displacement", "stress", "von_mises",
                     "contact_pressure"]:
            x, y = getattr(a, name), getattr(b, name)
            assert x.dtype == y.dtype and x.tobytes() == y.tobytes(), (a.name, name)


def test_one_file_for_all_bodies_of_a_monolithic_solve_and_of_load_steps(notch, tmp_path):
    result = contactdd.monolithic(notch)
    result.write_vtu(tmp_path / "mono", layout="collection")
    assert_same_result(result, contactdd.load_results(tmp_path / "mono"))
    with pytest.raises(contactdd.ContactddError, match="'per-body' or 'collection'"):
        result.write_vtu(tmp_path / "bad", layout="pieces")
    if not CLI.is_file():
        pytest.skip(f"{CLI} is not built (cargo build --release)")
    toml = REPO / "examples" / "recess_steps.toml"
    for layout in ["per-body", "collection"]:
        out = subprocess.run([str(CLI), "solve", str(toml), "--out", str(tmp_path / layout),
                              "--vtu-layout", layout, "-q"],
                             capture_output=True, text=True, timeout=600)
        assert out.returncode == 0, out.stderr
    files = json.loads((tmp_path / "collection" / "summary.json").read_text())["files"]
    steps = len(json.loads((tmp_path / "collection" / "summary.json").read_text())["steps"])
    assert [f for f in files if f.endswith(".vtu")] == [f"bodies-step{k}.vtu"
                                                       for k in range(1, steps + 1)]
    assert_same_result(contactdd.load_results(tmp_path / "per-body"),
                       contactdd.load_results(tmp_path / "collection"), timing=False)
