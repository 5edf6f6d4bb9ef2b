"""What mwst.triangulate accepts and refuses: every kind of bad array and bad option gives
mwst.InputError (a ValueError) with the library's message; array-likes that are not contiguous
float64 are converted and give the same mesh; a contiguous float64 array is read in place."""

import tracemalloc

import numpy as np
import pytest

import mwst
from conftest import canonical_triangles, square_with_hole


def random_points(n, seed=1):
    return np.random.default_rng(seed).random((n, 2))


def test_input_error_is_a_value_error():
    assert issubclass(mwst.InputError, ValueError)
    assert issubclass(mwst.ResourceError, MemoryError)


# ---- shapes and dtypes ----------------------------------------------------------------------

@pytest.mark.parametrize("vertices", [
    np.zeros((5, 3)),
    np.zeros(10),
    np.zeros((2, 5, 2)),
    np.zeros((5, 1)),
])
def test_vertices_of_wrong_shape(vertices):
    with pytest.raises(mwst.InputError, match=r"vertices: expected an \(n, 2\) array, got shape"):
        mwst.triangulate(vertices)


@pytest.mark.parametrize("name,kwargs,message", [
    ("segments", {"segments": [[0, 1, 2]]}, r"segments: expected an \(n, 2\) array, got shape \(1, 3\)"),
    ("segments", {"segments": [0, 1]}, r"segments: expected an \(n, 2\) array, got shape \(2,\)"),
    ("holes", {"holes": [0.5, 0.5]}, r"holes: expected an \(n, 2\) array, got shape \(2,\)"),
    ("regions", {"regions": [[0.5, 0.5]]}, r"regions: expected an \(n, 4\) array, got shape \(1, 2\)"),
])
def test_other_arrays_of_wrong_shape(name, kwargs, message):
    square = [[0, 0], [1, 0], [1, 1], [0, 1]]
    with pytest.raises(mwst.InputError, match=message):
        mwst.triangulate(square, **kwargs)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf, 1e60, 1e-60])
def test_coordinates_outside_the_supported_range(bad):
    """The library's own check and message: NaN, infinities and magnitudes outside [1e-50, 1e50]."""
    vertices = random_points(10)
    vertices[6, 1] = bad
    with pytest.raises(mwst.InputError, match=r"^point 7 has a coordinate outside the supported range"):
        mwst.triangulate(vertices)


@pytest.mark.parametrize("index", [4, 100, -1, 2**40])
def test_segment_index_out_of_range(index):
    square = [[0, 0], [1, 0], [1, 1], [0, 1]]
    with pytest.raises(mwst.InputError, match="^segment names a vertex that does not exist$"):
        mwst.triangulate(square, [[0, 1], [1, index]])


def test_fractional_and_non_numeric_indices():
    square = [[0, 0], [1, 0], [1, 1], [0, 1]]
    with pytest.raises(mwst.InputError, match="expected integer vertex indices, got non-integral numbers"):
        mwst.triangulate(square, [[0, 1.5]])
    with pytest.raises(mwst.InputError, match="expected integer vertex indices, got an array of dtype bool"):
        mwst.triangulate(square, np.array([[True, False]]))
    # Floats holding whole numbers are indices.
    a = mwst.triangulate(square, np.array([[0.0, 2.0]]))
    b = mwst.triangulate(square, [[0, 2]])
    np.testing.assert_array_equal(a.segments, b.segments)


@pytest.mark.parametrize("vertices", [
    np.array([["a", "b"], ["c", "d"], ["e", "f"]]),
    np.array([[True, False], [False, True], [True, True]]),
    np.array([[1 + 2j, 0], [0, 1], [1, 1]]),
    np.array([[0, 0], [2**60, 0], [0, 1]], dtype=np.int64),
])
def test_vertices_that_are_not_floats(vertices):
    with pytest.raises(mwst.InputError, match="vertices: "):
        mwst.triangulate(vertices)


def test_int_arrays_give_the_float_mesh():
    vertices, segments, holes = square_with_hole()
    as_float = mwst.triangulate(vertices, segments, holes, method="dr", min_angle=30)
    for dtype in (np.int32, np.int64, np.uint16):
        as_int = mwst.triangulate(vertices.astype(dtype), segments.astype(dtype), holes, method="dr", min_angle=30)
        np.testing.assert_array_equal(as_int.vertices, as_float.vertices)
        np.testing.assert_array_equal(as_int.triangles, as_float.triangles)
    as_lists = mwst.triangulate(vertices.tolist(), segments.tolist(), holes.tolist(), method="dr", min_angle=30)
    np.testing.assert_array_equal(as_lists.triangles, as_float.triangles)
    # float32 coordinates convert exactly to float64.
    points = random_points(500).astype(np.float32)
    np.testing.assert_array_equal(mwst.triangulate(points).triangles,
                                  mwst.triangulate(points.astype(np.float64)).triangles)


def test_non_contiguous_arrays_give_the_contiguous_mesh():
    points = random_points(3000)
    expected = mwst.triangulate(points)
    fortran = np.asfortranarray(points)
    assert not fortran.flags.c_contiguous
    np.testing.assert_array_equal(mwst.triangulate(fortran).triangles, expected.triangles)
    wide = np.zeros((3000, 5))
    wide[:, 1], wide[:, 3] = points[:, 0], points[:, 1]
    strided = wide[:, 1::2]
    assert not strided.flags.c_contiguous
    np.testing.assert_array_equal(mwst.triangulate(strided).triangles, expected.triangles)
    every_other = np.repeat(points, 2, axis=0)[::2]
    assert not every_other.flags.c_contiguous
    np.testing.assert_array_equal(mwst.triangulate(every_other).triangles, expected.triangles)
    vertices, segments, holes = square_with_hole()
    a = mwst.triangulate(vertices, segments, holes)
    b = mwst.triangulate(np.asfortranarray(vertices), np.asfortranarray(segments), np.asfortranarray(holes))
    np.testing.assert_array_equal(a.triangles, b.triangles)


def test_contiguous_float64_is_read_in_place():
    """No copy is made of a contiguous float64 vertex array: the numpy memory traced while
    triangulating it stays far below its size, while a Fortran-ordered one is copied whole."""
    points = random_points(200_000)
    fortran = np.asfortranarray(points)
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        mwst.triangulate(points, threads=1)
        in_place_peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.reset_peak()
        mwst.triangulate(fortran, threads=1)
        copied_peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert in_place_peak < points.nbytes / 20
    assert copied_peak >= points.nbytes


def test_results_are_the_library_arrays_without_a_copy():
    mesh = mwst.triangulate(random_points(1000), method="dr")
    for name in ("vertices", "triangles", "neighbors", "segments", "vertex_kind", "vertex_markers"):
        array = getattr(mesh, name)
        assert not array.flags.owndata and type(array.base).__name__ == "PyCapsule", name
        assert array.flags.c_contiguous
    assert mesh.vertices.dtype == np.float64 and mesh.vertices.shape[1] == 2
    assert mesh.triangles.dtype == np.int32 and mesh.neighbors.dtype == np.int32
    assert mesh.vertex_kind.dtype == np.uint8


# ---- errors of the library ------------------------------------------------------------------

@pytest.mark.parametrize("vertices,message", [
    ([[0, 0], [1, 1]], r"^fewer than three points \(2\)$"),
    ([], r"^fewer than three points \(0\)$"),
    ([[0, 0], [1, 1], [2, 2], [3, 3]], "^all points are collinear$"),
    ([[1, 1], [1, 1], [1, 1]], "fewer than three distinct points"),
])
def test_degenerate_inputs(vertices, message):
    with pytest.raises(mwst.InputError, match=message):
        mwst.triangulate(vertices)


def test_strict_refuses_crossing_segments():
    vertices = [[0, 0], [2, 2], [0, 2], [2, 0]]
    crossing = [[0, 1], [2, 3]]
    mesh = mwst.triangulate(vertices, crossing)
    assert mesh.report["crossings"] == 1
    assert mwst.VertexKind.CROSSING in mesh.vertex_kind
    with pytest.raises(mwst.InputError, match="cross"):
        mwst.triangulate(vertices, crossing, strict=True)


@pytest.mark.parametrize("kwargs,message", [
    ({"method": "fast"}, "method: expected one of dt, dr, brh, qtr, opt, got 'fast'"),
    ({"steiner": "middle"}, "steiner: expected offcenter or circumcenter, got 'middle'"),
    ({"method": "dr", "min_angle": 70}, r"^min_angle must be in \[0, 60\) degrees$"),
    ({"method": "dr", "min_angle": -1}, r"^min_angle must be in \[0, 60\) degrees$"),
    ({"method": "dr", "min_angle": float("nan")}, r"^min_angle must be in \[0, 60\) degrees$"),
    ({"method": "dr", "max_area": 0}, "max_area: expected a number > 0"),
    ({"method": "dr", "max_area": -2.5}, "max_area: expected a number > 0"),
    ({"method": "dr", "max_steiner": -1}, "max_steiner: expected a whole number >= 0"),
    ({"method": "brh", "bundle_k": -3}, "bundle_k: expected a whole number >= 0"),
    ({"method": "brh", "bundle_k": 2}, r"^bundle_k must be at least 3"),
    ({"method": "dr", "time_limit": 0}, "time_limit: expected seconds > 0"),
    ({"threads": -1}, "threads: expected a whole number >= 0"),
])
def test_bad_options(kwargs, message):
    with pytest.raises(mwst.InputError, match=message):
        mwst.triangulate([[0, 0], [1, 0], [0, 1]], **kwargs)


def test_option_errors_name_the_python_keywords():
    # The library names its option fields (min_angle_deg, ...); Python callers see the keywords.
    for kwargs in ({"method": "dr", "min_angle": 75}, {"method": "brh", "min_angle": 60.5}):
        with pytest.raises(mwst.InputError) as raised:
            mwst.triangulate([[0, 0], [1, 0], [0, 1]], **kwargs)
        assert "min_angle_deg" not in str(raised.value)
        assert str(raised.value).startswith("min_angle ")


def test_budgets_and_bounds_reach_the_library():
    vertices, segments, holes = square_with_hole()
    capped = mwst.triangulate(vertices, segments, holes, method="dr", min_angle=33, max_steiner=5)
    assert capped.report["steiner"] <= 5
    small = mwst.triangulate(vertices, segments, holes, method="dr", max_area=0.01)
    assert small.report["max_triangle_area"] <= 0.01
    assert len(small.triangles) > 12 / 0.01 * 0.9
    hull = mwst.triangulate(vertices, segments, holes, convex_hull=True)
    assert len(hull.triangles) > len(mwst.triangulate(vertices, segments, holes).triangles) - 1
    assert mwst.triangulate(vertices, segments, holes, method="brh", bundle_k=9).report["parameters"]["bundle_k"] == 9


def test_regions_give_triangle_attributes():
    vertices = [[0, 0], [2, 0], [2, 1], [0, 1], [1, 0], [1, 1]]
    segments = [[0, 4], [4, 1], [1, 2], [2, 5], [5, 3], [3, 0], [4, 5]]
    regions = [[0.5, 0.5, 7.0, -1.0], [1.5, 0.5, 9.0, -1.0]]
    mesh = mwst.triangulate(vertices, segments, regions=regions, method="dr")
    centroids = mesh.vertices[mesh.triangles].mean(axis=1)
    np.testing.assert_array_equal(mesh.triangle_attributes, np.where(centroids[:, 0] < 1, 7.0, 9.0))
    assert mwst.triangulate(vertices, segments).triangle_attributes is None


def test_same_mesh_whatever_the_thread_count():
    points = random_points(60_000, seed=7)
    one = mwst.triangulate(points, threads=1)
    two = mwst.triangulate(points, threads=2)
    np.testing.assert_array_equal(one.triangles, two.triangles)


def test_a_pslg_or_dict_in_place_of_vertices():
    vertices, segments, holes = square_with_hole()
    direct = mwst.triangulate(vertices, segments, holes, method="dr")
    via_pslg = mwst.triangulate(mwst.Pslg(vertices, segments, holes), method="dr")
    via_dict = mwst.triangulate({"vertices": vertices, "segments": segments, "holes": holes}, method="dr")
    for other in (via_pslg, via_dict):
        np.testing.assert_array_equal(canonical_triangles(other.vertices, other.triangles),
                                      canonical_triangles(direct.vertices, direct.triangles))


def test_library_warnings_become_python_warnings():
    vertices, segments, _ = square_with_hole()
    vertices = np.vstack([vertices, [[2.0, 2.0]]])
    with pytest.warns(mwst.MeshWarning, match=r"hole 1 at \(2.000000, 2.000000\) lies on a segment or vertex"):
        mesh = mwst.triangulate(vertices, segments, [[2.0, 2.0]])
    assert mesh.report["warnings"] and len(mesh.triangles) == 12
