// tests/algorithms/bundle/test_bundle.cpp — the exact bundle number (mwst/algorithms/bundle.hpp, src/algorithms/bundle/bundle.cpp),
// after Boyacı, Erten, Üngör, "Triangulations Loosing Bundles and Weight" (k-bundles) and
// docs/algorithms/bundle-number.md.
//
// The oracle is independent of the library's method: it enumerates EVERY pair of vertices p, q (not
// only Delaunay edges), finds the exact range [s_lo, s_hi] of vertex-empty disks through p and q
// with GMP rationals, and evaluates the exact number of triangles met by the disk at every
// threshold the pencil can have (circles through a vertex and tangents at p, q: exact rationals;
// tangencies to edge lines: rounded, then made rational) and at the midpoints between consecutive
// thresholds. A disk meets a triangle's interior iff the distance from its centre to the closed
// triangle is below its radius; that comparison is decided in double when clearly separated and
// otherwise with GMP. Its answer is therefore the count of real vertex-empty disks (a true lower
// bound) and the maximum whenever every open interval of the pencil contains one of the samples
// (it does unless two distinct thresholds are within rounding of each other).
//
// Cases: the 7-point counterexample (answer 6, circumdisks 5); random Delaunay triangulations,
// randomly flipped ones (not Delaunay), and subsets of triangles (non-convex domains with holes) on
// random points, on integer grids (many exact ties: cocircular squares, collinear edges) and on
// small random integer points and rotated lattices with fixed diagonal patterns; invariance under
// renumbering; threads and pruning; a carved data set and a refined mesh; per-triangle values and
// the cheap circumdisk variant; input errors; `mwst bundle` and `mwst triangulate --bundle`.
#include <gtest/gtest.h>
#include <gmpxx.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "mwst/algorithms/brh.hpp"
#include "mwst/algorithms/bundle.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/mesh/mesh.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/algorithms/refine.hpp"
#include "algorithms/bundle/circle_predicates.hpp"
#include "support/huge_pages.hpp"
#include "support/mesh_queries.hpp"

namespace mwst {
namespace {

using Tri = std::array<std::uint32_t, 3>;
using Q = mpq_class;

struct QPoint {
  Q x, y;
};

Q cross(const QPoint& a, const QPoint& b) { return a.x * b.y - a.y * b.x; }
Q dot(const QPoint& a, const QPoint& b) { return a.x * b.x + a.y * b.y; }
QPoint sub(const QPoint& a, const QPoint& b) { return {a.x - b.x, a.y - b.y}; }

// Squared distance from c to the closed segment ab, exactly.
Q segment_distance2(const QPoint& c, const QPoint& a, const QPoint& b) {
  const QPoint ab = sub(b, a), ac = sub(c, a);
  const Q len2 = dot(ab, ab);
  Q t = dot(ac, ab) / len2;
  if (t < 0) t = 0;
  if (t > 1) t = 1;
  const QPoint d{ac.x - t * ab.x, ac.y - t * ab.y};
  return dot(d, d);
}

// Does the open disk (c, r²) meet the interior of triangle t? Equivalently (the disk is open, the
// triangle the closure of its interior): is the distance from c to the closed triangle below r?
bool disk_meets(const QPoint& c, const Q& r2, const std::array<QPoint, 3>& t) {
  // Floating-point filter: decide in double when clearly separated.
  const double cx = c.x.get_d(), cy = c.y.get_d(), rr = r2.get_d();
  double best = std::numeric_limits<double>::infinity();
  double ax[3], ay[3];
  for (int i = 0; i < 3; ++i) {
    ax[i] = t[i].x.get_d();
    ay[i] = t[i].y.get_d();
  }
  const double o = (ax[1] - ax[0]) * (ay[2] - ay[0]) - (ay[1] - ay[0]) * (ax[2] - ax[0]);
  bool inside = true;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    const double side = (ax[j] - ax[i]) * (cy - ay[i]) - (ay[j] - ay[i]) * (cx - ax[i]);
    if (side * o < 0) inside = false;
    const double ex = ax[j] - ax[i], ey = ay[j] - ay[i];
    double s = ((cx - ax[i]) * ex + (cy - ay[i]) * ey) / (ex * ex + ey * ey);
    s = std::clamp(s, 0.0, 1.0);
    const double dx = cx - ax[i] - s * ex, dy = cy - ay[i] - s * ey;
    best = std::min(best, dx * dx + dy * dy);
  }
  if (inside) best = 0.0;
  const double tol = 1e-9 * (rr + best) + 1e-300;
  if (best < rr - tol) return true;
  if (best > rr + tol) return false;
  // Exact.
  const Q orient = cross(sub(t[1], t[0]), sub(t[2], t[0]));
  bool in = true;
  for (int i = 0; i < 3; ++i) {
    const Q side = cross(sub(t[(i + 1) % 3], t[i]), sub(c, t[i]));
    if (sgn(side) * sgn(orient) < 0) in = false;
  }
  if (in) return true;  // r² > 0
  for (int i = 0; i < 3; ++i) {
    if (segment_distance2(c, t[i], t[(i + 1) % 3]) < r2) return true;
  }
  return false;
}

struct OracleResult {
  std::uint32_t bundle = 0;
  std::uint32_t circumdisk = 0;
  std::vector<std::uint32_t> per_triangle;
};

// Brute force over all vertex pairs (see the file comment).
OracleResult oracle(const std::vector<Point>& pts, const std::vector<Tri>& tris) {
  OracleResult out;
  out.per_triangle.assign(tris.size(), 0);
  std::vector<std::uint32_t> used;
  for (const Tri& t : tris) used.insert(used.end(), t.begin(), t.end());
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::vector<QPoint> qp(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) qp[i] = {Q(pts[i].x), Q(pts[i].y)};
  std::vector<std::array<QPoint, 3>> qt(tris.size());
  for (std::size_t i = 0; i < tris.size(); ++i) qt[i] = {qp[tris[i][0]], qp[tris[i][1]], qp[tris[i][2]]};
  std::vector<std::uint32_t> met;

  for (std::size_t ii = 0; ii < used.size(); ++ii) {
    for (std::size_t jj = ii + 1; jj < used.size(); ++jj) {
      const std::uint32_t pi = used[ii], qi = used[jj];
      const QPoint& p = qp[pi];
      const QPoint& q = qp[qi];
      const QPoint b = sub(q, p);
      std::optional<Q> lo, hi;
      bool valid = true;
      std::vector<Q> values;
      for (const std::uint32_t v : used) {
        if (v == pi || v == qi) continue;
        const QPoint& x = qp[v];
        const Q d = cross(b, sub(x, p));
        if (d == 0) {
          if (dot(sub(x, p), sub(x, q)) < 0) valid = false;  // on the open chord
          continue;
        }
        const Q s = dot(sub(x, p), sub(x, q)) / d;
        values.push_back(s);
        if (d > 0) {
          if (!hi || s < *hi) hi = s;
        } else {
          if (!lo || s > *lo) lo = s;
        }
      }
      if (!valid || (lo && hi && *lo > *hi)) continue;
      // Tangents at p and q to triangle edges from them; tangencies to every edge line.
      const double mx = 0.5 * (pts[pi].x + pts[qi].x), my = 0.5 * (pts[pi].y + pts[qi].y);
      const double hx = -0.5 * (pts[qi].y - pts[pi].y), hy = 0.5 * (pts[qi].x - pts[pi].x);
      for (const Tri& t : tris) {
        for (int k = 0; k < 3; ++k) {
          const std::uint32_t u = t[k], w = t[(k + 1) % 3];
          for (const auto& [end, far] : {std::pair{u, w}, std::pair{w, u}}) {
            if (end != pi && end != qi) continue;
            const QPoint& x = qp[far];
            const Q d = cross(b, sub(x, p));
            if (d == 0) continue;
            values.push_back(end == pi ? Q(-dot(sub(x, p), b) / d) : Q(dot(sub(x, q), b) / d));
          }
          // Pencil circle tangent to the line uw: (α + sβ)² = |e|²|h|²(1 + s²).
          const double ex = pts[w].x - pts[u].x, ey = pts[w].y - pts[u].y;
          const double alpha = ex * (my - pts[u].y) - ey * (mx - pts[u].x);
          const double beta = ex * hy - ey * hx;
          const double e2 = ex * ex + ey * ey, h2 = hx * hx + hy * hy;
          const double qa = beta * beta - e2 * h2, qb = 2 * alpha * beta, qc = alpha * alpha - e2 * h2;
          if (qa != 0.0) {
            const double disc = qb * qb - 4 * qa * qc;
            if (disc >= 0) {
              values.push_back(Q((-qb + std::sqrt(disc)) / (2 * qa)));
              values.push_back(Q((-qb - std::sqrt(disc)) / (2 * qa)));
            }
          } else if (qb != 0.0) {
            values.push_back(Q(-qc / qb));
          }
        }
      }
      if (lo) values.push_back(*lo);
      if (hi) values.push_back(*hi);
      std::sort(values.begin(), values.end());
      values.erase(std::unique(values.begin(), values.end()), values.end());
      std::vector<Q> samples;
      for (std::size_t k = 0; k < values.size(); ++k) {
        samples.push_back(values[k]);
        if (k + 1 < values.size()) samples.push_back((values[k] + values[k + 1]) / 2);
      }
      samples.push_back(values.front() - 1);
      samples.push_back(values.back() + 1);
      const QPoint m{(p.x + q.x) / 2, (p.y + q.y) / 2};
      const QPoint h{-(q.y - p.y) / 2, (q.x - p.x) / 2};
      for (const Q& s : samples) {
        if ((lo && s < *lo) || (hi && s > *hi)) continue;
        const QPoint c{m.x + s * h.x, m.y + s * h.y};
        const QPoint cp = sub(c, p);
        const Q r2 = dot(cp, cp);
        met.clear();
        for (std::uint32_t t = 0; t < tris.size(); ++t) {
          if (disk_meets(c, r2, qt[t])) met.push_back(t);
        }
        const auto count = static_cast<std::uint32_t>(met.size());
        out.bundle = std::max(out.bundle, count);
        for (const std::uint32_t t : met) out.per_triangle[t] = std::max(out.per_triangle[t], count);
        if ((lo && s == *lo) || (hi && s == *hi)) out.circumdisk = std::max(out.circumdisk, count);
      }
    }
  }
  return out;
}

// ---- triangulation generators ------------------------------------------------------------------

std::vector<Tri> finite_triangles(const Mesh& m) {
  std::vector<Tri> out;
  for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
    if (m.in_domain(t)) out.push_back({m.triangles[t].v[0], m.triangles[t].v[1], m.triangles[t].v[2]});
  }
  return out;
}

// Flips random interior edges whose quadrilateral is strictly convex (the result is a valid, in
// general non-Delaunay, triangulation of the same points).
void random_flips(Mesh& m, std::size_t count, std::mt19937_64& rng) {
  std::uniform_int_distribution<std::size_t> pick(0, m.triangle_slots() - 1);
  for (std::size_t k = 0; k < count; ++k) {
    const auto t = static_cast<TriangleId>(pick(rng));
    if (!m.in_domain(t)) continue;
    const Handle h = make_handle(t, static_cast<unsigned>(rng() % 3));
    const TriangleId n = triangle_of(m.sym(h));
    if (!m.in_domain(n)) continue;
    const Point& a = m.points[m.org(h)];
    const Point& b = m.points[m.dest(h)];
    const Point& c = m.points[m.apex(h)];
    const Point& d = m.points[m.apex(m.sym(h))];
    if (orient2d(d, c, a) * orient2d(d, c, b) < 0) m.flip(h);
  }
}

std::vector<Point> random_points(std::size_t n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Point> p(n);
  for (auto& x : p) x = {u(rng), u(rng)};
  return p;
}

std::vector<Point> integer_points(std::size_t n, int range, std::mt19937_64& rng) {
  std::uniform_int_distribution<int> u(0, range);
  std::vector<Point> p;
  while (p.size() < n) {
    const Point x{double(u(rng)), double(u(rng))};
    if (std::find(p.begin(), p.end(), x) == p.end()) p.push_back(x);
  }
  return p;
}

std::vector<Point> grid(int nx, int ny) {
  std::vector<Point> p;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) p.push_back({double(i), double(j)});
  return p;
}

// A square lattice rotated by a random angle: generators u = (a, b), v = (−b, a) with a, b random
// integers near 2^26. Every lattice square is exactly cocircular and lattice lines exactly straight
// (integer coordinates), but the products in the threshold arithmetic exceed 53 bits and round, so
// exact ties reach the tie-breaking comparisons with different rounded values.
std::vector<Point> rotated_grid(int nx, int ny, std::mt19937_64& rng) {
  std::uniform_int_distribution<std::int64_t> u(std::int64_t{1} << 25, std::int64_t{1} << 26);
  const std::int64_t a = u(rng), b = u(rng);
  std::vector<Point> p;
  for (std::int64_t i = 0; i < nx; ++i)
    for (std::int64_t j = 0; j < ny; ++j) p.push_back({double(i * a - j * b), double(i * b + j * a)});
  return p;
}

bool all_collinear(const std::vector<Point>& p) {
  for (std::size_t i = 2; i < p.size(); ++i)
    if (orient2d(p[0], p[1], p[i]) != 0) return false;
  return true;
}

// A random triangulation of `pts`: Delaunay, then (flips > 0) random flips, then (keep < 1) a random
// subset of its triangles (non-convex, with holes, possibly disconnected).
std::vector<Tri> random_triangulation(const std::vector<Point>& pts, std::size_t flips, double keep,
                                      std::mt19937_64& rng) {
  Mesh m = delaunay(pts);
  random_flips(m, flips, rng);
  EXPECT_TRUE(validate(m).empty());
  std::vector<Tri> all = finite_triangles(m);
  if (keep >= 1.0) return all;
  std::bernoulli_distribution coin(keep);
  std::vector<Tri> kept;
  for (const Tri& t : all)
    if (coin(rng)) kept.push_back(t);
  if (kept.empty()) kept.push_back(all[rng() % all.size()]);
  return kept;
}

std::string describe(const std::vector<Point>& pts, const std::vector<Tri>& tris) {
  std::string s = "points:";
  for (const Point& p : pts) s += " (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ")";
  s += "\ntriangles:";
  for (const Tri& t : tris) s += " [" + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "]";
  return s;
}

// Runs the library and the oracle on one triangulation and compares everything.
void expect_matches_oracle(const std::vector<Point>& pts, const std::vector<Tri>& tris) {
  const BundleResult r = bundle_number(pts, tris, {.per_triangle = true});
  const OracleResult o = oracle(pts, tris);
  ASSERT_EQ(r.bundle_number, o.bundle) << describe(pts, tris);
  EXPECT_EQ(r.circumdisk_bound, o.circumdisk) << describe(pts, tris);
  EXPECT_EQ(r.per_triangle, o.per_triangle) << describe(pts, tris);
  EXPECT_EQ(r.triangles.size(), r.bundle_number);
  EXPECT_LE(r.circumdisk_bound, r.bundle_number);
  // The witness disk, shrunk by a relative 1e-9 (it is rounded and p, q lie on its boundary),
  // contains no vertex and meets the triangles it names.
  const Q cx(r.disk_center.x), cy(r.disk_center.y);
  const Q radius(r.disk_radius * (1.0 - 1e-9));
  const Q r2 = radius * radius;
  for (const Tri& t : tris) {
    for (const std::uint32_t v : t) {
      const Q dx = Q(pts[v].x) - cx, dy = Q(pts[v].y) - cy;
      EXPECT_GE(dx * dx + dy * dy, r2) << "witness contains vertex " << v << "\n" << describe(pts, tris);
    }
  }
  for (const std::uint32_t t : r.triangles) {
    const std::array<QPoint, 3> qt{QPoint{Q(pts[tris[t][0]].x), Q(pts[tris[t][0]].y)},
                                   QPoint{Q(pts[tris[t][1]].x), Q(pts[tris[t][1]].y)},
                                   QPoint{Q(pts[tris[t][2]].x), Q(pts[tris[t][2]].y)}};
    EXPECT_TRUE(disk_meets({cx, cy}, r2, qt)) << "witness misses triangle " << t << "\n" << describe(pts, tris);
  }
}

// ---- tests -------------------------------------------------------------------------------------

const std::vector<Point> kCounterexample = {{13, 8}, {18, 7}, {17, 3}, {0, 6}, {7, 12}, {5, 12}, {5, 2}};

TEST(Bundle, CounterexampleNeedsThePencilInterior) {
  const Mesh m = delaunay(kCounterexample);
  ASSERT_EQ(m.domain_triangle_count(), 6u);
  const BundleResult r = bundle_number(m);
  EXPECT_EQ(r.bundle_number, 6u);
  EXPECT_EQ(r.circumdisk_bound, 5u);
  EXPECT_EQ(r.triangles.size(), 6u);
  // docs/algorithms/bundle-number.md's disk: centre (9.12, 4.84), r² = 25.04, through (13, 8) and (5, 2), is
  // vertex-empty and meets all 6; ours must be an equally valid witness.
  expect_matches_oracle(kCounterexample, finite_triangles(m));
  const std::vector<std::uint32_t> cheap = circumdisk_bundle_per_triangle(m);
  EXPECT_EQ(*std::max_element(cheap.begin(), cheap.end()), 5u);
}

TEST(Bundle, SingleTriangleAndEmpty) {
  const std::vector<Point> pts = {{0, 0}, {1, 0}, {0, 1}, {5, 5}};
  EXPECT_EQ(bundle_number(pts, {Tri{0, 1, 2}}).bundle_number, 1u);
  EXPECT_EQ(bundle_number(pts, {Tri{0, 2, 1}}).bundle_number, 1u);  // clockwise accepted
  EXPECT_EQ(bundle_number(pts, std::vector<Tri>{}).bundle_number, 0u);
  expect_matches_oracle(pts, {Tri{0, 1, 2}});
}

// detail::enters_circle, the sweep's exact predicate, against rationals near tangency: u, p, q
// random in a box at an offset (0: the six differences carry full mantissas, so the second
// stage's factors are rounded; 2^37, as in inputs whose segments cross thousands of times: the
// differences are exact doubles of fewer bits), w just off the tangent at u of the circle through
// p, q and u, by 1e-18 to 1e-12 of its distance (the first stage cannot decide these; the second
// decides them with its bounds or defers), and w exactly on the tangent of lattice circles (0).
TEST(Bundle, EntersCircleMatchesRationalsNearTangency) {
  auto oracle = [](const Point& p, const Point& q, const Point& u, const Point& w) {
    const QPoint pu{Q(p.x) - Q(u.x), Q(p.y) - Q(u.y)}, qu{Q(q.x) - Q(u.x), Q(q.y) - Q(u.y)};
    const QPoint e{Q(w.x) - Q(u.x), Q(w.y) - Q(u.y)};
    const Q value = dot(pu, pu) * cross(e, qu) - dot(qu, qu) * cross(e, pu);
    return sgn(value) * sgn(cross(pu, qu));  // orient(p, q, u) = cross(p', q')
  };
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::size_t zeros = 0, checked = 0;
  for (int c = 0; c < 60000; ++c) {
    const double offset = c % 2 == 0 ? 0.0 : 0x1p37;
    const double size = c % 3 == 0 ? 1.0 : 1000.0;
    auto random_point = [&] { return Point{offset + size * unit(rng), offset + size * unit(rng)}; };
    const Point p = random_point(), q = random_point(), u = random_point();
    const int o = orient2d(p, q, u);
    if (o == 0) continue;
    // The centre of the circle through p, q, u (rounded), the tangent and the normal at u.
    const Point centre = circumcenter(p, q, u);
    const double nx = centre.x - u.x, ny = centre.y - u.y, len = std::hypot(nx, ny);
    if (!(len > 0.0) || !std::isfinite(len)) continue;
    const double along = (unit(rng) < 0.5 ? -1.0 : 1.0) * size * (0.01 + unit(rng));
    const double off = (unit(rng) < 0.5 ? -1.0 : 1.0) * std::pow(10.0, -18.0 + 6.0 * unit(rng)) * std::fabs(along);
    const Point w{u.x - ny / len * along + nx / len * off, u.y + nx / len * along + ny / len * off};
    if (w.x == u.x && w.y == u.y) continue;
    ASSERT_EQ(detail::enters_circle(p, q, u, w, o), oracle(p, q, u, w))
        << std::hexfloat << "p " << p.x << " " << p.y << " q " << q.x << " " << q.y << " u " << u.x << " " << u.y
        << " w " << w.x << " " << w.y;
    ++checked;
  }
  // Exact tangents: the circle through u, u + (0, 2b) and u + (2a, 0) has centre u + (a, b); the
  // tangent at u runs along (−b, a).
  for (int c = 0; c < 2000; ++c) {
    const double offset = c % 2 == 0 ? 0.0 : 0x1p37;
    std::uniform_int_distribution<int> small(-40, 40);
    const double a = small(rng), b = small(rng);
    if (a == 0.0 || b == 0.0) continue;
    const Point u{offset + small(rng), offset + small(rng)};
    const Point p{u.x, u.y + 2 * b}, q{u.x + 2 * a, u.y};
    const double k = small(rng);
    if (k == 0.0) continue;
    const Point w{u.x - k * b, u.y + k * a};
    const int o = orient2d(p, q, u);
    ASSERT_NE(o, 0);
    EXPECT_EQ(detail::enters_circle(p, q, u, w, o), 0);
    EXPECT_EQ(oracle(p, q, u, w), 0);
    ++zeros;
  }
  EXPECT_GT(checked, 50000u);
  EXPECT_GT(zeros, 1500u);
}

TEST(Bundle, RandomDelaunayMatchesOracle) {
  std::mt19937_64 rng(1);
  for (int c = 0; c < 50; ++c) {
    const auto pts = random_points(5 + c % 6, rng);
    expect_matches_oracle(pts, random_triangulation(pts, 0, 1.0, rng));
    if (HasFatalFailure()) return;
  }
}

TEST(Bundle, RandomFlippedMatchesOracle) {
  std::mt19937_64 rng(2);
  for (int c = 0; c < 60; ++c) {
    const auto pts = random_points(5 + c % 7, rng);
    expect_matches_oracle(pts, random_triangulation(pts, 20, 1.0, rng));
    if (HasFatalFailure()) return;
  }
}

TEST(Bundle, NonConvexWithHolesMatchesOracle) {
  std::mt19937_64 rng(3);
  for (int c = 0; c < 60; ++c) {
    const auto pts = random_points(6 + c % 6, rng);
    expect_matches_oracle(pts, random_triangulation(pts, c % 2 == 0 ? 0 : 20, 0.7, rng));
    if (HasFatalFailure()) return;
  }
}

// Grids: every grid rectangle is cocircular, every vertex has collinear edges, so thresholds tie
// exactly (s_lo = s_hi, tangents at p along collinear edges above and below, tangents equal to
// circumcircles). The oracle's rational thresholds are exact there. Small integer grids keep the
// library's rounded arithmetic exact too; rotated lattices with large generators do not.
TEST(Bundle, GridsWithTiesMatchOracle) {
  std::mt19937_64 rng(4);
  const std::pair<int, int> sizes[] = {{3, 3}, {4, 3}, {4, 4}, {5, 3}, {3, 2}};
  for (int c = 0; c < 80; ++c) {
    const auto [nx, ny] = sizes[c % 5];
    const auto pts = c % 2 == 0 ? grid(nx, ny) : rotated_grid(nx, ny, rng);
    const std::size_t flips = (c / 5) % 3 == 0 ? 0 : 30;
    const double keep = (c / 5) % 2 == 0 ? 1.0 : 0.75;
    expect_matches_oracle(pts, random_triangulation(pts, flips, keep, rng));
    if (HasFatalFailure()) return;
  }
}

// Rotated square lattices triangulated with every diagonal one way, the other way, or alternating:
// lattice circles are tangent to diagonals exactly at lattice vertices (the circle through a unit
// square is tangent at a corner to the diagonal of the neighbouring square), which the exact test
// "does the edge direction enter the circle" must call a tangency, not a tiny crossing.
TEST(Bundle, LatticeDiagonalPatternsMatchOracle) {
  std::mt19937_64 rng(7);
  for (int c = 0; c < 24; ++c) {
    const int nx = 4 + c % 2, ny = 3;
    const auto pts = rotated_grid(nx, ny, rng);  // index i * ny + j
    std::vector<Tri> tris;
    for (int i = 0; i + 1 < nx; ++i) {
      for (int j = 0; j + 1 < ny; ++j) {
        const auto id = [](int a, int b) { return static_cast<std::uint32_t>(a * ny + b); };
        const int pattern = c % 3;
        const bool slash = pattern == 0 || (pattern == 2 && (i + j) % 2 == 0);
        if (slash) {
          tris.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
          tris.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        } else {
          tris.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
          tris.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
        }
      }
    }
    if (c >= 12) {  // drop a few squares' triangles: concavities and holes
      std::vector<Tri> kept;
      for (std::size_t k = 0; k < tris.size(); ++k)
        if ((k * 7 + static_cast<std::size_t>(c)) % 5 != 0) kept.push_back(tris[k]);
      tris = kept;
    }
    expect_matches_oracle(pts, tris);
    if (HasFatalFailure()) return;
  }
}

TEST(Bundle, SmallIntegerPointsMatchOracle) {
  std::mt19937_64 rng(5);
  for (int c = 0; c < 60; ++c) {
    auto pts = integer_points(5 + c % 6, 5, rng);
    if (all_collinear(pts)) continue;
    expect_matches_oracle(pts, random_triangulation(pts, c % 3 == 0 ? 0 : 20, c % 4 == 0 ? 0.7 : 1.0, rng));
    if (HasFatalFailure()) return;
  }
}

TEST(Bundle, InvariantUnderRenumbering) {
  std::mt19937_64 rng(6);
  for (int c = 0; c < 20; ++c) {
    const auto pts = c % 2 == 0 ? random_points(40, rng) : grid(6, 5);
    const auto tris = random_triangulation(pts, 100, c % 3 == 0 ? 0.8 : 1.0, rng);
    const BundleResult r = bundle_number(pts, tris, {.per_triangle = true});
    // Renumber the points (with unused extra points), shuffle the triangles, rotate and mirror
    // their corners.
    std::vector<std::uint32_t> perm(pts.size() + 3);
    std::iota(perm.begin(), perm.end(), 0u);
    std::shuffle(perm.begin(), perm.end(), rng);
    std::vector<Point> pts2(perm.size(), Point{1e6, 1e6});
    for (std::size_t i = 0; i < pts.size(); ++i) pts2[perm[i]] = pts[i];
    std::vector<std::uint32_t> order(tris.size());
    std::iota(order.begin(), order.end(), 0u);
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<Tri> tris2;
    for (const std::uint32_t i : order) {
      Tri t{perm[tris[i][0]], perm[tris[i][1]], perm[tris[i][2]]};
      std::rotate(t.begin(), t.begin() + static_cast<long>(rng() % 3), t.end());
      if (rng() % 2) std::swap(t[1], t[2]);
      tris2.push_back(t);
    }
    const BundleResult r2 = bundle_number(pts2, tris2, {.per_triangle = true});
    EXPECT_EQ(r.bundle_number, r2.bundle_number);
    EXPECT_EQ(r.circumdisk_bound, r2.circumdisk_bound);
    for (std::size_t k = 0; k < order.size(); ++k) {
      EXPECT_EQ(r2.per_triangle[k], r.per_triangle[order[k]]) << "case " << c;
    }
  }
}

// A carved domain with holes and concavities: the Mesh entry point and the triangle-list entry
// point agree; per-triangle values reach the bundle number; the cheap variant is a lower bound
// whose maximum is the circumdisk bound.
TEST(Bundle, CarvedDataSetMeshAndListAgree) {
  const Pslg pslg = io::read_poly(std::string(MWST_DATA_DIR) + "/Superior.poly");  // a lake with islands
  ASSERT_FALSE(pslg.holes.empty());
  const Mesh m = constrained_delaunay(pslg);
  ASSERT_TRUE(validate(m).empty());
  const BundleResult r = bundle_number(m, {.per_triangle = true});
  std::vector<Tri> tris;
  std::vector<TriangleId> slot_of;
  for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
    if (!m.in_domain(t)) continue;
    tris.push_back({m.triangles[t].v[0], m.triangles[t].v[1], m.triangles[t].v[2]});
    slot_of.push_back(t);
  }
  const BundleResult r2 = bundle_number(m.points, tris, {.per_triangle = true});
  EXPECT_EQ(r.bundle_number, r2.bundle_number);
  EXPECT_EQ(r.circumdisk_bound, r2.circumdisk_bound);
  EXPECT_GE(r.bundle_number, 3u);
  std::uint32_t per_max = 0;
  const std::vector<std::uint32_t> cheap = circumdisk_bundle_per_triangle(m);
  std::uint32_t cheap_max = 0;
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const TriangleId t = slot_of[i];
    EXPECT_EQ(r.per_triangle[t], r2.per_triangle[i]);
    EXPECT_GE(r.per_triangle[t], 1u);
    EXPECT_LE(cheap[t], r.per_triangle[t]);
    per_max = std::max(per_max, r.per_triangle[t]);
    cheap_max = std::max(cheap_max, cheap[t]);
  }
  EXPECT_EQ(per_max, r.bundle_number);
  EXPECT_EQ(cheap_max, r.circumdisk_bound);
  for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
    if (!m.in_domain(t)) {
      EXPECT_EQ(r.per_triangle[t], 0u);
    }
  }
  // The witness triangles are in the domain and as many as the bundle number.
  EXPECT_EQ(r.triangles.size(), r.bundle_number);
  for (const std::uint32_t t : r.triangles) EXPECT_TRUE(m.in_domain(t));
}

// A point inside a hole is a vertex of the mesh (of carved-away triangles only) but not of the
// triangulation: disks may contain it. The Mesh entry point must agree with the triangle list,
// which does not even mention the point.
TEST(Bundle, PointsOutsideTheDomainAreNotVertices) {
  Pslg pslg;
  // A 10 × 10 square with a 6 × 6 square hole, points inside the hole (the hole seed is not one).
  pslg.points = {{0, 0}, {10, 0}, {10, 10}, {0, 10}, {2, 2}, {8, 2}, {8, 8}, {2, 8},
                 {5, 5.5}, {4.5, 4}, {6, 4.2}};
  for (std::uint32_t i = 0; i < 4; ++i) {
    pslg.segments.push_back({i, (i + 1) % 4, 1});
    pslg.segments.push_back({4 + i, 4 + (i + 1) % 4, 1});
  }
  pslg.holes = {{3, 3}};
  const Mesh m = constrained_delaunay(pslg);
  ASSERT_TRUE(validate(m).empty());
  std::vector<Tri> tris = finite_triangles(m);
  for (const Tri& t : tris)
    for (const std::uint32_t v : t) EXPECT_LT(v, 8u);
  const BundleResult r = bundle_number(m, {.per_triangle = true});
  const BundleResult r2 = bundle_number(m.points, tris, {.per_triangle = true});
  EXPECT_EQ(r.bundle_number, r2.bundle_number);
  EXPECT_EQ(r.circumdisk_bound, r2.circumdisk_bound);
  const OracleResult o = oracle(m.points, tris);
  EXPECT_EQ(r2.bundle_number, o.bundle);
  EXPECT_EQ(r2.per_triangle, o.per_triangle);
  // The big disk centred in the hole through the inner corners holds the hole's points and meets
  // all 8 triangles around the hole; nothing larger exists in this ring.
  EXPECT_EQ(r.bundle_number, 8u);
}

// The paper's lemma: minimum angle α ⇒ (4π/α + 3)-bundle-free, i.e. bundle number < 4π/α + 3.
TEST(Bundle, AngleLemmaOnEquilateralLattice) {
  std::vector<Point> pts;
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) pts.push_back({i + 0.5 * (j % 2), j * std::sqrt(3.0) / 2});
  const Mesh m = delaunay(pts);
  const BundleResult r = bundle_number(m);
  EXPECT_LT(r.bundle_number, 4 * 3 + 3);  // α ≈ 60°
  EXPECT_GE(r.bundle_number, 3u);
}

// Large enough for the worker threads (and, without per-triangle values, the pruning of pencils
// that cannot beat the best so far): one thread, two threads and the unpruned per-triangle run
// agree on everything, including the witness.
TEST(Bundle, ThreadsAndPruningDoNotChangeTheResult) {
  std::mt19937_64 rng(8);
  for (const bool flipped : {false, true}) {
    const auto pts = random_points(12000, rng);
    Mesh m = delaunay(pts);
    if (flipped) random_flips(m, 20000, rng);
    ASSERT_TRUE(validate(m).empty());
    const BundleResult one = bundle_number(m, {.threads = 1});
    const BundleResult two = bundle_number(m, {.threads = 2});
    const BundleResult per = bundle_number(m, {.per_triangle = true, .threads = 2});
    EXPECT_GE(one.pencils, 20000u);
    EXPECT_EQ(one.bundle_number, two.bundle_number);
    EXPECT_EQ(one.bundle_number, per.bundle_number);
    EXPECT_EQ(one.circumdisk_bound, two.circumdisk_bound);
    EXPECT_EQ(one.circumdisk_bound, per.circumdisk_bound);
    EXPECT_EQ(one.triangles, two.triangles);
    EXPECT_EQ(one.disk_center, two.disk_center);
    EXPECT_EQ(one.disk_radius, two.disk_radius);
    EXPECT_EQ(*std::max_element(per.per_triangle.begin(), per.per_triangle.end()), one.bundle_number);
    const std::vector<std::uint32_t> cheap1 = circumdisk_bundle_per_triangle(m, 1);
    const std::vector<std::uint32_t> cheap2 = circumdisk_bundle_per_triangle(m, 2);
    EXPECT_EQ(cheap1, cheap2);
    for (TriangleId t = 0; t < m.triangle_slots(); ++t) EXPECT_LE(cheap1[t], per.per_triangle[t]);
  }
}

// in_k_bundle (what BRH asks) answers exactly per_triangle[t] >= k, for every in-domain triangle
// queried, on Delaunay, flipped (non-Delaunay), carved (holes, concavities), lattice (ties) and
// refined meshes, for k from 3 to past the bundle number, for many queries and for a few (the
// local path); on one thread and on two.
TEST(Bundle, InKBundleAgreesWithPerTriangleValues) {
  std::mt19937_64 rng(11);
  std::vector<std::pair<std::string, Mesh>> meshes;
  meshes.emplace_back("random", delaunay(random_points(3000, rng)));
  Mesh flipped = delaunay(random_points(3000, rng));
  random_flips(flipped, 6000, rng);
  meshes.emplace_back("flipped", std::move(flipped));
  meshes.emplace_back("grid", delaunay(grid(30, 20)));
  meshes.emplace_back("Superior", constrained_delaunay(io::read_poly(std::string(MWST_DATA_DIR) + "/Superior.poly")));
  Mesh refined = constrained_delaunay(io::read_poly(std::string(MWST_DATA_DIR) + "/Africa.poly"));
  RefineOptions ro;
  ro.min_angle_deg = 10.0;
  refine(refined, ro);
  meshes.emplace_back("Africa refined 10deg", std::move(refined));
  Mesh large_refined = constrained_delaunay(io::read_poly(std::string(MWST_DATA_DIR) + "/Superior.poly"));
  ro.min_angle_deg = 20.0;
  ro.max_area = 1e-4 * measure(large_refined).area;
  refine(large_refined, ro);
  meshes.emplace_back("Superior refined 20deg", std::move(large_refined));
  std::size_t local_answers = 0;
  for (const auto& [name, m] : meshes) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(validate(m).empty());
    const BundleResult per = bundle_number(m, {.per_triangle = true});
    std::vector<TriangleId> queries;
    for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
      if (m.in_domain(t)) queries.push_back(t);
    }
    ASSERT_FALSE(queries.empty());
    std::shuffle(queries.begin(), queries.end(), rng);
    queries.resize(std::min<std::size_t>(queries.size(), 1500));
    queries.push_back(queries.front());  // repeats are answered too
    // Few queries take the local path (the Delaunay triangulation of the vertices near them).
    const std::vector<TriangleId> few(queries.begin(), queries.begin() + std::min<std::size_t>(queries.size(), 6));
    const std::uint32_t b = per.bundle_number;
    for (const std::uint32_t k : {3u, 5u, 7u, b - 1, b, b + 1}) {
      for (const unsigned threads : {1u, 2u}) {
        for (const std::vector<TriangleId>* asked : {&std::as_const(queries), &few}) {
          KBundleStats stats;
          const std::vector<std::uint8_t> in = in_k_bundle(m, k, *asked, &stats, threads);
          ASSERT_EQ(in.size(), asked->size());
          std::size_t yes = 0;
          for (std::size_t i = 0; i < asked->size(); ++i) {
            const TriangleId t = (*asked)[i];
            EXPECT_EQ(in[i] != 0, per.per_triangle[t] >= k) << "k " << k << " triangle " << t << " local " << stats.local;
            yes += in[i];
          }
          EXPECT_EQ(yes, stats.decided_by_circumdisks + stats.decided_by_pencils);
          local_answers += stats.local;
        }
      }
    }
  }
  EXPECT_GT(local_answers, 0u);
}

// KBundleCache, what BRH keeps between its passes: (1) with it in_k_bundle answers exactly as
// without it, on the same mesh (where sweeps are reused) and after refinement has changed part of
// the mesh; (2) its reach boxes are sound: a query answered 0 whose box meets no triangle the
// refinement made (the hull unchanged) is still answered 0 — what BRH's clean list relies on —
// and each box holds its query.
// A deadline that has passed: in_k_bundle throws KBundleTimeout (one and two threads, over the
// whole mesh and on the local path) instead of answering; without one it answers. (Bundle removal
// turns the timeout into stop_reason "time budget": on a fuzzed input of 96 points whose segments
// cross 2552 times, one exact test took 31-71 s; with --time-limit 0.5 BRH stops at 0.50 s.)
TEST(Bundle, InKBundleGivesUpAtItsDeadline) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Point> pts(2000);
  for (Point& p : pts) p = {u(rng), u(rng)};
  const Mesh m = delaunay(pts);
  std::vector<TriangleId> all;
  for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
    if (m.in_domain(t)) all.push_back(t);
  }
  const std::vector<TriangleId> few(all.begin(), all.begin() + 3);
  const auto past = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  for (const unsigned threads : {1u, 2u}) {
    for (const std::vector<TriangleId>* asked : {&std::as_const(all), &few}) {
      EXPECT_THROW(in_k_bundle(m, 5, *asked, nullptr, threads, nullptr, past), KBundleTimeout);
      EXPECT_EQ(in_k_bundle(m, 5, *asked, nullptr, threads).size(), asked->size());
    }
  }
}

TEST(Bundle, KBundleCacheReusesSweepsAndBoundsWhatChangesAnAnswer) {
  std::mt19937_64 rng(21);
  for (const bool point_set : {false, true}) {
    SCOPED_TRACE(point_set ? "point set refined by BRH" : "random Delaunay");
    Mesh m;
    if (point_set) {
      // Flat hull circumdisks: large pencils, the ones the cache keeps.
      Pslg pslg;
      pslg.points = random_points(5000, rng);
      m = constrained_delaunay(pslg);
      BrhOptions bo;
      bo.min_angle_deg = 20.0;
      bo.bundle_k = 12;
      bundle_removal(m, bo);
    } else {
      m = delaunay(random_points(3000, rng));
    }
    const std::uint32_t b = bundle_number(m).bundle_number;
    std::size_t reused = 0;  // sweeps answered from the cache
    for (const std::uint32_t k : {6u, b - 1}) {
      SCOPED_TRACE(k);
      Mesh mesh = m;
      std::vector<TriangleId> queries;
      for (TriangleId t = 0; t < mesh.triangle_slots(); ++t) {
        if (!mesh.in_domain(t)) continue;
        // On the point set, BRH's questions: the skinny triangles it left (near the hull, many
        // need the sweeps of flat pencils).
        if (!point_set || test::min_angle_of(mesh, t) < 20.0) queries.push_back(t);
      }
      KBundleCache cache;
      const std::vector<std::uint8_t> plain = in_k_bundle(mesh, k, queries, nullptr, 1);
      KBundleStats first, second;
      EXPECT_EQ(in_k_bundle(mesh, k, queries, &first, 1, &cache), plain);
      const auto reach = cache.reach;
      ASSERT_EQ(reach.size(), queries.size());
      EXPECT_EQ(in_k_bundle(mesh, k, queries, &second, 2, &cache), plain);
      EXPECT_EQ(first.pencils_reused, 0u);
      EXPECT_LE(second.pencils_reused, second.pencils_swept);
      reused += second.pencils_reused;
      for (std::size_t i = 0; i < queries.size(); ++i) {
        for (const VertexId v : mesh.triangles[queries[i]].v) {
          const Point& p = mesh.points[v];
          EXPECT_TRUE(reach[i][0] <= p.x && p.x <= reach[i][2] && reach[i][1] <= p.y && p.y <= reach[i][3]);
        }
      }
      // Refine a little (a few Steiner points, below a tighter angle bound).
      const std::vector<Triangle> before = mesh.triangles;
      const std::vector<std::uint8_t> before_flags = mesh.flags;
      RefineOptions ro;
      ro.min_angle_deg = 25.0;
      ro.max_steiner = 12;
      refine(mesh, ro);
      std::vector<std::array<double, 4>> made;
      bool hull_changed = false;
      for (TriangleId t = 0; t < mesh.triangle_slots(); ++t) {
        if (t < before.size() && before[t].v == mesh.triangles[t].v && before_flags[t] == mesh.flags[t]) continue;
        if (mesh.is_dead(t)) continue;
        if (mesh.is_ghost(t)) {
          hull_changed = true;
          continue;
        }
        std::array<double, 4> box{1e300, 1e300, -1e300, -1e300};
        for (const VertexId v : mesh.triangles[t].v) {
          const Point& p = mesh.points[v];
          box = {std::min(box[0], p.x), std::min(box[1], p.y), std::max(box[2], p.x), std::max(box[3], p.y)};
        }
        made.push_back(box);
      }
      ASSERT_FALSE(made.empty());
      std::vector<TriangleId> still;  // queries alive with the same corners
      std::vector<std::size_t> still_at;
      for (std::size_t i = 0; i < queries.size(); ++i) {
        const TriangleId t = queries[i];
        if (!mesh.is_dead(t) && mesh.triangles[t].v == before[t].v && mesh.in_domain(t)) {
          still.push_back(t);
          still_at.push_back(i);
        }
      }
      const std::vector<std::uint8_t> after = in_k_bundle(mesh, k, still, nullptr, 1);
      KBundleStats third;
      EXPECT_EQ(in_k_bundle(mesh, k, still, &third, 1, &cache), after);
      if (hull_changed) continue;
      std::size_t kept = 0;
      for (std::size_t j = 0; j < still.size(); ++j) {
        const auto& r = reach[still_at[j]];
        const bool touched = std::any_of(made.begin(), made.end(), [&](const auto& box) {
          return box[0] <= r[2] && r[0] <= box[2] && box[1] <= r[3] && r[1] <= box[3];
        });
        if (plain[still_at[j]] || touched) continue;
        ++kept;
        EXPECT_EQ(after[j], 0) << "triangle " << still[j] << " joined a " << k << "-bundle far from the change";
      }
      EXPECT_GT(kept, 0u);
    }
    // The large pencils (those kept) are the flat ones along the hull of a point set.
    if (point_set) {
      EXPECT_GT(reused, 0u);
    }
  }
}

// KBundleCache::reach_when_all_no false: a call answering every query 0 leaves every reach box
// empty ("nothing known", which bundle removal does not keep); a call answering some query 1
// computes the same boxes as with the flag set. The answers never change.
TEST(Bundle, KBundleCacheSkipsReachBoxesOnlyWhenEveryAnswerIsNo) {
  std::mt19937_64 rng(23);
  const Mesh mesh = delaunay(random_points(3000, rng));
  const std::uint32_t b = bundle_number(mesh).bundle_number;
  std::vector<TriangleId> queries;
  for (TriangleId t = 0; t < mesh.triangle_slots(); ++t) {
    if (mesh.in_domain(t)) queries.push_back(t);
  }
  auto is_empty = [](const std::array<double, 4>& r) { return !(r[0] <= r[2] && r[1] <= r[3]); };
  for (const std::uint32_t k : {6u, b + 1}) {
    SCOPED_TRACE(k);
    const std::vector<std::uint8_t> plain = in_k_bundle(mesh, k, queries, nullptr, 1);
    const bool any_yes = std::find(plain.begin(), plain.end(), 1) != plain.end();
    EXPECT_EQ(any_yes, k <= b);  // (the bundle number is the largest k with a k-bundle)
    KBundleCache with, without;
    without.reach_when_all_no = false;
    KBundleStats st_with, st_without;
    EXPECT_EQ(in_k_bundle(mesh, k, queries, &st_with, 1, &with), plain);
    EXPECT_EQ(in_k_bundle(mesh, k, queries, &st_without, 2, &without), plain);
    EXPECT_FALSE(st_with.local);  // (the reach boxes are skipped over DT(V) only)
    ASSERT_EQ(with.reach.size(), queries.size());
    ASSERT_EQ(without.reach.size(), queries.size());
    for (std::size_t i = 0; i < queries.size(); ++i) {
      EXPECT_FALSE(is_empty(with.reach[i])) << "query " << i;  // it holds the query's corners
      if (any_yes) {
        EXPECT_EQ(without.reach[i], with.reach[i]) << "query " << i;
      } else {
        EXPECT_TRUE(is_empty(without.reach[i])) << "query " << i;
      }
    }
  }
}

// A KBundleCache keeps DT(V) between calls over the whole mesh; the next call inserts the vertices
// added since (here by refinement, which also splits hull edges, so some land outside the old
// hull) instead of building DT(V) again. The answers must be those of a fresh DT(V); a cache
// whose triangulation does not fit the mesh (other points) must be rebuilt, not reused.
TEST(Bundle, KeptDelaunayTriangulationTakesTheNewVertices) {
  std::mt19937_64 rng(33);
  auto domain_triangles = [](const Mesh& m) {
    std::vector<TriangleId> q;
    for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
      if (m.in_domain(t)) q.push_back(t);
    }
    return q;
  };
  Pslg pslg;
  pslg.points = random_points(2000, rng);
  Mesh mesh = constrained_delaunay(pslg);
  KBundleCache cache;
  cache.reuse_sweeps = false;  // as BRH's first exact test: only DT(V) is kept
  const std::uint32_t k = 6;
  KBundleStats st;
  auto queries = domain_triangles(mesh);
  EXPECT_EQ(in_k_bundle(mesh, k, queries, &st, 1, &cache), in_k_bundle(mesh, k, queries, nullptr, 1));
  EXPECT_FALSE(st.kept_dt);
  std::size_t answered_one = 0;
  for (int round = 0; round < 3; ++round) {
    SCOPED_TRACE(round);
    const std::size_t vertices = mesh.points.size();
    RefineOptions ro;
    ro.min_angle_deg = 25.0;
    ro.max_steiner = 60;
    refine(mesh, ro);
    ASSERT_TRUE(validate(mesh).empty());
    ASSERT_GT(mesh.points.size(), vertices);
    cache.reuse_sweeps = round == 2;  // sweeps kept too in the last round
    queries = domain_triangles(mesh);
    const std::vector<std::uint8_t> plain = in_k_bundle(mesh, k, queries, nullptr, 1);
    EXPECT_EQ(in_k_bundle(mesh, k, queries, &st, 2, &cache), plain);
    EXPECT_TRUE(st.kept_dt);
    answered_one += static_cast<std::size_t>(std::count(plain.begin(), plain.end(), 1));
  }
  EXPECT_GT(answered_one, 0u);
  // Another point set with the same vertex ids: the kept triangulation does not fit.
  Pslg other_pslg;
  other_pslg.points = random_points(1500, rng);
  const Mesh other = constrained_delaunay(other_pslg);
  const auto other_queries = domain_triangles(other);
  EXPECT_EQ(in_k_bundle(other, k, other_queries, &st, 1, &cache), in_k_bundle(other, k, other_queries, nullptr, 1));
  EXPECT_FALSE(st.kept_dt);
}

// Bundle removal on a point set splits the long hull edges; the split points are rounded off the
// hull line, so DT(V) has flat triangles of nearly collinear hull vertices whose circumdisks have
// radii near 10¹⁷ and bulge into the mesh by less than the rounding of the incircle values of the
// mesh vertices. Whether a mesh edge crosses such a disk is a degree-8 sign that rounding got
// wrong (circumdisks "meeting" 60 triangles that meet 3, so in_k_bundle's cheap circumdisk test
// disagreed with the pencil sweep). Checked against exact rational circumdisks: the cheap per-
// triangle circumdisk counts, and in_k_bundle against per_triangle for every triangle.
TEST(Bundle, FlatHullCircumdisksAreCountedExactly) {
  for (const std::uint64_t seed : {3u}) {
    SCOPED_TRACE(seed);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    Pslg pslg;
    pslg.points.resize(seed == 3 ? 300 : 1000);
    for (auto& p : pslg.points) p = {unit(rng), unit(rng)};
    Mesh m = constrained_delaunay(pslg);
    BrhOptions options;
    options.min_angle_deg = 20.0;
    options.bundle_k = 8;
    bundle_removal(m, options);
    ASSERT_TRUE(validate(m).empty());
    std::vector<TriangleId> in_domain;
    std::vector<std::array<QPoint, 3>> exact_triangles;
    std::vector<std::array<double, 4>> boxes;  // x min, x max, y min, y max
    for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
      if (!m.in_domain(t)) continue;
      in_domain.push_back(t);
      std::array<QPoint, 3> q;
      std::array<double, 4> box{1e300, -1e300, 1e300, -1e300};
      for (int i = 0; i < 3; ++i) {
        const Point& p = m.points[m.triangles[t].v[i]];
        q[i] = {Q(p.x), Q(p.y)};
        box = {std::min(box[0], p.x), std::max(box[1], p.x), std::min(box[2], p.y), std::max(box[3], p.y)};
      }
      exact_triangles.push_back(q);
      boxes.push_back(box);
    }
    // The exact circumdisk count per triangle: the largest number of in-domain triangles met by the
    // circumdisk of a triangle of DT(V) that meets it (V: every point, all are vertices here).
    std::vector<std::uint32_t> expected(m.triangle_slots(), 0);
    const Mesh dt = delaunay(m.points);
    std::vector<std::size_t> met;
    std::size_t flat = 0;
    for (TriangleId d = 0; d < dt.triangle_slots(); ++d) {
      if (!dt.in_domain(d)) continue;
      const auto& v = dt.triangles[d].v;
      const QPoint a{Q(dt.points[v[0]].x), Q(dt.points[v[0]].y)};
      const QPoint ba = sub(QPoint{Q(dt.points[v[1]].x), Q(dt.points[v[1]].y)}, a);
      const QPoint ca = sub(QPoint{Q(dt.points[v[2]].x), Q(dt.points[v[2]].y)}, a);
      const Q den = 2 * cross(ba, ca);
      const Q ux = (ca.y * dot(ba, ba) - ba.y * dot(ca, ca)) / den;
      const Q uy = (ba.x * dot(ca, ca) - ca.x * dot(ba, ba)) / den;
      const QPoint centre{a.x + ux, a.y + uy};
      const Q r2 = ux * ux + uy * uy;
      const double cx = centre.x.get_d(), cy = centre.y.get_d(), r = std::sqrt(r2.get_d());
      if (r > 1e6) ++flat;
      met.clear();
      for (std::size_t i = 0; i < in_domain.size(); ++i) {
        const auto& box = boxes[i];
        const double gx = std::max({box[0] - cx, cx - box[1], 0.0});
        const double gy = std::max({box[2] - cy, cy - box[3], 0.0});
        if (std::hypot(gx, gy) > r * (1.0 + 1e-9) + 1e-300) continue;  // clearly apart
        if (disk_meets(centre, r2, exact_triangles[i])) met.push_back(i);
      }
      for (const std::size_t i : met) {
        expected[in_domain[i]] = std::max(expected[in_domain[i]], static_cast<std::uint32_t>(met.size()));
      }
    }
    EXPECT_GT(flat, 0u);  // the case this test is about is there
    EXPECT_EQ(circumdisk_bundle_per_triangle(m, 1), expected);
    const BundleResult per = bundle_number(m, {.per_triangle = true});
    for (const std::uint32_t k : {6u, 8u, 12u}) {
      const std::vector<std::uint8_t> in = in_k_bundle(m, k, in_domain, nullptr, 1);
      for (std::size_t i = 0; i < in_domain.size(); ++i) {
        EXPECT_EQ(in[i] != 0, per.per_triangle[in_domain[i]] >= k) << "k " << k << " triangle " << in_domain[i];
      }
    }
  }
}

// The local path of in_k_bundle copies only a region of the mesh around the queries (and gives up
// for a larger region or DT(V) when a flood would leave it or a Delaunay triangle it needs is not
// one of DT(V)). Long thin triangles whose circumdisks reach far along a strip (points on a thin
// ellipse; two rows of points far apart, on their lines or off them) and a few queries: the
// answers still equal per_triangle[t] >= k.
TEST(Bundle, InKBundleLocalRegionHandlesFarReachingDisks) {
  std::mt19937_64 rng(29);
  std::vector<std::pair<std::string, Mesh>> meshes;
  std::vector<Point> ellipse;
  for (int i = 0; i < 1200; ++i) {
    const double t = 2.0 * 3.141592653589793 * i / 1200.0;
    ellipse.push_back({std::cos(t), 0.02 * std::sin(t)});
  }
  meshes.emplace_back("thin ellipse", delaunay(ellipse));
  std::vector<Point> strip;
  std::uniform_real_distribution<double> jitter(0.0, 0.3);
  for (int i = 0; i < 700; ++i) {
    strip.push_back({i + jitter(rng), 0.0});
    strip.push_back({i + jitter(rng), 40.0});
  }
  meshes.emplace_back("two rows", delaunay(strip));
  std::vector<Point> rows;  // two rows again, each point off its line by up to 0.05
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 500; ++i) {
    rows.push_back({i + 0.4 * unit(rng), 0.05 * unit(rng)});
    rows.push_back({i + 0.4 * unit(rng), 30.0 + 0.05 * unit(rng)});
  }
  meshes.emplace_back("two jittered rows", delaunay(rows));
  for (const auto& [name, m] : meshes) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(validate(m).empty());
    const BundleResult per = bundle_number(m, {.per_triangle = true});
    std::vector<TriangleId> in_domain;
    for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
      if (m.in_domain(t)) in_domain.push_back(t);
    }
    ASSERT_GT(in_domain.size(), 1000u);
    for (int trial = 0; trial < 4; ++trial) {
      std::shuffle(in_domain.begin(), in_domain.end(), rng);
      const std::vector<TriangleId> few(in_domain.begin(), in_domain.begin() + 3);
      const std::uint32_t b = per.bundle_number;
      for (const std::uint32_t k : {3u, 8u, b / 2, b - 1, b, b + 1}) {
        KBundleStats stats;
        const std::vector<std::uint8_t> in = in_k_bundle(m, k, few, &stats, 1);
        ASSERT_EQ(in.size(), few.size());
        for (std::size_t i = 0; i < few.size(); ++i) {
          EXPECT_EQ(in[i] != 0, per.per_triangle[few[i]] >= k) << "k " << k << " triangle " << few[i] << " local "
                                                                 << stats.local;
        }
      }
    }
    // Each query alone at its own bundle size and one more: the sharpest test of a local answer.
    // On the jittered rows the Delaunay triangulation of the vertices near a query has triangles
    // at the ends of the region whose circumdisks reach over the query and hold vertices outside
    // the region; taken for empty disks, they meet one triangle too many (without in_k_bundle's
    // check that the local triangles it uses are Delaunay in the whole mesh, 12 of its 80 probes
    // answer yes at per-triangle value + 1).
    for (int trial = 0; trial < 40; ++trial) {
      const TriangleId q = in_domain[static_cast<std::size_t>(trial) * 7 % in_domain.size()];
      for (const std::uint32_t k : {per.per_triangle[q], per.per_triangle[q] + 1}) {
        if (k < 3) continue;
        KBundleStats stats;
        const std::vector<std::uint8_t> in = in_k_bundle(m, k, {q}, &stats, 1);
        EXPECT_EQ(in.at(0) != 0, per.per_triangle[q] >= k) << "k " << k << " triangle " << q << " local "
                                                             << stats.local;
      }
    }
  }
}

// A Delaunay-refined mesh (20°): the paper's lemma bounds its bundle number by 4π/α + 3 = 39.
// Points on a circle: every circumdisk of their Delaunay triangulation is (nearly) the whole circle
// and meets (nearly) every triangle. in_k_bundle must stop counting at k: every query is decided
// by the first circumdisk it meets, counted only up to k, so the floods' work is O(k) per query,
// not O(n) (the bound asserted is far below the n² the old full lists cost: 16 million here).
std::vector<Point> circle_points(std::size_t n, double rx = 1.0, double ry = 1.0) {
  std::vector<Point> pts(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2.0 * 3.14159265358979323846 * static_cast<double>(i) / static_cast<double>(n);
    pts[i] = {rx * std::cos(a), ry * std::sin(a)};
  }
  return pts;
}

std::vector<TriangleId> domain_triangles_of(const Mesh& m) {
  std::vector<TriangleId> q;
  for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
    if (m.in_domain(t)) q.push_back(t);
  }
  return q;
}

TEST(Bundle, InKBundleStopsCountingAtK) {
  const std::uint32_t k = 10;
  {
    // Small: the answers are those of the per-triangle values.
    const Mesh m = delaunay(circle_points(300));
    const std::vector<TriangleId> queries = domain_triangles_of(m);
    const BundleResult full = bundle_number(m, {.per_triangle = true});
    for (const std::uint32_t kk : {k, full.bundle_number, full.bundle_number + 1}) {
      const std::vector<std::uint8_t> in = in_k_bundle(m, kk, queries, nullptr, 1);
      for (std::size_t i = 0; i < queries.size(); ++i) {
        EXPECT_EQ(in[i] != 0, full.per_triangle[queries[i]] >= kk) << "k " << kk << " triangle " << queries[i];
      }
    }
  }
  const Mesh m = delaunay(circle_points(4000));
  const std::vector<TriangleId> queries = domain_triangles_of(m);
  for (const unsigned threads : {1u, 2u}) {
    KBundleStats st;
    const std::vector<std::uint8_t> in = in_k_bundle(m, k, queries, &st, threads);
    EXPECT_EQ(static_cast<std::size_t>(std::count(in.begin(), in.end(), 1)), queries.size());
    EXPECT_EQ(st.decided_by_circumdisks, queries.size());
    EXPECT_EQ(st.pencils_swept, 0u);
    EXPECT_EQ(st.flooded, 0u);  // no full list was built
    EXPECT_LE(st.disks_counted, queries.size());
    EXPECT_LE(st.flood_visits, 4 * std::size_t{k} * queries.size());
  }
}

// A brute-force check of a witness: the disk, shrunk by a relative 1e-9 (it is rounded and vertices
// lie on its boundary), contains no vertex and meets each triangle it names (exact rationals).
void expect_witness(const std::vector<Point>& pts, const std::vector<Tri>& tris, const BundleResult& r) {
  const Q cx(r.disk_center.x), cy(r.disk_center.y);
  const Q radius(r.disk_radius * (1.0 - 1e-9));
  const Q r2 = radius * radius;
  std::vector<std::uint8_t> used(pts.size(), 0);
  for (const Tri& t : tris) {
    for (const std::uint32_t v : t) used[v] = 1;
  }
  for (std::uint32_t v = 0; v < pts.size(); ++v) {
    if (!used[v]) continue;
    const Q dx = Q(pts[v].x) - cx, dy = Q(pts[v].y) - cy;
    EXPECT_GE(dx * dx + dy * dy, r2) << "witness contains vertex " << v;
  }
  EXPECT_EQ(r.triangles.size(), r.lower_bound);
  for (const std::uint32_t t : r.triangles) {
    const std::array<QPoint, 3> qt{QPoint{Q(pts[tris[t][0]].x), Q(pts[tris[t][0]].y)},
                                   QPoint{Q(pts[tris[t][1]].x), Q(pts[tris[t][1]].y)},
                                   QPoint{Q(pts[tris[t][2]].x), Q(pts[tris[t][2]].y)}};
    EXPECT_TRUE(disk_meets({cx, cy}, r2, qt)) << "witness misses triangle " << t;
  }
}

// With a candidate budget too small for the circumdisks of points on a circle or an ellipse, the
// result gives exact bounds (lower ≤ the exact number ≤ upper, the oracle's on the small inputs)
// with a witness for the lower one, checked by brute force; with a budget large enough, the exact
// result itself, witness included.
TEST(Bundle, BudgetGivesExactBoundsWithAWitness) {
  std::mt19937_64 rng(41);
  for (const double ry : {1.0, 0.5}) {
    for (const std::size_t n : {24u, 40u, 400u}) {
      SCOPED_TRACE(std::to_string(n) + " points, ry " + std::to_string(ry));
      std::vector<Point> pts = circle_points(n, 1.0, ry);
      // A few points inside: not every circumdisk is the whole circle.
      std::uniform_real_distribution<double> u(-0.3, 0.3);
      for (int i = 0; i < 3; ++i) pts.push_back({u(rng), u(rng) * ry});
      const std::vector<Tri> tris = finite_triangles(delaunay(pts));
      const BundleResult exact = bundle_number(pts, tris);
      EXPECT_TRUE(exact.exact);
      EXPECT_EQ(exact.lower_bound, exact.bundle_number);
      EXPECT_EQ(exact.upper_bound, exact.bundle_number);
      if (n <= 24) {
        EXPECT_EQ(exact.bundle_number, oracle(pts, tris).bundle);
      }
      const BundleResult cut = bundle_number(pts, tris, {.candidate_budget = 1});
      EXPECT_GT(cut.truncated_disks, 0u);
      EXPECT_LE(cut.lower_bound, exact.bundle_number);
      EXPECT_GE(cut.upper_bound, exact.bundle_number);
      EXPECT_EQ(cut.exact, cut.lower_bound == cut.upper_bound);
      EXPECT_EQ(cut.bundle_number, cut.lower_bound);
      EXPECT_LE(cut.upper_bound, tris.size());
      expect_witness(pts, tris, cut);
      const BundleResult roomy = bundle_number(pts, tris, {.candidate_budget = tris.size() * tris.size() * 4});
      EXPECT_TRUE(roomy.exact);
      EXPECT_EQ(roomy.truncated_disks, 0u);
      EXPECT_EQ(roomy.bundle_number, exact.bundle_number);
      EXPECT_EQ(roomy.triangles, exact.triangles);
      EXPECT_EQ(roomy.disk_center, exact.disk_center);
    }
  }
}

// On small random inputs (Delaunay, flipped, with holes) a budget changes nothing when it is not
// exhausted, and otherwise gives bounds around the unbudgeted exact answer.
TEST(Bundle, BudgetMatchesTheExactAnswerOnRandomInputs) {
  std::mt19937_64 rng(43);
  std::size_t cut_short = 0;
  for (int c = 0; c < 60; ++c) {
    const auto pts = random_points(8 + c % 30, rng);
    const auto tris = random_triangulation(pts, c % 3 == 0 ? 0 : 15, c % 4 == 0 ? 0.7 : 1.0, rng);
    const BundleResult exact = bundle_number(pts, tris);
    for (const std::size_t budget : {std::size_t{1}, std::size_t{64}, std::size_t{100000}}) {
      const BundleResult r = bundle_number(pts, tris, {.candidate_budget = budget});
      if (r.truncated_disks == 0) {
        EXPECT_TRUE(r.exact);
        EXPECT_EQ(r.bundle_number, exact.bundle_number);
        EXPECT_EQ(r.triangles, exact.triangles);
        EXPECT_EQ(r.disk_center, exact.disk_center);
        EXPECT_EQ(r.circumdisk_bound, exact.circumdisk_bound);
      } else {
        ++cut_short;
        EXPECT_LE(r.lower_bound, exact.bundle_number);
        EXPECT_GE(r.upper_bound, exact.bundle_number);
        if (r.exact) {
          EXPECT_EQ(r.bundle_number, exact.bundle_number);
        }
        expect_witness(pts, tris, r);
      }
    }
  }
  EXPECT_GT(cut_short, 0u);
}

TEST(Bundle, RefinedMeshRespectsAngleLemma) {
  const Pslg pslg = io::read_poly(std::string(MWST_DATA_DIR) + "/Superior.poly");
  Mesh m = constrained_delaunay(pslg);
  RefineOptions options;
  options.min_angle_deg = 20.0;
  refine(m, options);
  ASSERT_TRUE(validate(m).empty());
  const BundleResult r = bundle_number(m, {.per_triangle = true});
  EXPECT_LT(r.bundle_number, 39u);
  EXPECT_GE(r.bundle_number, r.circumdisk_bound);
  EXPECT_EQ(*std::max_element(r.per_triangle.begin(), r.per_triangle.end()), r.bundle_number);
}

// ---- the command line ----------------------------------------------------------------------------

struct CliRun {
  int exit_code = -1;
  std::string out, err;
};

CliRun run_mwst(const std::string& dir, const std::string& args) {
  const std::string out = dir + "/stdout.txt", err = dir + "/stderr.txt";
  const std::string command = std::string("cd '") + dir + "' && '" + MWST_BINARY + "' " + args + " > '" + out +
                              "' 2> '" + err + "'";
  const int status = std::system(command.c_str());
  CliRun r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream o(out), e(err);
  std::stringstream so, se;
  so << o.rdbuf();
  se << e.rdbuf();
  r.out = so.str();
  r.err = se.str();
  return r;
}

std::string temp_dir(const std::string& name) {
  const std::string dir = testing::TempDir() + "/mwst_bundle_" + std::to_string(::getpid()) + "_" + name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  f << text;
}

std::string counterexample_node() {
  std::string node = "7 2 0 0\n";
  for (std::size_t i = 0; i < kCounterexample.size(); ++i) {
    node += std::to_string(i + 1) + " " + std::to_string(kCounterexample[i].x) + " " +
            std::to_string(kCounterexample[i].y) + "\n";
  }
  return node;
}

TEST(BundleCli, JsonWitnessOfTheCounterexample) {
  const std::string dir = temp_dir("json");
  write_text(dir + "/c.node", counterexample_node());
  io::write_mesh(delaunay(kCounterexample), dir + "/c.1");
  const CliRun r = run_mwst(dir, "bundle c.node c.1 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("bundle_number").get<int>(), 6);
  EXPECT_EQ(j.at("circumdisk_bound").get<int>(), 5);
  const auto triangles = j.at("triangles").get<std::vector<int>>();
  EXPECT_EQ(triangles, (std::vector<int>{1, 2, 3, 4, 5, 6}));  // numbered from 1
  const double x = j.at("disk").at("x").get<double>(), y = j.at("disk").at("y").get<double>();
  const double radius = j.at("disk").at("r").get<double>();
  for (const Point& p : kCounterexample) EXPECT_GE(std::hypot(p.x - x, p.y - y), radius * (1 - 1e-9));
  const CliRun text = run_mwst(dir, "bundle c.node c.1");
  EXPECT_EQ(text.exit_code, 0);
  EXPECT_NE(text.out.find("bundle number 6"), std::string::npos) << text.out;
  std::filesystem::remove_all(dir);
}

TEST(BundleCli, OverlappingTrianglesAreBadInput) {
  const std::string dir = temp_dir("overlap");
  write_text(dir + "/s.node", "4 2 0 0\n1 0 0\n2 2 0\n3 0 2\n4 2 2\n");
  write_text(dir + "/s.1.node", "4 2 0 0\n1 0 0\n2 2 0\n3 0 2\n4 2 2\n");
  write_text(dir + "/s.1.ele", "2 3 0\n1 1 2 3\n2 1 4 3\n");
  const CliRun r = run_mwst(dir, "bundle s.node s.1 --json");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("mwst: s.1.ele: "), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_EQ(run_mwst(dir, "bundle s.node").exit_code, 2);  // PREFIX missing
  std::filesystem::remove_all(dir);
}

TEST(BundleCli, TriangulateReportsTheBundleNumber) {
  const std::string dir = temp_dir("triangulate");
  write_text(dir + "/c.node", counterexample_node());
  const CliRun r = run_mwst(dir, "triangulate c.node --bundle --json report.json --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream f(dir + "/report.json");
  const nlohmann::json j = nlohmann::json::parse(f);
  EXPECT_EQ(j.at("bundle_number").get<int>(), 6);
  EXPECT_EQ(j.at("bundle_circumdisk_bound").get<int>(), 5);
  EXPECT_GT(j.at("bundle_disk").at("r").get<double>(), 0.0);
  EXPECT_TRUE(j.at("seconds").contains("bundle"));
  std::filesystem::remove_all(dir);
}

// `mwst bundle` puts its large arrays on huge pages (src/cli/large_allocations.cpp): every block
// of 4 MiB or more comes from support::allocate_on_huge_pages. Such a block starts on a 2 MiB
// boundary, holds what is written to it and is released by free().
TEST(BundleCli, HugePageBlocksAreAlignedAndHoldTheirValues) {
  for (const std::size_t bytes : {2 * support::kHugePage, 5 * support::kHugePage + 12345}) {
    void* block = support::allocate_on_huge_pages(bytes);
    ASSERT_NE(block, nullptr);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(block) % support::kHugePage, 0u);
    auto* words = static_cast<std::uint32_t*>(block);
    const std::size_t count = bytes / sizeof(std::uint32_t);
    for (std::size_t i = 0; i < count; ++i) words[i] = static_cast<std::uint32_t>(i * 2654435761u);
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < count; ++i) wrong += words[i] != static_cast<std::uint32_t>(i * 2654435761u) ? 1 : 0;
    EXPECT_EQ(wrong, 0u);
    std::free(block);
  }
}

// And with them (a mesh whose arrays run to megabytes) the command gives what the library gives
// for the same triangles and budget: the number, the bounds and the witness.
TEST(BundleCli, LargeMeshOnHugePagesMatchesTheLibrary) {
  const std::string dir = temp_dir("large");
  std::mt19937_64 rng(20261127);
  const std::vector<Point> pts = random_points(60000, rng);
  std::ostringstream node;
  node.precision(17);
  node << pts.size() << " 2 0 0\n";
  for (std::size_t i = 0; i < pts.size(); ++i) node << i + 1 << ' ' << pts[i].x << ' ' << pts[i].y << '\n';
  write_text(dir + "/u.node", node.str());
  io::write_mesh(delaunay(pts), dir + "/u.1");
  const CliRun r = run_mwst(dir, "bundle u.node u.1 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  io::MeshFiles mesh = io::read_mesh(dir + "/u.1");
  BundleOptions options;
  options.candidate_budget = 12 * mesh.triangles.size() + (std::size_t{1} << 20);  // the command's default
  const BundleResult expected = bundle_number(std::move(mesh.points), std::move(mesh.triangles), options);
  EXPECT_EQ(j.at("bundle_number").get<std::uint32_t>(), expected.bundle_number);
  EXPECT_EQ(j.at("lower_bound").get<std::uint32_t>(), expected.lower_bound);
  EXPECT_EQ(j.at("upper_bound").get<std::uint32_t>(), expected.upper_bound);
  EXPECT_EQ(j.at("disk").at("x").get<double>(), expected.disk_center.x);
  EXPECT_EQ(j.at("disk").at("y").get<double>(), expected.disk_center.y);
  EXPECT_EQ(j.at("disk").at("r").get<double>(), expected.disk_radius);
  std::vector<std::uint32_t> triangles;
  for (const std::uint32_t t : expected.triangles) triangles.push_back(t + 1);
  EXPECT_EQ(j.at("triangles").get<std::vector<std::uint32_t>>(), triangles);
  EXPECT_GT(expected.bundle_number, 0u);
  std::filesystem::remove_all(dir);
}

// `mwst bundle` reports the bounds when its budget is exhausted, and the exact number otherwise.
TEST(BundleCli, BudgetExhaustedReportsBounds) {
  const std::string dir = temp_dir("budget");
  std::ostringstream node;
  const std::vector<Point> pts = circle_points(200, 1.0, 0.5);
  node.precision(17);
  node << pts.size() << " 2 0 0\n";
  for (std::size_t i = 0; i < pts.size(); ++i) node << i + 1 << ' ' << pts[i].x << ' ' << pts[i].y << '\n';
  write_text(dir + "/e.node", node.str());
  io::write_mesh(delaunay(pts), dir + "/e.1");
  const CliRun cut_run = run_mwst(dir, "bundle e.node e.1 --json --candidate-budget 1");
  const CliRun full_run = run_mwst(dir, "bundle e.node e.1 --json");
  ASSERT_EQ(cut_run.exit_code, 0) << cut_run.err;
  ASSERT_EQ(full_run.exit_code, 0) << full_run.err;
  const nlohmann::json cut = nlohmann::json::parse(cut_run.out), full = nlohmann::json::parse(full_run.out);
  EXPECT_TRUE(full.at("exact").get<bool>());
  EXPECT_EQ(full.at("lower_bound"), full.at("bundle_number"));
  EXPECT_EQ(full.at("upper_bound"), full.at("bundle_number"));
  EXPECT_LE(cut.at("lower_bound").get<long long>(), full.at("bundle_number").get<long long>());
  EXPECT_GE(cut.at("upper_bound").get<long long>(), full.at("bundle_number").get<long long>());
  EXPECT_EQ(cut.at("exact").get<bool>(), cut.at("lower_bound") == cut.at("upper_bound"));
  EXPECT_EQ(cut.at("triangles").size(), cut.at("lower_bound").get<std::size_t>());
  const CliRun text = run_mwst(dir, "bundle e.node e.1 --candidate-budget 1");
  EXPECT_EQ(text.exit_code, 0);
  if (!cut.at("exact").get<bool>()) {
    EXPECT_NE(text.out.find("bundle number between"), std::string::npos) << text.out;
  }
  std::filesystem::remove_all(dir);
}

TEST(Bundle, InputErrors) {
  const std::vector<Point> pts = {{0, 0}, {2, 0}, {0, 2}, {2, 2}, {1, 0}, {0.5, 0.5}};
  EXPECT_THROW(bundle_number(pts, {Tri{0, 1, 7}}), InputError);               // index out of range
  EXPECT_THROW(bundle_number(pts, {Tri{0, 1, 4}}), InputError);               // collinear corners
  EXPECT_THROW(bundle_number(pts, {Tri{0, 1, 2}, Tri{0, 2, 1}}), InputError); // repeated
  EXPECT_THROW(bundle_number(pts, {Tri{0, 1, 2}, Tri{0, 3, 2}}), InputError); // overlapping
  EXPECT_THROW(bundle_number(pts, {Tri{0, 1, 2}, Tri{1, 3, 2}, Tri{0, 5, 4}}), InputError);  // vertex inside
  EXPECT_THROW(bundle_number(pts, {Tri{0, 1, 2}, Tri{4, 3, 1}}), InputError);  // vertex on an edge
  const std::vector<Point> twin = {{0, 0}, {1, 0}, {0, 1}, {0, 0}, {1, 1}};
  EXPECT_THROW(bundle_number(twin, {Tri{0, 1, 2}, Tri{3, 4, 2}}), InputError);  // coincident points
}

}  // namespace
}  // namespace mwst
