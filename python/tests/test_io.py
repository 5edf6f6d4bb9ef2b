"""mwst.read / mwst.write (the library's readers and writer of Triangle's files), mwst.check (the
library's checker), mwst.bundle_number, mwst.plot, the stub and the docstrings."""

import ast
import inspect
import json
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import mwst
from conftest import DATA, canonical_triangles, cli_triangulate, square_with_hole


# ---- read and write -------------------------------------------------------------------------

def test_read_poly():
    plate = mwst.read(str(DATA / "Plate.poly"))
    assert isinstance(plate, mwst.Pslg)
    assert plate.vertices.shape == (65, 2) and plate.holes.shape == (5, 2)
    assert plate.segments.shape[1] == 2 and plate.segments.min() == 0 and plate.segments.max() == 64
    assert plate.first_index == 1 and plate.source.endswith("Plate.poly")
    points = mwst.read(str(DATA / "Ellipse.node"))
    assert points.segments is None and points.vertices.shape == (1000, 2)


def test_read_errors_name_file_and_line(tmp_path):
    with pytest.raises(mwst.InputError, match="missing.poly"):
        mwst.read(str(tmp_path / "missing.poly"))
    bad = tmp_path / "bad.poly"
    bad.write_text("3 2 0 0\n1 0 0\n2 1 0\n3 zero 1\n0 0\n0\n")
    with pytest.raises(mwst.InputError, match=r"bad\.poly:4: "):
        mwst.read(str(bad))
    with pytest.raises(mwst.InputError, match="missing"):
        mwst.read(str(tmp_path / "missing.1"))


def test_write_then_read_gives_the_same_mesh(tmp_path, cli):
    vertices, segments, holes = square_with_hole()
    mesh = mwst.triangulate(vertices, segments, holes, method="dr", min_angle=30, max_area=0.2)
    prefix = tmp_path / "square.1"
    mwst.write(str(prefix), mesh)
    back = mwst.read(str(prefix))
    np.testing.assert_array_equal(back.vertices, mesh.vertices)  # shortest round-trip decimals
    np.testing.assert_array_equal(back.triangles, mesh.triangles)
    assert {tuple(sorted(s)) for s in back.segments.tolist()} == {tuple(sorted(s)) for s in mesh.segments.tolist()}
    assert mwst.check(back, vertices, segments, holes, min_angle=30).ok
    # With the holes, the .poly is the domain again: re-meshing it gives the same area.
    mwst.write(str(tmp_path / "square.2"), mesh, holes=holes)
    again = mwst.triangulate(mwst.read(str(tmp_path / "square.2.poly")))
    assert mwst.check(again, vertices, segments, holes).ok
    # The command line's checker accepts the files too.
    source = tmp_path / "square.poly"
    rows = [f"{len(vertices)} 2 0 0"] + [f"{i + 1} {x} {y}" for i, (x, y) in enumerate(vertices)]
    rows += [f"{len(segments)} 0"] + [f"{i + 1} {a + 1} {b + 1}" for i, (a, b) in enumerate(segments)]
    rows += ["1", "1 2 2"]
    source.write_text("\n".join(rows) + "\n")
    assert "valid" in cli("check", source, prefix, "--min-angle", "30").stdout
    # Zero-based files, and a dict as the `triangle` package has it.
    mwst.write(str(tmp_path / "zero"), {"vertices": mesh.vertices, "triangles": mesh.triangles}, first_index=0)
    assert (tmp_path / "zero.ele").read_text().splitlines()[1].split()[0] == "0"
    assert not (tmp_path / "zero.poly").exists()


def test_python_reads_what_the_command_line_writes(cli, tmp_path):
    expected, prefix = cli_triangulate(cli, tmp_path, DATA / "Texas.poly", "--method", "dr", "--min-angle", "28")
    mesh = mwst.read(prefix)
    assert isinstance(mesh, mwst.Triangulation) and len(mesh.triangles) == expected["triangles"]
    assert mesh.weight == pytest.approx(expected["weight_total"], rel=1e-12)
    # (Angles below 28 degrees remain next to Texas's small input angles, so no angle check.)
    assert mwst.check(mesh, mwst.read(str(DATA / "Texas.poly"))).ok


def test_write_refuses_a_segment_that_is_no_edge(tmp_path):
    mesh = {"vertices": [[0, 0], [1, 0], [0, 1], [1, 1]], "triangles": [[0, 1, 2], [1, 3, 2]],
            "segments": [[0, 3]]}
    with pytest.raises(mwst.InputError, match=r"segments: segment 0 \(0, 3\) is not an edge of the triangles"):
        mwst.write(str(tmp_path / "x"), mesh)
    with pytest.raises(mwst.InputError, match="triangles: triangle 1 names vertex 4"):
        mwst.write(str(tmp_path / "x"), {"vertices": mesh["vertices"], "triangles": [[0, 1, 2], [1, 4, 2]]})
    assert not list(tmp_path.iterdir())


# ---- check ------------------------------------------------------------------------------------

def test_check_finds_what_is_wrong():
    vertices, segments, holes = square_with_hole()
    mesh = mwst.triangulate(vertices, segments, holes, method="dr", min_angle=25)
    assert mwst.check(mesh, vertices, segments, holes, delaunay=True, min_angle=25)
    missing = {"vertices": mesh.vertices, "triangles": mesh.triangles[1:]}
    result = mwst.check(missing, vertices, segments, holes)
    assert not result and result.violations >= 1 and result.messages
    assert result.area < result.domain_area
    flipped = {"vertices": mesh.vertices, "triangles": mesh.triangles[:, ::-1]}
    assert not mwst.check(flipped, vertices, segments, holes)
    # The hole filled: the mesh covers more than the domain.
    filled = mwst.triangulate(vertices, segments)
    assert not mwst.check(filled, vertices, segments, holes)
    # Plain Delaunay of points is Delaunay, and has angles below 20 degrees.
    points = np.random.default_rng(2).random((500, 2))
    dt = mwst.triangulate(points)
    assert mwst.check(dt, points, delaunay=True)
    assert not mwst.check(dt, points, min_angle=20)


# ---- bundle number ----------------------------------------------------------------------------

def test_bundle_number_matches_the_command_line(cli, tmp_path):
    expected_report, prefix = cli_triangulate(cli, tmp_path, DATA / "Africa.poly", "--method", "dr")
    expected = json.loads(cli("bundle", DATA / "Africa.poly", prefix, "--json").stdout)
    mesh = mwst.read(prefix)
    got = mwst.bundle_number(mesh)
    assert got.number == expected["bundle_number"] and got.exact == expected["exact"]
    assert got.center == pytest.approx((expected["disk"]["x"], expected["disk"]["y"]), rel=0, abs=0)
    assert got.radius == expected["disk"]["r"]
    assert sorted(t + 1 for t in got.triangles.tolist()) == sorted(expected["triangles"])
    again = mwst.bundle_number(mesh.vertices, mesh.triangles)
    assert again.number == got.number and again.center == got.center
    np.testing.assert_array_equal(again.triangles, got.triangles)


def test_bundle_witness_is_a_vertex_empty_disk_meeting_that_many_triangles():
    points = np.random.default_rng(4).random((300, 2))
    mesh = mwst.triangulate(points, method="dr", min_angle=20)
    b = mwst.bundle_number(mesh)
    assert b.exact and len(b.triangles) == b.number >= 1
    center, r = np.array(b.center), b.radius
    used = np.unique(mesh.triangles)
    assert np.min(np.hypot(*(mesh.vertices[used] - center).T)) >= r * (1 - 1e-9)
    # The disk meets each witness triangle: its centre is within r of the triangle (of its edges,
    # or inside it).
    for t in b.triangles:
        a, bb, c = mesh.vertices[mesh.triangles[t]]
        inside = all(np.cross(q - p, center - p) >= 0 for p, q in ((a, bb), (bb, c), (c, a)))
        def dist(p, q):
            s = np.clip(np.dot(center - p, q - p) / np.dot(q - p, q - p), 0, 1)
            return np.hypot(*(p + s * (q - p) - center))
        assert inside or min(dist(a, bb), dist(bb, c), dist(c, a)) < r
    with pytest.raises(mwst.InputError, match="triangles: triangle 0 names vertex 300"):
        mwst.bundle_number(points, [[0, 1, 300]])


# ---- plot -------------------------------------------------------------------------------------

def test_import_does_not_import_matplotlib():
    code = "import sys, mwst; mwst.triangulate([[0, 0], [1, 0], [0, 1]]); print('matplotlib' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_plot(tmp_path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    vertices, segments, holes = square_with_hole()
    mesh = mwst.triangulate(vertices, segments, holes, method="dr", min_angle=30)
    ax = mwst.plot(mesh)
    faces, lines = ax.collections
    assert len(faces.get_paths()) == len(mesh.triangles)
    assert len(lines.get_paths()) == len(mesh.segments)
    assert max(lines.get_linewidths()) > max(faces.get_linewidths())  # segments bold
    steiner = ax.lines[0].get_xydata()
    np.testing.assert_array_equal(steiner, mesh.vertices[mesh.vertex_kind >= mwst.VertexKind.STEINER])
    # The hole stays empty: no triangle covers its seed.
    assert not any(p.contains_point((2.0, 2.0)) for p in faces.get_paths())
    ax.figure.savefig(tmp_path / "mesh.png")
    assert (tmp_path / "mesh.png").stat().st_size > 1000
    fig, given = plt.subplots()
    assert mwst.plot({"vertices": mesh.vertices, "triangles": mesh.triangles}, given) is given
    plt.close("all")


# ---- stub and docstrings ----------------------------------------------------------------------

def test_every_public_function_has_a_docstring():
    for name in mwst.__all__:
        obj = getattr(mwst, name)
        if callable(obj):
            assert obj.__doc__ and len(obj.__doc__.strip()) > 20, name


def test_stub_matches_the_package():
    stub = pathlib.Path(mwst.__file__).with_name("__init__.pyi")
    tree = ast.parse(stub.read_text())
    functions = {n.name: n for n in tree.body if isinstance(n, ast.FunctionDef)}
    classes = {n.name for n in tree.body if isinstance(n, ast.ClassDef)}
    for name in mwst.__all__:
        if name == "__version__":
            continue
        obj = getattr(mwst, name)
        if inspect.isclass(obj):
            assert name in classes, name
            continue
        assert name in functions, name
        stub_args = functions[name].args
        declared = [a.arg for a in stub_args.posonlyargs + stub_args.args + stub_args.kwonlyargs]
        actual = [p.name for p in inspect.signature(obj).parameters.values()
                  if p.kind not in (p.VAR_KEYWORD, p.VAR_POSITIONAL)]
        assert declared == actual, name
    assert pathlib.Path(mwst.__file__).with_name("py.typed").exists()


def test_example_light_mesh(tmp_path):
    """examples/python/light_mesh.py prints the four weights and saves the figure."""
    example = pathlib.Path(__file__).resolve().parents[2] / "examples" / "python" / "light_mesh.py"
    figure = tmp_path / "light.png"
    env = dict(os.environ, PYTHONPATH=str(pathlib.Path(mwst.__file__).resolve().parents[1]))
    out = subprocess.run([sys.executable, str(example), "-o", str(figure)], capture_output=True, text=True,
                         check=True, cwd=tmp_path, env=env).stdout
    weights = {line.split()[0]: float(line.split("weight")[1].split()[0])
               for line in out.splitlines() if "weight" in line}
    assert set(weights) == {"dt", "dr", "brh+flip", "opt"}
    # opt starts from the lightest of its starts (the Delaunay triangulation among them).
    assert weights["opt"] <= weights["dt"]
    assert figure.stat().st_size > 10_000
