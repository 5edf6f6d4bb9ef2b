// tests/support/exact_checker.hpp — the independent checker of the tests.
// It never calls mwst's predicates or validate(): it reads only the triangle vertex lists (and the
// subsegment flags for the CDT), and decides every sign with GMP integers. Every double is an odd
// integer times a power of two, so one common shift makes all coordinates of a set integers; the
// determinants are homogeneous, so their signs are the true signs. It checks: every triangle
// counter-clockwise; every distinct point used by exactly one vertex id; edges manifold; the
// boundary edges are exactly the convex hull (Andrew's monotone chain, collinear hull points
// kept); total area = hull area (exact integers); Euler's formula; and by brute force that no
// point lies strictly inside a circumcircle (Delaunay), or, for a CDT, that no point inside a
// circumcircle is visible from the triangle's centroid. Also: segment coverage and domain areas.
#pragma once

#include <gmpxx.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mwst/geometry/geometry.hpp"
#include "mwst/mesh/mesh.hpp"
#include "mwst/mesh/pslg.hpp"
#include "support/mesh_queries.hpp"

namespace mwst::test {

// ---- exact arithmetic --------------------------------------------------------------------------

// The coordinates of a point set as integers: each coordinate times 2^shift, one shift for all.
class ExactPlane {
 public:
  explicit ExactPlane(const std::vector<Point>& pts) {
    long min_exp = 0;
    std::vector<std::pair<long long, long>> xs(pts.size()), ys(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
      xs[i] = decompose(pts[i].x);
      ys[i] = decompose(pts[i].y);
      if (xs[i].first != 0) min_exp = std::min(min_exp, xs[i].second);
      if (ys[i].first != 0) min_exp = std::min(min_exp, ys[i].second);
    }
    shift_ = -min_exp;
    x_.resize(pts.size());
    y_.resize(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
      to_mpz(xs[i], x_[i]);
      to_mpz(ys[i], y_[i]);
    }
  }
  std::size_t size() const { return x_.size(); }
  const mpz_class& x(std::size_t i) const { return x_[i]; }
  const mpz_class& y(std::size_t i) const { return y_[i]; }
  long shift() const { return shift_; }

  // Twice the signed area of (a, b, c) in integer units.
  mpz_class twice_area(std::size_t a, std::size_t b, std::size_t c) const {
    mpz_class r = (x_[b] - x_[a]) * (y_[c] - y_[a]);
    r -= (y_[b] - y_[a]) * (x_[c] - x_[a]);
    return r;
  }
  int orient(std::size_t a, std::size_t b, std::size_t c) const { return sgn(twice_area(a, b, c)); }

  // +1 if d is strictly inside the circle through the counter-clockwise a, b, c.
  int incircle(std::size_t a, std::size_t b, std::size_t c, std::size_t d) const {
    adx_ = x_[a] - x_[d];
    ady_ = y_[a] - y_[d];
    bdx_ = x_[b] - x_[d];
    bdy_ = y_[b] - y_[d];
    cdx_ = x_[c] - x_[d];
    cdy_ = y_[c] - y_[d];
    lift_ = adx_ * adx_ + ady_ * ady_;
    cross_ = bdx_ * cdy_ - cdx_ * bdy_;
    det_ = lift_ * cross_;
    lift_ = bdx_ * bdx_ + bdy_ * bdy_;
    cross_ = cdx_ * ady_ - adx_ * cdy_;
    det_ += lift_ * cross_;
    lift_ = cdx_ * cdx_ + cdy_ * cdy_;
    cross_ = adx_ * bdy_ - bdx_ * ady_;
    det_ += lift_ * cross_;
    return sgn(det_);
  }

  // Sign of (c − a)·(b − a): where c projects along a→b relative to a.
  int dot_sign(std::size_t a, std::size_t b, std::size_t c) const {
    mpz_class r = (x_[c] - x_[a]) * (x_[b] - x_[a]);
    r += (y_[c] - y_[a]) * (y_[b] - y_[a]);
    return sgn(r);
  }
  // Sign of (c − a)·(b − a) − |b − a|²: positive when c projects beyond b.
  int beyond_sign(std::size_t a, std::size_t b, std::size_t c) const {
    mpz_class r = (x_[c] - x_[b]) * (x_[b] - x_[a]);
    r += (y_[c] - y_[b]) * (y_[b] - y_[a]);
    return sgn(r);
  }

 private:
  // v = mantissa · 2^exponent with an odd mantissa (or 0).
  static std::pair<long long, long> decompose(double v) {
    if (v == 0.0) return {0, 0};
    int e = 0;
    const double m = std::frexp(v, &e);
    auto mant = static_cast<long long>(std::ldexp(m, 53));
    long exp = e - 53;
    while ((mant & 1) == 0) {
      mant /= 2;
      ++exp;
    }
    return {mant, exp};
  }
  void to_mpz(const std::pair<long long, long>& d, mpz_class& out) const {
    out = static_cast<long>(d.first);
    if (d.first != 0) mpz_mul_2exp(out.get_mpz_t(), out.get_mpz_t(), static_cast<mp_bitcnt_t>(d.second + shift_));
  }
  std::vector<mpz_class> x_, y_;
  long shift_ = 0;
  mutable mpz_class adx_, ady_, bdx_, bdy_, cdx_, cdy_, lift_, cross_, det_;
};

// ---- the independent checker -------------------------------------------------------------------

struct CheckOptions {
  bool empty_circles = false;  // brute-force Delaunay test (no point strictly inside a circumcircle)
  // Constrained version: a point strictly inside a circumcircle is a violation only if the segment
  // from the triangle's centroid to it meets no constraint (edges given here).
  const std::vector<std::pair<std::uint32_t, std::uint32_t>>* constraints = nullptr;
  std::size_t max_brute_force = 200000;  // skip the circle tests above this many points
};

struct CheckResult {
  std::vector<std::string> problems;
  std::size_t distinct_points = 0;
  std::size_t hull_points = 0;  // on the hull boundary, collinear ones included
  std::size_t circle_tests = 0;  // (triangle, point) pairs decided by the filter or exactly
};

// A check's messages, one per line (for a failed expectation's output).
inline std::string joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + "\n";
  return s;
}

// Convex hull by Andrew's monotone chain over the given (distinct) point ids, exact orientation.
// keep_collinear: points on hull edges are kept as hull vertices. Counter-clockwise, no repeat.
inline std::vector<std::uint32_t> convex_hull(const ExactPlane& ep, const std::vector<Point>& pts,
                                              std::vector<std::uint32_t> ids, bool keep_collinear) {
  std::sort(ids.begin(), ids.end(), [&](std::uint32_t a, std::uint32_t b) {
    return pts[a].x < pts[b].x || (pts[a].x == pts[b].x && pts[a].y < pts[b].y);
  });
  if (ids.size() < 3) return ids;
  std::vector<std::uint32_t> h(2 * ids.size());
  std::size_t k = 0;
  auto bad_turn = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const int o = ep.orient(a, b, c);
    return keep_collinear ? o < 0 : o <= 0;
  };
  for (std::size_t i = 0; i < ids.size(); ++i) {
    while (k >= 2 && bad_turn(h[k - 2], h[k - 1], ids[i])) --k;
    h[k++] = ids[i];
  }
  for (std::size_t i = ids.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && bad_turn(h[k - 2], h[k - 1], ids[i])) --k;
    h[k++] = ids[i];
  }
  h.resize(k - 1);
  return h;
}

// Checks that `tris` triangulates the convex hull of `pts` (see the header comment).
inline CheckResult check_triangulation(const std::vector<Point>& pts, const std::vector<Tri>& tris,
                                       const CheckOptions& options = {}) {
  CheckResult r;
  auto report = [&](const std::string& s) {
    if (r.problems.size() < 30) r.problems.push_back(s);
  };
  const std::size_t n = pts.size();
  const ExactPlane ep(pts);
  // Distinct locations and which ids are used.
  std::vector<char> used(n, 0);
  for (const Tri& t : tris) {
    for (std::uint32_t v : t) {
      if (v >= n) {
        report("a triangle names vertex " + std::to_string(v) + " out of range");
        return r;
      }
      used[v] = 1;
    }
  }
  std::vector<std::uint32_t> order(n);
  for (std::uint32_t i = 0; i < n; ++i) order[i] = i;
  auto less = [&](std::uint32_t a, std::uint32_t b) {
    return pts[a].x < pts[b].x || (pts[a].x == pts[b].x && pts[a].y < pts[b].y);
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<std::uint32_t> representatives;  // the used id of each distinct location
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i;
    std::size_t used_here = 0;
    std::uint32_t rep = order[i];
    while (j < n && pts[order[j]] == pts[order[i]]) {
      if (used[order[j]]) {
        ++used_here;
        rep = order[j];
      }
      ++j;
    }
    if (used_here != 1) {
      report("the point (" + std::to_string(pts[order[i]].x) + ", " + std::to_string(pts[order[i]].y) +
             ") is used by " + std::to_string(used_here) + " vertex ids (expected exactly 1)");
    }
    representatives.push_back(rep);
    i = j;
  }
  r.distinct_points = representatives.size();
  // Orientation and edge manifoldness (directed edges as sorted 64-bit keys).
  std::vector<std::uint64_t> directed;
  directed.reserve(3 * tris.size());
  mpz_class area_sum = 0;
  for (const Tri& t : tris) {
    const int o = ep.orient(t[0], t[1], t[2]);
    if (o <= 0) report("triangle (" + std::to_string(t[0]) + ", " + std::to_string(t[1]) + ", " +
                       std::to_string(t[2]) + ") is not counter-clockwise");
    area_sum += ep.twice_area(t[0], t[1], t[2]);
    for (int e = 0; e < 3; ++e) directed.push_back((std::uint64_t{t[e]} << 32) | t[(e + 1) % 3]);
  }
  std::sort(directed.begin(), directed.end());
  for (std::size_t i = 1; i < directed.size(); ++i) {
    if (directed[i] == directed[i - 1]) {
      report("directed edge " + std::to_string(directed[i] >> 32) + "->" +
             std::to_string(directed[i] & 0xFFFFFFFFu) + " appears in two triangles");
    }
  }
  // Boundary edges: directed edges whose reverse is absent. They must be exactly the hull cycle.
  std::unordered_map<std::uint32_t, std::uint32_t> boundary_next;
  std::size_t edges = 0;
  for (const std::uint64_t e : directed) {
    const auto from = static_cast<std::uint32_t>(e >> 32), to = static_cast<std::uint32_t>(e);
    if (!std::binary_search(directed.begin(), directed.end(), (std::uint64_t{to} << 32) | from)) {
      if (!boundary_next.emplace(from, to).second) {
        report("vertex " + std::to_string(from) + " starts two boundary edges");
      }
      ++edges;
    } else if (from < to) {
      ++edges;
    }
  }
  const std::vector<std::uint32_t> hull = convex_hull(ep, pts, representatives, true);
  r.hull_points = hull.size();
  if (boundary_next.size() != hull.size()) {
    report("the triangulation has " + std::to_string(boundary_next.size()) +
           " boundary edges; the convex hull has " + std::to_string(hull.size()) + " boundary points");
  } else {
    for (std::size_t i = 0; i < hull.size(); ++i) {
      const auto it = boundary_next.find(hull[i]);
      if (it == boundary_next.end() || it->second != hull[(i + 1) % hull.size()]) {
        report("hull edge " + std::to_string(hull[i]) + "->" + std::to_string(hull[(i + 1) % hull.size()]) +
               " is not a boundary edge of the triangulation");
        break;
      }
    }
  }
  mpz_class hull_area = 0;
  for (std::size_t i = 1; i + 1 < hull.size(); ++i) hull_area += ep.twice_area(hull[0], hull[i], hull[i + 1]);
  if (area_sum != hull_area) report("the triangles' area differs from the convex hull's area");
  // Euler: V − E + F = 1 for a triangulated disk (F counts the triangles).
  const std::size_t v_count = representatives.size();
  if (static_cast<long long>(v_count) - static_cast<long long>(edges) + static_cast<long long>(tris.size()) != 1) {
    report("Euler count fails: V=" + std::to_string(v_count) + " E=" + std::to_string(edges) +
           " F=" + std::to_string(tris.size()));
  }
  if (tris.size() != 2 * v_count - hull.size() - 2) {
    report("expected 2n − h − 2 = " + std::to_string(2 * v_count - hull.size() - 2) + " triangles, got " +
           std::to_string(tris.size()));
  }
  // Brute-force empty circumcircles. Points sorted by x; for each triangle the x-range of its
  // circumcircle is found by binary search and the points in it are filtered by a conservative
  // long double distance test (circumcentre relative to a corner, generous margin) before the exact
  // test; ill-conditioned triangles (circumradius above 1e6 times their size) test every point.
  if ((options.empty_circles || options.constraints) && n <= options.max_brute_force) {
    std::vector<std::uint32_t> by_x = representatives, by_y = representatives;
    std::sort(by_x.begin(), by_x.end(), [&](std::uint32_t a, std::uint32_t b) { return pts[a].x < pts[b].x; });
    std::sort(by_y.begin(), by_y.end(), [&](std::uint32_t a, std::uint32_t b) { return pts[a].y < pts[b].y; });
    std::vector<std::uint32_t> candidates;
    for (const Tri& t : tris) {
      const Point &a = pts[t[0]], &b = pts[t[1]], &c = pts[t[2]];
      const long double bx = (long double)b.x - a.x, by = (long double)b.y - a.y;
      const long double cx = (long double)c.x - a.x, cy = (long double)c.y - a.y;
      const long double d = 2 * (bx * cy - by * cx);
      const long double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
      const long double ux = (cy * b2 - by * c2) / d, uy = (bx * c2 - cx * b2) / d;
      const long double radius = std::sqrt(ux * ux + uy * uy);
      const long double diam = std::sqrt(std::max(b2, c2));
      candidates.clear();
      if (std::isfinite((double)radius) && radius < 1e6L * diam) {
        const long double reach = radius + 1e-6L * (radius + diam);
        const long double centre_x = a.x + ux, centre_y = a.y + uy;
        // Scan the slab (x or y, whichever holds fewer points) that contains the circle.
        auto slab = [&](const std::vector<std::uint32_t>& sorted, auto coord, long double lo, long double hi) {
          const auto first = std::lower_bound(sorted.begin(), sorted.end(), lo,
                                              [&](std::uint32_t v, long double x) { return coord(v) < x; });
          const auto last = std::upper_bound(first, sorted.end(), hi,
                                             [&](long double x, std::uint32_t v) { return x < coord(v); });
          return std::make_pair(first, last);
        };
        const auto xs = slab(by_x, [&](std::uint32_t v) { return pts[v].x; }, centre_x - reach, centre_x + reach);
        const auto ys = slab(by_y, [&](std::uint32_t v) { return pts[v].y; }, centre_y - reach, centre_y + reach);
        const auto range = xs.second - xs.first <= ys.second - ys.first ? xs : ys;
        for (auto it = range.first; it != range.second; ++it) {
          ++r.circle_tests;
          const long double dx = pts[*it].x - centre_x, dy = pts[*it].y - centre_y;
          if (dx * dx + dy * dy <= reach * reach) candidates.push_back(*it);
        }
      } else {
        candidates = representatives;
        r.circle_tests += candidates.size();
      }
      for (const std::uint32_t p : candidates) {
        if (p == t[0] || p == t[1] || p == t[2]) continue;
        if (ep.incircle(t[0], t[1], t[2], p) <= 0) continue;
        bool hidden = false;
        if (options.constraints) {
          // Does a constraint meet the closed segment centroid→p (other than at p itself)? In
          // coordinates scaled by 3 the centroid a + b + c is a lattice point. Conservative: any
          // touch or collinear overlap counts as blocking, so only true violations are reported.
          const mpz_class gx = ep.x(t[0]) + ep.x(t[1]) + ep.x(t[2]);
          const mpz_class gy = ep.y(t[0]) + ep.y(t[1]) + ep.y(t[2]);
          const mpz_class px = 3 * ep.x(p), py = 3 * ep.y(p);
          auto orient3 = [](const mpz_class& ax, const mpz_class& ay, const mpz_class& qx,
                            const mpz_class& qy, const mpz_class& rx, const mpz_class& ry) {
            const mpz_class v = (qx - ax) * (ry - ay) - (qy - ay) * (rx - ax);
            return sgn(v);
          };
          for (const auto& [u, w] : *options.constraints) {
            const mpz_class ux3 = 3 * ep.x(u), uy3 = 3 * ep.y(u), wx3 = 3 * ep.x(w), wy3 = 3 * ep.y(w);
            const int o1 = orient3(gx, gy, px, py, ux3, uy3), o2 = orient3(gx, gy, px, py, wx3, wy3);
            if (u == p || w == p) {
              // Incident to p: blocks only if it runs back along the sight line.
              if ((u == p ? o2 : o1) == 0) hidden = true;
            } else {
              const int o3 = orient3(ux3, uy3, wx3, wy3, gx, gy), o4 = orient3(ux3, uy3, wx3, wy3, px, py);
              if (o1 * o2 <= 0 && o3 * o4 <= 0) hidden = true;
            }
            if (hidden) break;
          }
        }
        if (!hidden) {
          report("point " + std::to_string(p) + " lies inside the circumcircle of triangle (" +
                 std::to_string(t[0]) + ", " + std::to_string(t[1]) + ", " + std::to_string(t[2]) + ")" +
                 (options.constraints ? " and is visible from its centroid" : ""));
        }
      }
    }
  }
  return r;
}

// ---- PSLG helpers ------------------------------------------------------------------------------

// The vertex of the mesh at each point of the input (by coordinates; duplicates map to the vertex
// that is used). kNone where no live finite triangle uses a vertex at that location.
inline std::vector<std::uint32_t> vertex_at_input_points(const Mesh& m, const std::vector<Point>& input) {
  std::map<std::pair<double, double>, std::uint32_t> at;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (m.is_dead(t)) continue;
    for (VertexId v : m.triangles[t].v) {
      if (v != kInfinite) at[{m.points[v].x, m.points[v].y}] = v;
    }
  }
  std::vector<std::uint32_t> out(input.size(), kNone);
  for (std::size_t i = 0; i < input.size(); ++i) {
    const auto it = at.find({input[i].x, input[i].y});
    if (it != at.end()) out[i] = it->second;
  }
  return out;
}

// Checks that every input segment (non-degenerate) is covered by a chain of subsegments from the
// vertex at its first end to the vertex at its second whose vertices advance along it and lie on it:
// exactly (rel_tol == 0) or within rel_tol·|ab| of its line (crossing points are rounded). Also
// checks that every subsegment lies on some input segment in the same sense.
inline std::vector<std::string> check_segments_covered(const Mesh& m, const Pslg& pslg, double rel_tol) {
  std::vector<std::string> problems;
  const std::vector<std::uint32_t> at = vertex_at_input_points(m, pslg.points);
  const auto subs = subsegments(m);
  std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> adj;
  for (const auto& [u, w] : subs) {
    adj[u].push_back(w);
    adj[w].push_back(u);
  }
  // Points of the mesh plus the input points, for exact tests.
  std::vector<Point> all = m.points;
  const std::size_t base = all.size();
  all.insert(all.end(), pslg.points.begin(), pslg.points.end());
  const ExactPlane ep(all);
  // True if mesh vertex v lies on input segment (a, b) (input indices).
  auto on_segment = [&](std::uint32_t v, std::uint32_t sa, std::uint32_t sb) {
    if (rel_tol == 0.0) {
      return ep.orient(base + sa, base + sb, v) == 0 && ep.dot_sign(base + sa, base + sb, v) >= 0 &&
             ep.beyond_sign(base + sa, base + sb, v) <= 0;
    }
    const Point &a = pslg.points[sa], &b = pslg.points[sb], &p = m.points[v];
    const long double dx = (long double)b.x - a.x, dy = (long double)b.y - a.y;
    const long double len = std::sqrt(dx * dx + dy * dy);
    const long double px = (long double)p.x - a.x, py = (long double)p.y - a.y;
    const long double dist = std::fabs(px * dy - py * dx) / len;
    const long double t = (px * dx + py * dy) / (len * len);
    const long double tol = rel_tol * len;
    return dist <= tol && t >= -rel_tol && t <= 1 + rel_tol;
  };
  auto param = [&](std::uint32_t v, std::uint32_t sa, std::uint32_t sb) {
    const Point &a = pslg.points[sa], &b = pslg.points[sb], &p = m.points[v];
    const long double dx = (long double)b.x - a.x, dy = (long double)b.y - a.y;
    return ((p.x - (long double)a.x) * dx + (p.y - (long double)a.y) * dy) / (dx * dx + dy * dy);
  };
  std::set<std::pair<std::uint32_t, std::uint32_t>> covered;
  for (std::size_t i = 0; i < pslg.segments.size(); ++i) {
    const Segment& s = pslg.segments[i];
    if (pslg.points[s.a] == pslg.points[s.b]) continue;  // zero length: dropped
    const std::uint32_t from = at[s.a], to = at[s.b];
    if (from == kNone || to == kNone) {
      problems.push_back("segment " + std::to_string(i) + ": an endpoint is not a mesh vertex");
      continue;
    }
    // Depth-first search along subsegments that stay on ab and advance towards b.
    std::vector<std::uint32_t> stack{from};
    std::map<std::uint32_t, std::uint32_t> parent{{from, from}};
    bool found = false;
    while (!stack.empty() && !found) {
      const std::uint32_t v = stack.back();
      stack.pop_back();
      const long double tv = param(v, s.a, s.b);
      for (std::uint32_t w : adj[v]) {
        if (parent.count(w) || !on_segment(w, s.a, s.b) || !(param(w, s.a, s.b) > tv)) continue;
        parent[w] = v;
        if (w == to) {
          found = true;
          break;
        }
        stack.push_back(w);
      }
    }
    if (!found) {
      problems.push_back("segment " + std::to_string(i) + " (" + std::to_string(s.a) + ", " +
                         std::to_string(s.b) + ") is not covered by a chain of subsegments");
      continue;
    }
    for (std::uint32_t v = to; v != from; v = parent[v]) {
      covered.insert({std::min(v, parent[v]), std::max(v, parent[v])});
    }
  }
  // Every subsegment lies on an input segment: on the chain found above, or else (rounded crossing
  // points can leave two near-coincident chains) on some input segment geometrically.
  for (const auto& e : subs) {
    if (covered.count(e)) continue;
    bool on_some = false;
    for (std::size_t i = 0; i < pslg.segments.size() && !on_some; ++i) {
      const Segment& s = pslg.segments[i];
      on_some = !(pslg.points[s.a] == pslg.points[s.b]) && on_segment(e.first, s.a, s.b) &&
                on_segment(e.second, s.a, s.b);
    }
    if (!on_some) {
      problems.push_back("subsegment " + std::to_string(e.first) + "-" + std::to_string(e.second) +
                         " lies on no input segment");
      if (problems.size() > 30) break;
    }
  }
  return problems;
}

// Area enclosed by the segments of a PSLG whose segments form disjoint closed rings, computed from
// the input only: each ring's shoelace area, signed by its nesting depth (even-depth rings add,
// odd-depth rings — holes — subtract; depth by ray casting a vertex of the ring against the others).
// NaN if some vertex does not have exactly two segments.
inline long double ring_domain_area(const Pslg& pslg, std::size_t* ring_count = nullptr) {
  // Merge duplicate points by coordinates.
  std::map<std::pair<double, double>, std::uint32_t> id_of;
  std::vector<Point> pts;
  auto id = [&](std::uint32_t i) {
    const auto [it, fresh] = id_of.emplace(std::make_pair(pslg.points[i].x, pslg.points[i].y),
                                           static_cast<std::uint32_t>(pts.size()));
    if (fresh) pts.push_back(pslg.points[i]);
    return it->second;
  };
  std::map<std::uint32_t, std::vector<std::uint32_t>> adj;
  for (const Segment& s : pslg.segments) {
    const std::uint32_t a = id(s.a), b = id(s.b);
    if (a == b) continue;
    adj[a].push_back(b);
    adj[b].push_back(a);
  }
  // Walk the rings: every vertex of a ring graph has exactly two segments.
  std::vector<std::vector<std::uint32_t>> rings;
  std::set<std::uint32_t> visited;
  for (const auto& [start, nbrs] : adj) {
    if (visited.count(start)) continue;
    if (nbrs.size() != 2) return std::numeric_limits<long double>::quiet_NaN();
    std::vector<std::uint32_t> ring{start};
    visited.insert(start);
    std::uint32_t prev = start, cur = nbrs[0];
    while (cur != start) {
      const auto& nc = adj[cur];
      if (nc.size() != 2 || visited.count(cur)) return std::numeric_limits<long double>::quiet_NaN();
      ring.push_back(cur);
      visited.insert(cur);
      const std::uint32_t next = nc[0] == prev ? nc[1] : nc[0];
      prev = cur;
      cur = next;
    }
    rings.push_back(std::move(ring));
  }
  auto shoelace = [&](const std::vector<std::uint32_t>& r) {
    long double s = 0;
    for (std::size_t k = 0; k < r.size(); ++k) {
      const Point &p = pts[r[k]], &q = pts[r[(k + 1) % r.size()]];
      s += (long double)p.x * q.y - (long double)q.x * p.y;
    }
    return s / 2;
  };
  auto inside = [&](const Point& p, const std::vector<std::uint32_t>& r) {
    bool in = false;
    for (std::size_t k = 0, j = r.size() - 1; k < r.size(); j = k++) {
      const Point &a = pts[r[k]], &b = pts[r[j]];
      if ((a.y > p.y) != (b.y > p.y) &&
          p.x < (long double)(b.x - a.x) * (p.y - a.y) / ((long double)b.y - a.y) + a.x) {
        in = !in;
      }
    }
    return in;
  };
  long double area = 0;
  for (std::size_t i = 0; i < rings.size(); ++i) {
    int depth = 0;
    for (std::size_t j = 0; j < rings.size(); ++j) {
      if (j != i && inside(pts[rings[i][0]], rings[j])) ++depth;
    }
    const long double a = std::fabs(shoelace(rings[i]));
    area += depth % 2 == 0 ? a : -a;
  }
  if (ring_count) *ring_count = rings.size();
  return area;
}

// Sum of the areas of the in-domain triangles (long double, from the coordinates).
inline long double domain_area(const Mesh& m) {
  long double s = 0;
  for (const Tri& t : finite_triangles(m, true)) {
    const Point &a = m.points[t[0]], &b = m.points[t[1]], &c = m.points[t[2]];
    s += ((long double)b.x - a.x) * ((long double)c.y - a.y) - ((long double)b.y - a.y) * ((long double)c.x - a.x);
  }
  return s / 2;
}

}  // namespace mwst::test
