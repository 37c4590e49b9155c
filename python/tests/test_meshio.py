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
