// Greedy weight-reducing edge flips (the EFH of Boyacı, Erten and Üngör, "Triangulations Loosing
// Bundles and Weight"). In a strictly convex quadrilateral a d b c with diagonal ab, flipping to
// cd lowers the weight by |ab| − |cd| when |cd| < |ab|. We always take the flip with the largest
// relative gain |ab|/|cd| first (a lazy max-heap: entries are re-checked when popped), and decide
// "strictly shorter" with an exact comparison of squared lengths, so near-ties can never flip back
// and forth. Each flip strictly lowers the weight, hence termination; the result is a locally
// minimal triangulation in the sense of the MWT literature (not the minimum weight triangulation).
#include "mwst/algorithms/flip.hpp"

#include <chrono>
#include <cmath>
#include <queue>
#include <vector>

#include "mwst/algorithms/metrics.hpp"

namespace mwst {

namespace {

// The quadrilateral of edge h = a→b with apex c and far apex d, if flippable at all.
bool flippable(const Mesh& m, Handle h) {
  if (m.is_segment(h)) return false;
  const TriangleId t = h >> 2;
  const Handle s = m.sym(h);
  if (!m.in_domain(t) || !m.in_domain(s >> 2)) return false;
  const Point& a = m.points[m.org(h)];
  const Point& b = m.points[m.dest(h)];
  const Point& c = m.points[m.apex(h)];
  const Point& d = m.points[m.apex(s)];
  // Strictly convex: both new triangles (c, a, d) and (d, b, c) are counter-clockwise.
  if (!(orient2d(c, a, d) > 0 && orient2d(d, b, c) > 0)) return false;
  // The new triangles must not have a straight corner at a Steiner point on a segment (at a
  // crossing point the two sides would belong to different segments; refusing there only forgoes
  // a flip).
  return !is_straight_corner(m, m.org(h), m.is_segment(Mesh::lprev(h)), m.is_segment(Mesh::lnext(s))) &&
         !is_straight_corner(m, m.dest(h), m.is_segment(Mesh::lnext(h)), m.is_segment(Mesh::lprev(s)));
}

struct Candidate {
  double ratio;  // |ab| / |cd|, > 1 for an improving flip
  Handle edge;
  bool operator<(const Candidate& o) const {
    // Max-heap on the ratio; ties by handle for determinism.
    return ratio < o.ratio || (ratio == o.ratio && edge > o.edge);
  }
};

double gain_ratio(const Mesh& m, Handle h) {
  const Point& a = m.points[m.org(h)];
  const Point& b = m.points[m.dest(h)];
  const Point& c = m.points[m.apex(h)];
  const Point& d = m.points[m.apex(m.sym(h))];
  return std::sqrt(squared_distance(a, b) / squared_distance(c, d));
}

}  // namespace

bool is_weight_reducing_flip(const Mesh& m, Handle h, double max_area) {
  if (!flippable(m, h)) return false;
  const Point& a = m.points[m.org(h)];
  const Point& b = m.points[m.dest(h)];
  const Point& c = m.points[m.apex(h)];
  const Point& d = m.points[m.apex(m.sym(h))];
  if (compare_squared_lengths(c, d, a, b) >= 0) return false;
  // The new triangles (c, a, d) and (d, b, c) under the area bound.
  return !(max_area > 0.0) || (triangle_area(c, a, d) <= max_area && triangle_area(d, b, c) <= max_area);
}

std::size_t count_weight_reducing_flips(const Mesh& m, double max_area) {
  std::size_t count = 0;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (!m.in_domain(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if ((m.sym(h) >> 2) < t) continue;  // each edge once
      if (is_weight_reducing_flip(m, h, max_area)) ++count;
    }
  }
  return count;
}

FlipStats flip_to_local_minimum(Mesh& m, double max_area) {
  return flip_to_local_minimum(m, max_area, std::chrono::steady_clock::time_point::max());
}

FlipStats flip_to_local_minimum(Mesh& m, double max_area, std::chrono::steady_clock::time_point deadline) {
  const bool timed = deadline != std::chrono::steady_clock::time_point::max();
  std::size_t pops = 0;
  const auto t0 = std::chrono::steady_clock::now();
  FlipStats stats;
  if (timed && std::chrono::steady_clock::now() >= deadline) {
    // (Not even the scan of every edge: on a million triangles it takes a second.)
    stats.out_of_time = true;
    return stats;
  }
  stats.weight_before = measure(m).weight_total;
  std::vector<Candidate> storage;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (!m.in_domain(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if ((m.sym(h) >> 2) < t) continue;
      if (is_weight_reducing_flip(m, h, max_area)) storage.push_back({gain_ratio(m, h), h});
    }
  }
  std::priority_queue<Candidate> heap(std::less<Candidate>(), std::move(storage));
  while (!heap.empty()) {
    // (The clock every 1024 entries: a flip and its four pushes take about a microsecond.)
    if (timed && (++pops & 1023u) == 0 && std::chrono::steady_clock::now() >= deadline) {
      stats.out_of_time = true;
      break;
    }
    const Candidate top = heap.top();
    heap.pop();
    // The entry may be stale: the edge may have changed since it was pushed.
    if (!is_weight_reducing_flip(m, top.edge, max_area)) continue;
    const double ratio = gain_ratio(m, top.edge);
    if (ratio != top.ratio) {
      heap.push({ratio, top.edge});
      continue;
    }
    const Handle diag = m.flip(top.edge);
    ++stats.flips;
    const Handle other = m.sym(diag);
    for (const Handle h : {Mesh::lnext(diag), Mesh::lprev(diag), Mesh::lnext(other), Mesh::lprev(other)}) {
      if (is_weight_reducing_flip(m, h, max_area)) heap.push({gain_ratio(m, h), h});
    }
  }
  stats.weight_after = measure(m).weight_total;
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

bool is_straight_corner(const Mesh& mesh, VertexId v, bool side1_is_segment, bool side2_is_segment) {
  return side1_is_segment && side2_is_segment && v < mesh.vertex_kind.size() &&
         mesh.vertex_kind[v] == VertexKind::kSteinerOnSegment;
}

}  // namespace mwst
