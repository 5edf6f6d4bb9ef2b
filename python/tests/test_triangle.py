"""mwst.triangle, the drop-in for the `triangle` package: each switch, read by the library's parser,
through a round trip (its output fed back as input), and the refusals."""

import numpy as np
import pytest

import mwst
import mwst.triangle as tr
from conftest import canonical_triangles, square_with_hole


def pslg():
    vertices, segments, holes = square_with_hole()
    return {"vertices": vertices, "segments": segments, "holes": holes}


def areas(out):
    a, b, c = (out["vertices"][out["triangles"][:, i]] for i in range(3))
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def valid(out, tri=None, **check):
    tri = pslg() if tri is None else tri
    result = mwst.check(out, tri["vertices"], tri.get("segments"), tri.get("holes"), **check)
    assert result.ok, result.messages
    return result


def round_trip(out, opts):
    """A result fed back as input with the switches `opts` triangulates the same vertices into as
    many triangles over the same area, a valid (constrained) Delaunay mesh: the result was already
    one (the triangles themselves may differ where four vertices are cocircular)."""
    again = tr.triangulate(out, opts)
    np.testing.assert_array_equal(again["vertices"], out["vertices"])
    assert len(again["triangles"]) == len(out["triangles"])
    assert areas(again).sum() == pytest.approx(areas(out).sum(), rel=1e-12)
    valid(again, {k: out[k] for k in ("vertices", "segments", "holes") if k in out} if "p" in opts
          else {"vertices": out["vertices"]}, delaunay=True)


def test_no_switch_is_the_delaunay_triangulation_of_the_points():
    out = tr.triangulate(pslg())  # Triangle ignores segments and holes without p
    assert set(out) == {"vertices", "vertex_markers", "triangles"}
    valid(out, {"vertices": pslg()["vertices"]}, delaunay=True)
    assert areas(out).sum() == 16
    assert out["triangles"].dtype == np.int32 and out["vertex_markers"].shape == (8, 1)
    round_trip(out, "")


def test_p_uses_segments_and_holes():
    out = tr.triangulate(pslg(), "p")
    assert set(out) == {"vertices", "vertex_markers", "triangles", "segments", "segment_markers", "holes"}
    valid(out, delaunay=True)
    assert areas(out).sum() == 12
    np.testing.assert_array_equal(out["holes"], pslg()["holes"])
    round_trip(out, "p")


@pytest.mark.parametrize("opts,angle", [("pq", 20), ("pq30", 30), ("pq32.5", 32.5)])
def test_q_refines_to_the_angle(opts, angle):
    out = tr.triangulate(pslg(), opts)
    valid(out, delaunay=True, min_angle=angle)
    assert len(out["vertices"]) > 8
    round_trip(out, "p")


@pytest.mark.parametrize("opts,area", [("pa0.1", 0.1), ("pq25a0.02", 0.02), ("pa.5", 0.5)])
def test_a_bounds_the_area(opts, area):
    out = tr.triangulate(pslg(), opts)
    valid(out, delaunay=True)
    assert areas(out).max() <= area and areas(out).sum() == pytest.approx(12)
    same = mwst.triangulate(pslg(), method="dr", min_angle=25 if "q" in opts else 0, max_area=area)
    np.testing.assert_array_equal(canonical_triangles(out["vertices"], out["triangles"]),
                                  canonical_triangles(same.vertices, same.triangles))
    round_trip(out, "p")


def test_c_keeps_the_convex_hull_with_segments():
    points = np.random.default_rng(3).random((50, 2))
    out = tr.triangulate({"vertices": points}, "c")
    assert set(out) == {"vertices", "vertex_markers", "triangles", "segments", "segment_markers"}
    hull = {tuple(sorted(e)) for e in out["segments"].tolist()}
    assert hull == {tuple(sorted(e)) for e in tr.convex_hull(points).tolist()}
    assert np.all(out["segment_markers"] == 1)
    # A polygon with c: the hull around it is meshed too, and its edges are segments.
    concave = {"vertices": [[0, 0], [2, 0], [2, 2], [1, 0.5], [0, 2]], "segments": [[0, 1], [1, 2], [2, 3], [3, 4], [4, 0]]}
    inside, whole = tr.triangulate(concave, "p"), tr.triangulate(concave, "pc")
    assert areas(whole).sum() > areas(inside).sum()
    assert len(whole["segments"]) == 6


def test_S_caps_the_steiner_points():
    out = tr.triangulate(pslg(), "pq33S5")
    assert len(out["vertices"]) - 8 <= 5
    assert len(tr.triangulate(pslg(), "pq33S")["vertices"]) == 8
    valid(out)


def test_A_gives_regional_attributes():
    vertices = [[0, 0], [2, 0], [2, 1], [0, 1], [1, 0], [1, 1]]
    segments = [[0, 4], [4, 1], [1, 2], [2, 5], [5, 3], [3, 0], [4, 5]]
    tri = {"vertices": vertices, "segments": segments, "regions": [[0.5, 0.5, 1, 0], [1.5, 0.5, 2, 0]]}
    out = tr.triangulate(tri, "pqA")
    centroids = out["vertices"][out["triangles"]].mean(axis=1)
    np.testing.assert_array_equal(out["triangle_attributes"][:, 0], np.where(centroids[:, 0] < 1, 1.0, 2.0))
    np.testing.assert_array_equal(out["regions"], np.array(tri["regions"], dtype=float))
    assert "triangle_attributes" not in tr.triangulate(tri, "pq")


def test_e_lists_every_edge_once_with_markers():
    tri = pslg()
    tri["segment_markers"] = [5, 5, 5, 5, 7, 7, 7, 7]
    out = tr.triangulate(tri, "pq30e")
    t = out["triangles"]
    from_triangles = {tuple(sorted(e)) for k in range(3) for e in t[:, [k, (k + 1) % 3]].tolist()}
    listed = [tuple(sorted(e)) for e in out["edges"].tolist()]
    assert len(listed) == len(set(listed)) and set(listed) == from_triangles
    segment_marker = {tuple(sorted(s)): m for s, m in zip(out["segments"].tolist(), out["segment_markers"][:, 0])}
    assert set(segment_marker.values()) == {5, 7}
    for edge, marker in zip(listed, out["edge_markers"][:, 0]):
        assert marker == segment_marker.get(edge, 0)


def test_n_gives_neighbors():
    out = tr.triangulate(pslg(), "pq30n")
    t, n = out["triangles"], out["neighbors"]
    assert n.shape == t.shape
    for k in range(len(t)):
        for i in range(3):
            if n[k, i] >= 0:
                assert {t[k, (i + 1) % 3], t[k, (i + 2) % 3]} <= set(t[n[k, i]])
    assert (n < 0).sum() == len(out["segments"])  # the boundary is all segments


def test_j_leaves_out_unused_vertices():
    tri = pslg()
    tri["vertices"] = np.vstack([tri["vertices"], [[2.5, 2.2], [0.0, 0.0]]])  # in the hole; a duplicate
    kept = tr.triangulate(tri, "p")
    assert len(kept["vertices"]) == 10
    out = tr.triangulate(tri, "pj")
    assert len(out["vertices"]) == 8 and out["triangles"].max() == 7
    np.testing.assert_array_equal(canonical_triangles(out["vertices"], out["triangles"]),
                                  canonical_triangles(kept["vertices"], kept["triangles"]))


@pytest.mark.parametrize("opts,missing", [
    ("pB", {"vertex_markers", "segment_markers"}),
    ("pP", {"segments", "segment_markers"}),
    ("pN", {"vertices", "vertex_markers"}),
    ("pE", {"triangles"}),
])
def test_output_suppressing_switches(opts, missing):
    full = tr.triangulate(pslg(), "p")
    out = tr.triangulate(pslg(), opts)
    assert set(out) == set(full) - missing


def test_O_ignores_holes():
    out = tr.triangulate(pslg(), "pO")
    assert areas(out).sum() == 16 and "holes" not in out


@pytest.mark.parametrize("opts", ["pz", "pQ", "pV", "pVV", "pI", "pv", "pi", "pF", "pl", "ps", "pC", "pX", "-p", "Qzp"])
def test_switches_that_do_not_change_the_mesh(opts):
    expected = tr.triangulate(pslg(), "pq30")
    out = tr.triangulate(pslg(), opts + "q30")
    np.testing.assert_array_equal(out["triangles"], expected["triangles"])
    np.testing.assert_array_equal(out["vertices"], expected["vertices"])


@pytest.mark.parametrize("opts", ["pD", "pq30D", "pY", "pYY", "pa"])
def test_switches_the_mesher_may_refuse(opts):
    """D, Y, YY and a without a number are parsed; the mesher refuses them until it honours them
    (then the result must be a valid mesh)."""
    try:
        out = tr.triangulate(pslg(), opts)
    except mwst.InputError as e:
        assert "not supported" in str(e)
    else:
        valid(out)


def test_r_refines_a_mesh_or_is_refused():
    coarse = tr.triangulate(pslg(), "p")
    try:
        out = tr.triangulate(coarse, "rpq30")
    except mwst.InputError as e:
        assert "not supported" in str(e)
    else:
        valid(out, min_angle=30)
    with pytest.raises(mwst.InputError, match="-r: refining needs the triangles"):
        tr.triangulate(pslg(), "rp")


@pytest.mark.parametrize("opts,message", [
    ("pu", "^-u: user-defined size constraints"),
    ("pg", r"^-g: Object File Format \(.off\) output is not supported"),
    ("po2", r"^-o2: second-order"),
    ("px", "^-x: unknown switch"),
    ("pq3.0.1", "q"),
    ("pa0", "^-a: the maximum area must be greater than zero"),
    ("pe5", "^-e: takes no number"),
])
def test_refused_switches_name_themselves(opts, message):
    with pytest.raises(mwst.InputError, match=message):
        tr.triangulate(pslg(), opts)


def test_parse_switches_is_the_library_parser():
    s = tr.parse_switches("pq28.5a0.25cS12AenjzQ")
    assert (s["method"], s["min_angle"], s["max_area"], s["max_steiner"]) == ("dr", 28.5, 0.25, 12)
    assert s["poly"] and s["convex_hull"] and s["region_attributes"] and s["edges"] and s["neighbours"]
    assert s["jettison"] and s["zero_based"] and s["quiet"] and not s["refine"]
    plain = tr.parse_switches("")
    assert plain["method"] == "dt" and plain["max_area"] is None and plain["max_steiner"] is None
    assert tr.parse_switches("a1")["min_angle"] == 0 and tr.parse_switches("a1")["method"] == "dr"


def test_delaunay_convex_hull_voronoi():
    pts = [[0, 0], [0, 1], [0.5, 0.5], [1, 1], [1, 0]]
    triangles = tr.delaunay(pts)
    assert triangles.shape == (4, 3) and triangles.dtype == np.int32
    assert areas({"vertices": np.array(pts, dtype=float), "triangles": triangles}).min() > 0
    hull = tr.convex_hull([[0, 0], [0, 1], [1, 1], [1, 0], [0.5, 0.5]])
    assert {tuple(sorted(e)) for e in hull.tolist()} == {(0, 1), (1, 2), (2, 3), (0, 3)}
    points, edges, ray_origins, ray_directions = tr.voronoi(pts)
    # The triangle package's documented answer for these points, up to order.
    assert sorted(map(tuple, points.tolist())) == [(0.0, 0.5), (0.5, 0.0), (0.5, 1.0), (1.0, 0.5)]
    assert len(edges) == 4 and len(ray_origins) == 4
    rays = sorted((tuple(points[o]), tuple(d)) for o, d in zip(ray_origins, ray_directions.tolist()))
    assert rays == [((0.0, 0.5), (-1.0, 0.0)), ((0.5, 0.0), (0.0, -1.0)), ((0.5, 1.0), (0.0, 1.0)),
                    ((1.0, 0.5), (1.0, 0.0))]
    # Every Voronoi vertex is equidistant from the corners of its triangle.
    many = np.random.default_rng(8).random((200, 2))
    centres = tr.voronoi(many)[0]
    t = tr.delaunay(many)
    d = np.hypot(*(many[t] - centres[:, None, :]).transpose(2, 0, 1))
    np.testing.assert_allclose(d, d[:, :1].repeat(3, axis=1), rtol=1e-9)


def test_vertex_attributes_pass_through_without_steiner_points():
    tri = pslg()
    tri["vertex_attributes"] = np.arange(8.0)
    out = tr.triangulate(tri, "p")
    np.testing.assert_array_equal(out["vertex_attributes"][:, 0], np.arange(8.0))


@pytest.mark.parametrize("opts", ["pq30", "pq25a0.5", "pq30j", "q30", "pcq28"])
def test_vertex_attributes_are_interpolated_to_steiner_points(opts):
    """Input vertices keep their attributes; Steiner points get them interpolated linearly, so two
    linear functions of the coordinates are reproduced exactly at every output vertex."""
    tri = pslg()
    v = np.asarray(tri["vertices"], dtype=np.float64)
    tri["vertex_attributes"] = np.column_stack([v[:, 0] + 2 * v[:, 1], 3 - v[:, 1]])
    out = tr.triangulate(tri, opts)
    assert len(out["vertices"]) > len(v)  # Steiner points were added
    w = out["vertices"]
    assert out["vertex_attributes"].shape == (len(w), 2)
    np.testing.assert_allclose(out["vertex_attributes"], np.column_stack([w[:, 0] + 2 * w[:, 1], 3 - w[:, 1]]),
                               rtol=0, atol=1e-9)
    if "j" not in opts:
        np.testing.assert_array_equal(out["vertex_attributes"][: len(v)], tri["vertex_attributes"])


def test_vertex_attributes_of_the_wrong_shape_are_refused():
    tri = pslg()
    tri["vertex_attributes"] = np.zeros((3, 2))
    with pytest.raises(ValueError):
        tr.triangulate(tri, "pq30")


def test_docstrings():
    for name in tr.__all__:
        assert getattr(tr, name).__doc__, name


def test_stub_matches_the_module():
    import ast
    import inspect
    import pathlib

    stub = ast.parse(pathlib.Path(tr.__file__).with_suffix(".pyi").read_text())
    declared = {n.name: [a.arg for a in n.args.args] for n in stub.body if isinstance(n, ast.FunctionDef)}
    assert set(declared) == set(tr.__all__)
    for name in tr.__all__:
        assert declared[name] == list(inspect.signature(getattr(tr, name)).parameters), name


def test_markers_carried_as_triangle_carries_them():
    """Vertices on a segment take its marker (Steiner points included), other boundary vertices 1,
    inside 0; the library's rules (format_triangle_files), as Triangle's."""
    tri = pslg()
    tri["segment_markers"] = [5, 5, 5, 5, 7, 7, 7, 7]
    out = tr.triangulate(tri, "pq30a0.05")
    x, y = out["vertices"].T
    outer = (x == 0) | (x == 4) | (y == 0) | (y == 4)
    inner = ~outer & (((x == 1) | (x == 3)) & (y >= 1) & (y <= 3) | ((y == 1) | (y == 3)) & (x >= 1) & (x <= 3))
    expected = np.where(outer, 5, np.where(inner, 7, 0))
    np.testing.assert_array_equal(out["vertex_markers"][:, 0], expected)
    assert (expected == 0).any() and len(out["vertices"]) > 8


@pytest.mark.parametrize("opts", ["pA", "pq25a", "p"])
def test_a_region_seed_outside_the_domain_is_an_input_error(opts):
    # The seed (2, 2) lies in the hole of the square: refused whatever the switches (Triangle
    # ignores such a region).
    tri = dict(pslg(), regions=np.array([[2.0, 2.0, 1.0, 0.5]]))
    with pytest.raises(mwst.InputError, match=r"region 1: its seed \(2, 2\) lies outside the domain"):
        tr.triangulate(tri, opts)
