// algorithms/quadtree/size_bound.cpp — before the tree is built: a lower bound on the number of
// leaves it will have, from the input's CDT, so that an input whose tree is far beyond the leaf
// limit falls back at once instead of after building the tree up to the limit.
//
// BEG's tree has Θ(∫ dA / lfs²) leaves (Bern, Eppstein, Gilbert 1994; Ruppert 1995 for the
// integral), unbounded in the number of features: nearly parallel segments that do not touch (the
// spikes of a narrow fan, a long thin strip) need leaves about as small as their distance along all
// their length. The route refused such a tree at the leaf limit (1024 per feature), but only after
// building it to there: a fan of 5,000 spikes took 23 s of CPU and 2.2 GB to fall back to its CDT
// of 10,000 triangles. The bound below is the one-dimensional part of the integral, along the segments:
//
//   Leaf C of size s meeting segment e at x, with its extended cell B(C) simple (every leaf is,
//   unless it is at the deepest level): B(C) is C grown by s for segments and by s/2 for vertices,
//   so a segment g that does not touch e lies farther than s from x in the maximum norm, and a
//   vertex g farther than s/2 (else g would be in C's list beside e); the distance d_g(x) is at
//   least that. The piece e ∩ C is at most s / f_e long, f_e = max(|cos|, |sin|) of e's
//   direction; so ∫ over e ∩ C of dℓ / d_g is below 1 / f_e (2 / f_e for a vertex g), and at
//   least f_e ∫_e dℓ / d_g leaves meet e (half that for a vertex g).
//   A simple B(C) meets no two segments that share no endpoint, so the segments C meets have a
//   common endpoint v; weighting e = (a, b) by w_e = 1 / max(deg a, deg b) (a fractional
//   matching: the weights at any vertex sum to at most 1) counts every leaf at most once:
//     leaves ≥ Σ_e w_e f_e max_g k_g ∫_e dℓ / max(d_g, c),  k_g = 1 for a segment, 1/2 for a vertex.
//   The clip c ≥ s_min covers leaves at the deepest level (size s_min), which need not be simple:
//   their pieces add at most 1 / f_e each as well. (A deepest-level leaf that meets several
//   segments without a common endpoint is counted once per segment; such a tree has leaves that see
//   the input non-simply and falls back in any case, there with the quadtree's free corners.)
//   On fans, strips, coastlines and the data sets the bound is 5 to 20 times below the leaves
//   that meet segments (tests/algorithms/quadtree/test_quadtree_size.cpp).
//
// The witnesses g of e are the features next to it in the CDT: the apex c of each triangle on e
// and the segments at c found by turning around c (a few edges each way). d_g is convex along e
// (the distance to a convex set), so on a piece of e it is at most its larger end value: the
// integral is bounded below by cutting e into pieces until that is within 3/2 of the piece's
// distance to g, which takes O(log(d_max / d_min)) pieces. Only the witnesses whose integral can
// beat the best so far (e's length over their least distance) are cut, and the sum stops once it
// passes the leaf limit: what the route needs to know is only whether it does.
#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "algorithms/quadtree/route.hpp"

namespace mwst::qtr {

namespace {

// A witness: the segment a–b, or the vertex a (is_vertex; b is a copy of a).
struct Witness {
  Point a, b;
  bool is_vertex;
};

double point_distance(const Point& x, const Witness& g) {
  if (g.is_vertex) return distance(x, g.a);
  const double dx = g.b.x - g.a.x, dy = g.b.y - g.a.y;
  const double len2 = dx * dx + dy * dy;
  double t = len2 > 0.0 ? ((x.x - g.a.x) * dx + (x.y - g.a.y) * dy) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return distance(x, Point{g.a.x + t * dx, g.a.y + t * dy});
}

// A lower bound on the distance between the piece p–q and g (they do not meet: clean features that
// do not touch are disjoint): the least of the four end-to-other distances, less rounding.
double piece_distance(const Point& p, const Point& q, const Witness& g) {
  const Witness piece{p, q, false};
  double d = std::min(point_distance(p, g), point_distance(q, g));
  d = std::min(d, point_distance(g.a, piece));
  if (!g.is_vertex) d = std::min(d, point_distance(g.b, piece));
  return d * (1.0 - 1e-9);
}

// The rounding slack for distances among points of magnitude up to `scale`: every distance above is
// computed from rounded points, so the distance used as an upper bound is raised by this.
double slack(double scale) { return 64.0 * DBL_EPSILON * scale; }

// A lower bound on ∫ over e = (p, q) of dℓ / max(d_g, clip), by bisection (see the file's head).
double integral_lower_bound(const Point& p, const Point& q, const Witness& g, double clip, double scale) {
  struct Piece {
    double t0, t1, d0, d1;
    int depth;
  };
  const double length = distance(p, q);
  const auto at = [&](double t) { return Point{p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)}; };
  const auto upper = [&](const Point& x) { return std::max(point_distance(x, g) * (1.0 + 1e-9) + slack(scale), clip); };
  // (At most kMaxSplits splits per call: where the rounding slack is as large as the distances —
  // features a few units apart at coordinates of 1e15 — far never comes within 3/2 of near, and
  // the bisection to depth 60 would visit 2^60 pieces. Every piece counted as it stands is a lower
  // bound on its part of the integral.)
  constexpr std::size_t kMaxSplits = 4096;
  std::size_t splits = 0;
  std::array<Piece, 128> stack;
  std::size_t top = 0;
  stack[top++] = {0.0, 1.0, upper(p), upper(q), 0};
  double sum = 0.0;
  while (top > 0) {
    const Piece piece = stack[--top];
    const double far = std::max(piece.d0, piece.d1);
    const double near = std::max(piece_distance(at(piece.t0), at(piece.t1), g), clip);
    if (far <= 1.5 * near || piece.depth >= 60 || top + 2 > stack.size() || splits >= kMaxSplits) {
      sum += length * (piece.t1 - piece.t0) / far;
      continue;
    }
    ++splits;
    const double tm = 0.5 * (piece.t0 + piece.t1), dm = upper(at(tm));
    stack[top++] = {piece.t0, tm, piece.d0, dm, piece.depth + 1};
    stack[top++] = {tm, piece.t1, dm, piece.d1, piece.depth + 1};
  }
  return sum;
}

// The witnesses of segment h = (a, b) on the side of its triangle h >> 2 (none on a ghost): the
// apex c, and the segments at c that do not touch (a, b), turning up to kTurns edges each way
// around c from the triangle.
void side_witnesses(const Mesh& cdt, Handle h, std::vector<Witness>& out) {
  constexpr int kTurns = 6;
  if (cdt.is_ghost(h >> 2)) return;
  const VertexId a = cdt.org(h), b = cdt.dest(h), c = cdt.apex(h);
  out.push_back({cdt.points[c], cdt.points[c], true});
  const Handle from_c = make_handle(h >> 2, prev3(h & 3));  // c → a
  const auto consider = [&](Handle e) {
    const VertexId x = cdt.dest(e);
    if (x == kInfinite || x == a || x == b || !cdt.is_segment(e)) return;
    out.push_back({cdt.points[c], cdt.points[x], false});
  };
  Handle e = from_c;
  for (int k = 0; k < kTurns; ++k) {  // counter-clockwise around c, away from the triangle
    e = cdt.onext(e);
    if (e == kNone || cdt.org(e) != c || cdt.dest(e) == kInfinite) break;
    consider(e);
  }
  e = from_c;
  for (int k = 0; k < kTurns; ++k) {  // clockwise: c → b, then on
    e = cdt.oprev(e);
    if (e == kNone || cdt.org(e) != c || cdt.dest(e) == kInfinite) break;
    consider(e);
  }
}

}  // namespace

double segment_leaf_lower_bound(const Mesh& cdt, double clip, double stop_above) {
  // Segments and their degrees (each segment is seen from both its triangles: counted once, from
  // the side where org < dest, with both sides' witnesses).
  std::vector<std::uint32_t> degree(cdt.points.size(), 0);
  for (TriangleId t = 0; t < cdt.triangles.size(); ++t) {
    if (cdt.is_dead(t)) continue;
    for (unsigned k = 0; k < 3; ++k) {
      const Handle h = make_handle(t, k);
      if (cdt.is_segment(h) && cdt.org(h) < cdt.dest(h)) {
        ++degree[cdt.org(h)];
        ++degree[cdt.dest(h)];
      }
    }
  }
  double leaves = 0.0;
  std::vector<Witness> witnesses;
  std::vector<std::pair<double, std::uint32_t>> most;  // per witness: the integral's upper bound
  for (TriangleId t = 0; t < cdt.triangles.size() && !(leaves > stop_above); ++t) {
    if (cdt.is_dead(t)) continue;
    for (unsigned k = 0; k < 3; ++k) {
      const Handle h = make_handle(t, k);
      const VertexId a = cdt.org(h), b = cdt.dest(h);
      if (!cdt.is_segment(h) || a > b || a == kInfinite || b == kInfinite) continue;
      witnesses.clear();
      side_witnesses(cdt, h, witnesses);
      side_witnesses(cdt, cdt.sym(h), witnesses);
      const Point &p = cdt.points[a], &q = cdt.points[b];
      const double length = distance(p, q);
      if (witnesses.empty() || !(length > 0.0)) continue;
      const double f = std::max(std::fabs(q.x - p.x), std::fabs(q.y - p.y)) / length;
      const double w = 1.0 / std::max(degree[a], degree[b]);
      // The witnesses by the most their integral can be (the length over their least distance),
      // largest first; the bisection stops at the first that cannot beat the best so far.
      most.clear();
      for (std::uint32_t i = 0; i < witnesses.size(); ++i) {
        const double share = witnesses[i].is_vertex ? 0.5 : 1.0;
        most.emplace_back(share * length / std::max(piece_distance(p, q, witnesses[i]), clip), i);
      }
      std::sort(most.begin(), most.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
      double best = 0.0;
      for (const auto& [upper, i] : most) {
        if (!(upper > best)) break;
        const Witness& g = witnesses[i];
        const double scale = std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(q.x), std::fabs(q.y),
                                       std::fabs(g.a.x), std::fabs(g.a.y), std::fabs(g.b.x), std::fabs(g.b.y)});
        const double share = g.is_vertex ? 0.5 : 1.0;
        best = std::max(best, share * integral_lower_bound(p, q, g, clip, scale));
      }
      leaves += w * f * best;
    }
  }
  return leaves;
}

}  // namespace mwst::qtr
