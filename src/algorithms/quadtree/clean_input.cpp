// algorithms/quadtree/clean_input.cpp — stage 1 of quadtree refinement: the features. A PSLG goes
// through the constrained Delaunay triangulation (duplicates merged, segments split at vertices on
// them and at crossings); a point set is cleaned by sorting and an exact monotone-chain hull. When
// the domain is the convex hull, the hull edges are features too.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "algorithms/quadtree/route.hpp"
#include "algorithms/quadtree/tree.hpp"
#include "mwst/error.hpp"
#include "mesh/keys.hpp"

namespace mwst::qtr {

// ==== the size bound's call begins here ==========================================================

namespace {

// The leaves the tree needs at least along the segments (size_bound.cpp), from a CDT whose segments
// are the clean input's (or some of them) and whose vertices are features: its witnesses are then
// features of the input. The clip is at least the deepest cells' size: the root's side is at most
// four times the input's span, the span of in.vertices in `points`. (It stops once past the leaf
// limit.)
double leaf_bound(const Mesh& cdt, const std::vector<Point>& points, const CleanInput& in,
                  const QuadtreeOptions& options) {
  if (in.segments.empty()) return 0.0;
  double xmin = std::numeric_limits<double>::infinity(), ymin = xmin, xmax = -xmin, ymax = -xmin;
  for (VertexId v : in.vertices) {
    xmin = std::min(xmin, points[v].x);
    xmax = std::max(xmax, points[v].x);
    ymin = std::min(ymin, points[v].y);
    ymax = std::max(ymax, points[v].y);
  }
  const int deepest = static_cast<int>(std::min(options.max_depth, 52u));
  const double clip = std::ldexp(4.0 * std::max(xmax - xmin, ymax - ymin), -deepest);
  const auto limit = static_cast<double>(Tree::leaf_limit(options, in.vertices.size() + in.segments.size()));
  return segment_leaf_lower_bound(cdt, clip, limit);
}

}  // namespace

// ==== the size bound's call ends here ============================================================

// ==== a graph begins here ========================================================================

// The centroid of finite triangle t of m, if it lies strictly inside t (exact orient2d; the
// rounded centroid of a sliver can fall on or beyond an edge): a point of t well clear of its
// edges, for a hole seed.
std::optional<Point> inner_centroid(const Mesh& m, TriangleId t) {
  const Triangle& T = m.triangles[t];
  const Point &a = m.points[T.v[0]], &b = m.points[T.v[1]], &c = m.points[T.v[2]];
  const Point g{(a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0};
  if (orient2d(a, b, g) > 0 && orient2d(b, c, g) > 0 && orient2d(c, a, g) > 0) return g;
  return std::nullopt;
}

// A PSLG with segments: its CDT resolves duplicates, vertices on segments and crossings; the
// subsegments of the CDT are the clean segments.
CleanInput clean_graph(const Pslg& pslg, const QuadtreeOptions& options, QuadtreeStats& stats) {
  ConstrainOptions constrain;
  constrain.strict = options.strict;
  constrain.convex_hull = options.convex_hull;
  Mesh cdt = constrained_delaunay(pslg, constrain, &stats.input);
  CleanInput in;
  in.domain_area = cdt.domain_area();
  in.vertices_only.points = cdt.points;
  in.vertices_only.vertex_kind = cdt.vertex_kind;
  in.vertices_only.vertex_marker = cdt.vertex_marker;
  in.vertices_only.duplicates = cdt.duplicates;
  in.vertices_only.input_vertex_count = cdt.input_vertex_count;
  for (VertexId v = 0; v < cdt.points.size(); ++v) {
    if (cdt.vertex_kind[v] != VertexKind::kDuplicate) in.vertices.push_back(v);
  }
  std::vector<std::pair<std::uint64_t, std::int32_t>> seen;
  std::vector<std::pair<VertexId, VertexId>> hull;
  for (TriangleId t = 0; t < cdt.triangles.size(); ++t) {
    if (cdt.is_dead(t)) continue;
    if (cdt.is_ghost(t)) {
      const Triangle& g = cdt.triangles[t];
      unsigned k = 0;
      while (g.v[k] != kInfinite) ++k;
      hull.emplace_back(g.v[next3(k)], g.v[prev3(k)]);
      continue;
    }
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if (!cdt.is_segment(h)) continue;
      const VertexId u = cdt.org(h), w = cdt.dest(h);
      const std::uint64_t key = undirected_key(u, w);
      seen.emplace_back(key, cdt.marker(h));
    }
  }
  // The holes are carved from the faces the CDT carved them from. A seed is a point of a face of
  // the segments' arrangement, but the clean segments are pieces between rounded crossing points,
  // and a seed on (or within rounding of) an input segment's line can lie on a piece in one mesh
  // and beside it in another: a seed exactly on such a line was beside the CDT's piece, and so
  // carved a face there, while the quadtree put a corner exactly on the line at the seed, which
  // made its carve ignore it (fuzz input; the domains then differed). So each seed the CDT
  // carved from is replaced by the centroid of its CDT triangle, a point well inside the same
  // face; the seeds the CDT ignored (on a segment or vertex, outside the hull, out of range) are
  // dropped — the CDT has warned about them.
  for (const Point& p : pslg.holes) {
    if (!in_supported_range(p)) continue;
    const Location loc = cdt.locate(p);
    if (loc.kind == Location::Kind::kOnVertex ||
        (loc.kind == Location::Kind::kOnEdge && cdt.is_segment(loc.handle))) {
      continue;
    }
    TriangleId t = loc.handle >> 2;
    if (cdt.is_ghost(t)) {
      if (loc.kind != Location::Kind::kOnEdge || cdt.is_ghost(cdt.sym(loc.handle) >> 2)) continue;
      t = cdt.sym(loc.handle) >> 2;  // on a hull edge: the triangle inside (as carve() takes it)
    }
    in.hole_seeds.push_back(inner_centroid(cdt, t).value_or(p));
  }
  std::sort(seen.begin(), seen.end());
  for (std::size_t i = 0; i < seen.size(); ++i) {
    if (i > 0 && seen[i].first == seen[i - 1].first) continue;
    in.segments.push_back({static_cast<VertexId>(seen[i].first >> 32),
                           static_cast<VertexId>(seen[i].first & 0xFFFFFFFFu), seen[i].second, false});
  }
  // The domain is the convex hull when asked or when no segment survived (all of zero length).
  if (options.convex_hull || in.segments.empty()) {
    for (const auto& [a, b] : hull) {
      const std::uint64_t key = undirected_key(a, b);
      const auto it = std::lower_bound(seen.begin(), seen.end(), std::make_pair(key, std::int32_t{0}),
                                       [](const auto& x, const auto& y) { return x.first < y.first; });
      if (it != seen.end() && it->first == key) continue;
      in.segments.push_back({a, b, 1, true});
    }
  }
  in.leaf_lower_bound = leaf_bound(cdt, cdt.points, in, options);
  // Under a time budget the CDT is kept: it is the fallback a route out of time returns, which
  // then costs no second CDT past the budget.
  if (options.deadline != Clock::time_point::max()) in.cdt_for_fallback = std::move(cdt);
  return in;
}

// ==== a graph ends here ==========================================================================

// ==== a point set begins here ========================================================================

namespace {

// A point with its index, sorted by (x, y, index): the keys are sorted with their coordinates
// copied beside them (an index sort reading p[a] in its comparisons missed the cache twice per
// comparison).
struct PointKey {
  double x, y;
  VertexId id;
};

// The refusals of delaunay(): too many points, a coordinate out of range, fewer than three.
void refuse_bad_point_set(const Pslg& pslg) {
  const std::size_t n = pslg.points.size();
  if (n >= std::numeric_limits<std::uint32_t>::max() / 4) {
    throw InputError(pslg.source, 0, "too many points (" + std::to_string(n) + ")");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!in_supported_range(pslg.points[i])) {
      throw InputError(pslg.source, 0,
                       "point " + std::to_string(i + static_cast<std::size_t>(pslg.first_index)) +
                           " has a coordinate outside the supported range (0 or magnitude in "
                           "[1e-50, 1e50])");
    }
  }
  if (n < 3) throw InputError(pslg.source, 0, "fewer than three points (" + std::to_string(n) + ")");
}

// The points sorted by (x, y, index). The two halves are sorted on two threads (large inputs) and
// merged: the order is total, so the result is the same as one sort.
std::vector<PointKey> sorted_points(const std::vector<Point>& p, const QuadtreeOptions& options) {
  const std::size_t n = p.size();
  std::vector<PointKey> keyed(n);
  for (std::size_t i = 0; i < n; ++i) keyed[i] = {p[i].x, p[i].y, static_cast<VertexId>(i)};
  const auto before = [](const PointKey& a, const PointKey& b) {
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.id < b.id;
  };
  const std::size_t half = n / 2;
  support::parallel_ranges(n >= threads_from(options, 65536) ? 2 : 1, 2,
                           [&](std::size_t, std::size_t begin, std::size_t end) {
                  for (std::size_t part = begin; part < end; ++part) {
                    std::sort(keyed.begin() + static_cast<std::ptrdiff_t>(part == 0 ? 0 : half),
                              part == 0 ? keyed.begin() + static_cast<std::ptrdiff_t>(half) : keyed.end(), before);
                  }
                });
  std::inplace_merge(keyed.begin(), keyed.begin() + static_cast<std::ptrdiff_t>(half), keyed.end(), before);
  return keyed;
}

// The distinct points, sorted by (x, y), with their points in the same order (read in sequence
// below); the others are marked as duplicates in m.
struct DistinctPoints {
  std::vector<VertexId> ids;
  std::vector<Point> points;
};
// The distinct points of the sorted keys; the others become duplicates in m.
DistinctPoints drop_duplicates(const std::vector<PointKey>& keyed, Mesh& m) {
  DistinctPoints unique;
  unique.ids.reserve(keyed.size());
  unique.points.reserve(keyed.size());
  for (const PointKey& key : keyed) {
    const VertexId v = key.id;
    const Point q{key.x, key.y};
    if (!unique.ids.empty() && unique.points.back() == q) {
      m.vertex_kind[v] = VertexKind::kDuplicate;
      m.duplicates.emplace_back(v, unique.ids.back());
      continue;
    }
    unique.ids.push_back(v);
    unique.points.push_back(q);
  }
  std::sort(m.duplicates.begin(), m.duplicates.end());
  return unique;
}

// The strict hull (collinear points popped), counter-clockwise: the lower chain left to right,
// then the upper chain right to left; lower_edges is the number of lower-chain edges.
struct Hull {
  std::vector<VertexId> vertices;
  std::size_t lower_edges = 0;
};
// Andrew's monotone chain over the distinct points (exact orient2d).
Hull strict_hull(const Pslg& pslg, const DistinctPoints& unique) {
  const std::vector<Point>& p = pslg.points;
  auto chain = [&](bool lower) {
    std::vector<VertexId> h;
    for (std::size_t k = 0; k < unique.ids.size(); ++k) {
      const std::size_t r = lower ? k : unique.ids.size() - 1 - k;
      const VertexId v = unique.ids[r];
      while (h.size() >= 2 && orient2d(p[h[h.size() - 2]], p[h.back()], unique.points[r]) <= 0) h.pop_back();
      h.push_back(v);
    }
    return h;
  };
  const std::vector<VertexId> lower = chain(true), upper = chain(false);
  if (lower.size() + upper.size() < 5) throw InputError(pslg.source, 0, "all points are collinear");
  Hull hull;
  hull.vertices.assign(lower.begin(), lower.end() - 1);
  hull.vertices.insert(hull.vertices.end(), upper.begin(), upper.end() - 1);
  hull.lower_edges = lower.size() - 1;
  return hull;
}

// The input points lying on each hull edge (the hull edges are the domain boundary, and a feature
// segment must not contain a vertex). An edge (a, b) of the counter-clockwise hull is found for a
// point by walking the x-monotone chains with the points (visited in increasing x); vertical
// edges only occur at the two extreme x.
std::vector<std::vector<VertexId>> points_on_hull_edges(const std::vector<Point>& p, const DistinctPoints& unique,
                                                        const Hull& hull_chains) {
  const std::vector<VertexId>& hull = hull_chains.vertices;
  std::vector<std::vector<VertexId>> on_edge(hull.size());
  std::vector<char> is_hull(p.size(), 0);
  for (VertexId v : hull) is_hull[v] = 1;
  const std::size_t lower_edges = hull_chains.lower_edges;
  // The vertical hull edges: at most two, at the smallest and the largest x (found once: a scan of
  // the hull per point would be quadratic when many points lie on it).
  std::vector<std::size_t> vertical;
  for (std::size_t e = 0; e < hull.size(); ++e) {
    if (p[hull[e]].x == p[hull[(e + 1) % hull.size()]].x) vertical.push_back(e);
  }
  auto between = [&](const Point& a, const Point& b, const Point& x) {
    // x is collinear with a and b: strictly between them along the dominant axis (exact).
    if (a.x != b.x) return (a.x < x.x && x.x < b.x) || (b.x < x.x && x.x < a.x);
    return (a.y < x.y && x.y < b.y) || (b.y < x.y && x.y < a.y);
  };
  // The edge candidates move monotonically: the points are visited in increasing x, the lower
  // chain's right ends have increasing x and the upper chain's decreasing x.
  const std::size_t h = hull.size();
  const auto right_x = [&](std::size_t e) { return p[hull[e + 1 == h ? 0 : e + 1]].x; };
  std::size_t lower_at = 0;  // first lower-chain edge whose right end has x ≥ x.x
  std::size_t upper_at = h;  // first upper-chain edge whose right end has x ≤ x.x
  for (std::size_t r = 0; r < unique.ids.size(); ++r) {
    const VertexId v = unique.ids[r];
    const Point& x = unique.points[r];
    while (lower_at < lower_edges && right_x(lower_at) < x.x) ++lower_at;
    while (upper_at > lower_edges && right_x(upper_at - 1) <= x.x) --upper_at;
    if (is_hull[v]) continue;
    // Candidate edges: the lower-chain and upper-chain edges spanning x.x, and the vertical edges
    // at the extreme x.
    auto test = [&](std::size_t e) {
      const Point& a = p[hull[e]];
      const Point& b = p[hull[e + 1 == h ? 0 : e + 1]];
      if (orient2d(a, b, x) == 0 && between(a, b, x)) {
        on_edge[e].push_back(v);
        return true;
      }
      return false;
    };
    if (lower_at < lower_edges && test(lower_at)) continue;
    if (lower_at + 1 < lower_edges && test(lower_at + 1)) continue;
    if (upper_at < h && test(upper_at)) continue;
    if (upper_at + 1 < h && test(upper_at + 1)) continue;
    // Vertical edges at the extreme x (both ends share x).
    for (const std::size_t e : vertical) {
      if (p[hull[e]].x == x.x && test(e)) break;
    }
  }
  return on_edge;
}

}  // namespace

// The size bound of a point set, along its hull edges (the segments of the clean input): from the
// CDT of the hull polygon alone (its vertices and the points on its edges), whose witnesses — hull
// vertices and hull edges — are features of the input; the interior points, left out, could only
// raise the bound (size_bound.cpp: every feature that does not touch a segment is a witness). A
// long thin strip of points, whose hull edges run close, is refused before the tree is built.
// O(h log h) for h points on the hull.
namespace {
double hull_leaf_bound(const CleanInput& in, const QuadtreeOptions& options) {
  const std::vector<Point>& p = in.vertices_only.points;
  Pslg polygon;
  polygon.is_poly = true;
  polygon.points.reserve(in.segments.size());
  for (const FeatureSegment& s : in.segments) polygon.points.push_back(p[s.a]);  // (a closed chain)
  const auto h = static_cast<VertexId>(polygon.points.size());
  for (VertexId k = 0; k < h; ++k) polygon.segments.push_back({k, k + 1 == h ? 0 : k + 1, 1});
  return leaf_bound(constrained_delaunay(polygon, ConstrainOptions{}), p, in, options);
}
}  // namespace

// A point set: duplicates by sorting, the convex hull by Andrew's monotone chain (exact), and the
// input points lying on hull edges inserted into them (the hull edges are the domain boundary, and
// a feature segment must not contain a vertex). O(n log n); the Delaunay triangulation of the CDT
// route would cost more than the whole quadtree for a million points. The refusals match delaunay().
CleanInput clean_point_set(const Pslg& pslg, const QuadtreeOptions& options) {
  refuse_bad_point_set(pslg);
  const std::size_t n = pslg.points.size();
  const std::vector<Point>& p = pslg.points;
  std::vector<PointKey> keyed = sorted_points(p, options);
  CleanInput in;
  Mesh& m = in.vertices_only;
  m.points = p;
  m.vertex_kind.assign(n, VertexKind::kInput);
  m.vertex_marker = pslg.point_markers.size() == n ? pslg.point_markers : std::vector<std::int32_t>(n, 0);
  m.input_vertex_count = static_cast<std::uint32_t>(n);
  const DistinctPoints unique = drop_duplicates(keyed, m);
  std::vector<PointKey>().swap(keyed);
  if (unique.ids.size() == 1) {
    throw InputError(pslg.source, 0, "fewer than three distinct points (all points coincide)");
  }
  if (unique.ids.size() == 2) throw InputError(pslg.source, 0, "fewer than three distinct points");
  const Hull hull_chains = strict_hull(pslg, unique);
  const std::vector<VertexId>& hull = hull_chains.vertices;
  for (std::size_t e = 1; e + 1 < hull.size(); ++e) {  // (a fan from the first hull vertex)
    in.domain_area += signed_area(p[hull[0]], p[hull[e]], p[hull[e + 1]]);
  }
  std::vector<std::vector<VertexId>> on_edge = points_on_hull_edges(p, unique, hull_chains);
  for (std::size_t e = 0; e < hull.size(); ++e) {
    const Point a = p[hull[e]];
    auto& list = on_edge[e];
    std::sort(list.begin(), list.end(), [&](VertexId u, VertexId w) {
      return std::fabs(p[u].x - a.x) + std::fabs(p[u].y - a.y) < std::fabs(p[w].x - a.x) + std::fabs(p[w].y - a.y);
    });
    VertexId from = hull[e];
    for (VertexId v : list) {
      in.segments.push_back({from, v, 1, true});
      from = v;
    }
    in.segments.push_back({from, hull[(e + 1) % hull.size()], 1, true});
  }
  // The distinct vertices in index order (every index but the duplicates; no sort needed).
  in.vertices.clear();
  in.vertices.reserve(unique.ids.size());
  for (VertexId v = 0; v < n; ++v) {
    if (m.vertex_kind[v] != VertexKind::kDuplicate) in.vertices.push_back(v);
  }
  in.leaf_lower_bound = hull_leaf_bound(in, options);
  return in;
}

// ==== a point set ends here ==========================================================================

}  // namespace mwst::qtr
