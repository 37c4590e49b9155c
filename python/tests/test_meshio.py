"""The VTU files and the .pvd collection a solve writes, read by meshio (an independent VTK
reader): every array by name and shape, and the values against the result object."""

import xml.etree.ElementTree as ET

import numpy as np
import pytest

import contactdd

meshio = pytest.importorskip("meshio")


def test_meshio_reads_every_vtu_of_the_collection(notch, tmp_path):
    result = contactdd.solve(notch)
    result.write_vtu(tmp_path)
    pvd = ET.parse(tmp_path / "results.pvd").getroot()
    files = [d.get("file") for d in pvd.iter("DataSet")]
    assert sorted(files) == ["lower.vtu", "upper.vtu"]
    for body, name in zip(result.bodies, ["lower.vtu", "upper.vtu"]):
        mesh = meshio.read(tmp_path / name)
        n = len(body.nodes)
        assert mesh.points.shape == (n, 3)
        np.testing.assert_allclose(mesh.points[:, :2], body.nodes)
        data = mesh.point_data
        assert data["displacement"].shape == (n, 3)
        np.testing.assert_allclose(data["displacement"][:, :2], body.displacement)
        assert data["stress"].shape == (n, 9)
        for scalar in ["von_mises", "contact_pressure", "gap", "contact_status",
                       "principal_stress_1", "principal_stress_2", "principal_stress_3"]:
            assert data[scalar].shape in [(n,), (n, 1)], scalar
        np.testing.assert_allclose(np.ravel(data["von_mises"]), body.von_mises)
        cells = sum(len(block.data) for block in mesh.cells)
        assert cells == len(body.triangles)
        assert sum(len(np.ravel(v)) for v in mesh.cell_data["element_von_mises"]) == cells


@pytest.mark.parametrize("order", ["p1", "p2"])
@pytest.mark.parametrize("encoding", ["binary", "zlib"])
def test_meshio_reads_binary_files_as_the_ascii_ones(tmp_path, order, encoding):
    """The binary and zlib encodings and ASCII, all read by meshio: the same arrays bit for bit
    (NaN where the other has NaN), the same cells; load_results reads them to the same result."""
    result = contactdd.solve(contactdd.notch_benchmark(16, 8, order))
    result.write_vtu(tmp_path / encoding, format=encoding)
    result.write_vtu(tmp_path / "ascii", format="ascii")
    head = (tmp_path / encoding / "lower.vtu").read_bytes()
    assert b'<AppendedData encoding="raw">' in head and b'format="ascii"' not in head
    assert (b'compressor="vtkZLibDataCompressor"' in head) == (encoding == "zlib")
    assert b"<AppendedData" not in (tmp_path / "ascii" / "lower.vtu").read_bytes()
    for body in result.bodies:
        a = meshio.read(tmp_path / "ascii" / f"{body.name}.vtu")
        b = meshio.read(tmp_path / encoding / f"{body.name}.vtu")
        assert b.points.tobytes() == a.points.tobytes()
        assert b.point_data["displacement"].tobytes() == a.point_data["displacement"].tobytes()
        # Against the result object too (an independent path: the solver's own arrays).
        assert b.point_data["displacement"][:, :2].tobytes() == body.displacement.tobytes()
        assert sorted(b.point_data) == sorted(a.point_data)
        for name, values in a.point_data.items():
            np.testing.assert_array_equal(b.point_data[name], values, err_msg=name)
        assert [c.type for c in b.cells] == [c.type for c in a.cells]
        for cb, ca in zip(b.cells, a.cells):
            np.testing.assert_array_equal(cb.data, ca.data)
    loaded = [contactdd.load_results(tmp_path / e) for e in ["ascii", encoding]]
    for x, y in zip(loaded[0].bodies, loaded[1].bodies):
        assert x.displacement.tobytes() == y.displacement.tobytes()
        assert x.stress.tobytes() == y.stress.tobytes()
        np.testing.assert_array_equal(x.triangles, y.triangles)


def test_meshio_reads_zlib_arrays_of_several_blocks(tmp_path):
    """A body large enough that its arrays span several 32 KiB zlib blocks (the stress tensor:
    72 bytes per node), read by meshio against the result object."""
    result = contactdd.solve(contactdd.notch_benchmark(64, 32))
    result.write_vtu(tmp_path, format="zlib")
    for body in result.bodies:
        assert 72 * len(body.nodes) > 3 * 32768
        mesh = meshio.read(tmp_path / f"{body.name}.vtu")
        np.testing.assert_array_equal(mesh.points[:, :2], body.nodes)
        assert mesh.point_data["displacement"][:, :2].tobytes() == body.displacement.tobytes()
        np.testing.assert_array_equal(np.ravel(mesh.point_data["von_mises"]), body.von_mises)
        np.testing.assert_array_equal(mesh.cells[0].data, body.triangles)


def test_write_vtu_refuses_an_unknown_format(tmp_path):
    result = contactdd.solve(contactdd.notch_benchmark(8, 4))
    with pytest.raises(contactdd.ContactddError,
                       match="unknown VTU format 'lzma'.*'zlib', 'binary' or 'ascii'"):
        result.write_vtu(tmp_path, format="lzma")
    assert not (tmp_path / "summary.json").exists()


@pytest.mark.parametrize("encoding", ["zlib", "binary", "ascii"])
def test_meshio_reads_the_points_of_the_one_file_of_all_bodies(tmp_path, encoding):
    """layout="collection": meshio merges the pieces of bodies.vtu into one mesh, the bodies'
    points and point arrays in body order. Its cells: meshio 5.3 keeps only the last piece's
    (shifted to the merged points) and its cell arrays, a limit of its reader that
    docs/outputs.md states; a reader that keeps every piece's gives them all, shifted."""
    result = contactdd.solve(contactdd.notch_benchmark(16, 8, "p2"))
    result.write_vtu(tmp_path, format=encoding, layout="collection")
    pvd = ET.parse(tmp_path / "results.pvd").getroot()
    assert [d.get("file") for d in pvd.iter("DataSet")] == ["bodies.vtu"]
    mesh = meshio.read(tmp_path / "bodies.vtu")
    bodies = result.bodies
    np.testing.assert_array_equal(mesh.points[:, :2], np.vstack([b.nodes for b in bodies]))
    assert mesh.point_data["displacement"][:, :2].tobytes() == \
        np.vstack([b.displacement for b in bodies]).tobytes()
    assert np.ravel(mesh.point_data["von_mises"]).tobytes() == \
        np.concatenate([b.von_mises for b in bodies]).tobytes()
    starts = np.cumsum([0] + [len(b.nodes) for b in bodies[:-1]])
    every = np.vstack([b.triangles + s for b, s in zip(bodies, starts)])
    last = bodies[-1].triangles + starts[-1]
    assert [c.type for c in mesh.cells] == ["triangle6"]
    cells = mesh.cells[0].data
    assert cells.shape in (every.shape, last.shape)
    np.testing.assert_array_equal(cells, every if len(cells) == len(every) else last)
    assert sum(len(np.ravel(v)) for v in mesh.cell_data["element_von_mises"]) == len(cells)
