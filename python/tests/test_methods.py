"""Every method through Python gives what the command line gives on the data sets: the same
weight (the same double), the same numbers of triangles and vertices, the same triangles."""

import pathlib

import numpy as np
import pytest

import mwst
from conftest import DATA, SLOW, canonical_triangles, cli_triangulate

DATA_SETS = sorted(p.name for p in DATA.glob("*.poly")) + sorted(p.name for p in DATA.glob("*.node"))
# (name, keyword arguments of mwst.triangulate, the same as command-line options)
METHODS = [
    ("dt", {"method": "dt"}, ["--method", "dt"]),
    ("dr", {"method": "dr"}, ["--method", "dr"]),
    ("dr25-circumcenter", {"method": "dr", "min_angle": 25, "steiner": "circumcenter"},
     ["--method", "dr", "--min-angle", "25", "--steiner", "circumcenter"]),
    ("brh", {"method": "brh"}, ["--method", "brh"]),
    ("brh+flip", {"method": "brh", "flip": True}, ["--method", "brh", "--flip"]),
    ("qtr", {"method": "qtr"}, ["--method", "qtr"]),
]
# opt takes seconds to minutes per data set: the small ones in CI, all with MWST_SLOW_TESTS=1.
OPT_DATA_SETS = DATA_SETS if SLOW else ["Airliner.poly", "PuertoRico.poly"]


def compare(cli, tmp_path, name, kwargs, options):
    path = DATA / name
    expected, prefix = cli_triangulate(cli, tmp_path, path, *options)
    mesh = mwst.triangulate(mwst.read(str(path)), **kwargs, threads=2)
    got = mesh.report
    assert got["weight_total"] == expected["weight_total"]
    assert got["weight_boundary"] == expected["weight_boundary"]
    for key in ("triangles", "vertices", "steiner", "min_angle", "max_angle", "duplicates", "crossings"):
        assert got[key] == expected[key], key
    assert got.get("stop_reason") == expected.get("stop_reason")
    assert got["method"] == expected["method"] and got["input"] == expected["input"]
    # The arrays are the mesh the report describes, and the one the command line wrote.
    assert mesh.triangles.shape == (expected["triangles"], 3)
    written = mwst.read(prefix)
    np.testing.assert_array_equal(canonical_triangles(mesh.vertices, mesh.triangles),
                                  canonical_triangles(written.vertices, written.triangles))
    return mesh


@pytest.mark.parametrize("name", DATA_SETS)
@pytest.mark.parametrize("label,kwargs,options", METHODS, ids=[m[0] for m in METHODS])
def test_same_as_command_line(cli, tmp_path, name, label, kwargs, options):
    compare(cli, tmp_path, name, kwargs, options)


@pytest.mark.parametrize("name", OPT_DATA_SETS)
def test_opt_same_as_command_line(cli, tmp_path, name):
    compare(cli, tmp_path, name, {"method": "opt"}, ["--method", "opt"])


def test_weights_add_up_and_mesh_checks():
    """The report's weight is the total length of the arrays' edges, and the library's checker
    accepts the arrays (min angle of dr at 25 degrees included)."""
    pslg = mwst.read(str(DATA / "Plate.poly"))
    mesh = mwst.triangulate(pslg, method="dr", min_angle=25)
    report_weight = mesh.report["weight_total"]
    mesh.report.clear()
    assert mesh.weight == pytest.approx(report_weight, rel=1e-12)
    result = mwst.check(mesh, pslg, delaunay=True, min_angle=25)
    assert result.ok, result.messages
    assert result.domain_area == pytest.approx(result.area, rel=1e-9)


def test_neighbors_and_vertex_kinds_consistent():
    pslg = mwst.read(str(DATA / "Africa.poly"))
    mesh = mwst.triangulate(pslg, method="dr", min_angle=30)
    t, n = mesh.triangles, mesh.neighbors
    for k in range(len(t)):
        for i in range(3):
            j = n[k, i]
            edge = {t[k, (i + 1) % 3], t[k, (i + 2) % 3]}
            if j >= 0:
                assert edge <= set(t[j]) and k in n[j]
    # Input points keep their indices; Steiner points follow and are marked as such.
    count = len(pslg.vertices)
    np.testing.assert_array_equal(mesh.vertices[:count], pslg.vertices)
    assert np.all(mesh.vertex_kind[:count] <= mwst.VertexKind.DUPLICATE)
    assert np.all(mesh.vertex_kind[count:] >= mwst.VertexKind.STEINER)
    assert mesh.report["steiner"] == len(mesh.vertices) - count
    # Counter-clockwise corners.
    a, b, c = (mesh.vertices[t[:, i]] for i in range(3))
    assert np.all((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]) > 0)
