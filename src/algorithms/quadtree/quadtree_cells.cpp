// Triangulating one quadtree cell (Bern, Eppstein, Gilbert, "Provably good mesh generation", 1994,
// section 3: "triangulate each square by a small case table"; Boyacı, Erten, Üngör use it as QTR).
//
// Two tools, both over the boundary vertices of a cell only (no interior Steiner point):
//  - triangulate_polygon(): the max–min-angle triangulation of a small simple polygon by dynamic
//    programming over its diagonals (Klincsek 1980's O(k³) scheme for decomposable objectives). It
//    serves cells whose corners were warped onto input vertices or segments and the pieces of cells
//    cut along a segment. Validity is decided exactly (orient2d); only the choice among valid
//    triangulations uses rounded angles.
//  - quadtree_case_table(): the same program run once on the unit square with each of the 16
//    patterns of side midpoints; untouched leaves look their triangles up.
//
// Quality measure: the sine of a triangle's smallest angle, |cross| / (|e2|·|e3|) with e2, e3 the
// two longer edges. The smallest angle is at most 60°, where the sine is increasing, so comparing
// sines compares smallest angles.
#include <algorithm>
#include <cmath>
#include <limits>

#include "mwst/algorithms/quadtree.hpp"
#include "algorithms/quadtree/cell_triangulation.hpp"
#include "geometry/segments.hpp"

namespace mwst::detail {

namespace {

constexpr std::size_t kMaxPolygon = 64;

// Squared distance (as squared_distance(), inline: the dynamic program below evaluates it often).
inline double squared_length(const Point& a, const Point& b) {
  const double dx = a.x - b.x, dy = a.y - b.y;
  return dx * dx + dy * dy;
}

// Sine of the smallest angle of triangle (a, b, c) given its squared sides ab, bc, ca (rounded; 0
// for a degenerate triangle).
inline double min_angle_sine(const Point& a, const Point& b, const Point& c, double ab, double bc, double ca) {
  const double cross = std::fabs((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
  // Product of the two longer squared edges = product of all three / the shortest.
  const double shortest = std::min({ab, bc, ca});
  const double longer = ab * bc * ca / shortest;
  if (!(longer > 0.0)) return 0.0;
  return cross / std::sqrt(longer);
}

double min_angle_sine(const Point& a, const Point& b, const Point& c) {
  return min_angle_sine(a, b, c, squared_length(a, b), squared_length(b, c), squared_length(c, a));
}

// The general program below (any k from 4 to kMaxPolygon). Kept out of line: its tables take
// about 100 KB of stack, whose pages the compiler probes on every call.
[[gnu::noinline]] bool max_min_general(const std::vector<Point>& q,
                                       std::vector<std::array<std::uint8_t, 3>>& out, double& quality_out);

// The program for a weakly convex quadrilateral (nine warped point-set cells in ten: a square with
// one or more corners moved and no side midpoint), step for step what max_min_general() does with
// k = 4 (its minima with +inf and sums with 0 left out: they change no double), so it picks the
// same diagonal and the same quality.
// The turns o[i] = orient2d(q[i-1], q[i], q[i+1]) are all the program needs: it is weakly convex
// when none is negative (the fan test orient2d(q0, q2, q3) is o[3] turned cyclically, which keeps
// an exact sign), and its candidate triangles (0 1 2), (1 2 3), (0 1 3), (0 2 3) are these turns
// at vertices 1, 2, 0 and 3. Returns false if the program has no triangulation.
bool max_min_quadrilateral(const std::vector<Point>& q, const int (&o)[4],
                           std::vector<std::array<std::uint8_t, 3>>& out, double& quality_out) {
  const Point &q0 = q[0], &q1 = q[1], &q2 = q[2], &q3 = q[3];
  const double s01 = squared_length(q0, q1), s02 = squared_length(q0, q2), s03 = squared_length(q0, q3);
  const double s12 = squared_length(q1, q2), s13 = squared_length(q1, q3), s23 = squared_length(q2, q3);
  // Sub-polygons 0..2 (closed by diagonal 02, apex 1) and 1..3 (diagonal 13, apex 2): their best
  // quality (−1: none) and total diagonal length. A diagonal joining two equal points is no chord.
  double best02 = -1.0, length02 = 0.0, best13 = -1.0, length13 = 0.0;
  if (!(q0 == q2) && o[1] > 0) {
    best02 = min_angle_sine(q0, q1, q2, s01, s12, s02);
    length02 = std::sqrt(s02);
  }
  if (!(q1 == q3) && o[2] > 0) {
    best13 = min_angle_sine(q1, q2, q3, s12, s23, s13);
    length13 = std::sqrt(s13);
  }
  // The whole polygon 0..3: apex 1 (diagonal 13), then apex 2 (diagonal 02), as the program tries
  // them; ties within rounding go to the lighter one.
  constexpr double tolerance = 1e-12;
  double current = -1.0, best_length = 0.0;
  unsigned split = 0;
  if (best13 >= 0.0 && o[0] > 0) {
    current = std::min(min_angle_sine(q0, q1, q3, s01, s13, s03), best13);
    best_length = length13;
    split = 1;
  }
  if (best02 >= 0.0 && !(current >= 0.0 && best02 < current - tolerance) && o[3] > 0) {
    const double quality = std::min(min_angle_sine(q0, q2, q3, s02, s23, s03), best02);
    const bool better = quality > current + tolerance ||
                        (quality >= current - tolerance && length02 < best_length - 1e-12 * length02);
    if (current < 0.0 || better) {
      current = quality;
      split = 2;
    }
  }
  if (current < 0.0) return false;
  // (The order in which the program unwinds its choices.)
  if (split == 1) {
    out.push_back({0, 1, 3});
    out.push_back({1, 2, 3});
  } else {
    out.push_back({0, 2, 3});
    out.push_back({0, 1, 2});
  }
  quality_out = current;
  return true;
}

// triangulate_polygon(), also giving the smallest-angle sine of the triangles it appends (the
// program's value for the whole polygon: the same doubles, so no second pass over them).
bool max_min_triangulation(const std::vector<Point>& q, std::vector<std::array<std::uint8_t, 3>>& out,
                           double& quality_out) {
  const std::size_t k = q.size();
  if (k < 3 || k > kMaxPolygon) return false;
  if (k == 3) {
    if (orient2d(q[0], q[1], q[2]) <= 0) return false;
    out.push_back({0, 1, 2});
    quality_out = min_angle_sine(q[0], q[1], q[2]);
    return true;
  }
  if (k == 4) {
    const int o[4] = {orient2d(q[3], q[0], q[1]), orient2d(q[0], q[1], q[2]), orient2d(q[1], q[2], q[3]),
                      orient2d(q[2], q[3], q[0])};
    if (o[0] >= 0 && o[1] >= 0 && o[2] >= 0 && o[3] >= 0) {
      return max_min_quadrilateral(q, o, out, quality_out);
    }
  }
  return max_min_general(q, out, quality_out);
}

bool max_min_general(const std::vector<Point>& q, std::vector<std::array<std::uint8_t, 3>>& out,
                     double& quality_out) {
  const std::size_t k = q.size();
  // ok(i, j), i < j: ij is a polygon edge or a diagonal strictly inside the polygon.
  // Flat k × k tables (entry i·k + j), deliberately left uninitialised: every entry is written
  // before it is read, and clearing 64 × 64 tables per cell dominated the run time.
  std::array<bool, kMaxPolygon * kMaxPolygon> ok;
  auto at = [k](std::size_t i, std::size_t j) { return i * k + j; };
  auto prev = [k](std::size_t i) { return i == 0 ? k - 1 : i - 1; };
  auto next = [k](std::size_t i) { return i + 1 == k ? 0 : i + 1; };
  // A weakly convex polygon (no reflex vertex, winding once: every triangle of the fan from q[0]
  // is not clockwise) has every chord inside it; a chord running along a straight side leaves a
  // collinear sub-polygon, which the program below rejects (no strictly counter-clockwise
  // triangle), so the O(k³) diagonal tests can be skipped. Warped point-set cells are of this kind.
  bool convex = true;
  for (std::size_t i = 0; i < k && convex; ++i) {
    if (orient2d(q[prev(i)], q[i], q[next(i)]) < 0) convex = false;
    if (i >= 1 && i + 1 < k && orient2d(q[0], q[i], q[i + 1]) < 0) convex = false;
  }
  for (std::size_t i = 0; i < k; ++i) {
    for (std::size_t j = i + 1; j < k; ++j) {
      if (j == i + 1 || (i == 0 && j == k - 1)) {
        ok[at(i, j)] = true;
        continue;
      }
      ok[at(i, j)] = false;
      if (q[i] == q[j]) continue;
      if (convex) {
        ok[at(i, j)] = true;
        continue;
      }
      // (A chord through a corner between i and j: is_polygon_diagonal, geometry/segments.hpp.)
      ok[at(i, j)] = is_polygon_diagonal(q, k, i, j);
    }
  }
  // Squared lengths of all chords (entry i·k + j, i < j), each computed once.
  std::array<double, kMaxPolygon * kMaxPolygon> squared;
  for (std::size_t i = 0; i < k; ++i) {
    for (std::size_t j = i + 1; j < k; ++j) squared[at(i, j)] = squared_length(q[i], q[j]);
  }
  // best(i, j): the best smallest-angle sine over triangulations of the sub-polygon i..j (closed by
  // the chord ij); length(i, j) the total length of its diagonals; split(i, j) the apex on ij.
  constexpr double kNoTriangulation = -1.0;
  std::array<double, kMaxPolygon * kMaxPolygon> best;
  std::array<double, kMaxPolygon * kMaxPolygon> length;
  std::array<std::uint8_t, kMaxPolygon * kMaxPolygon> split;
  for (std::size_t i = 0; i + 1 < k; ++i) {
    best[at(i, i + 1)] = std::numeric_limits<double>::infinity();
    length[at(i, i + 1)] = 0.0;
  }
  for (std::size_t gap = 2; gap < k; ++gap) {
    for (std::size_t i = 0; i + gap < k; ++i) {
      const std::size_t j = i + gap;
      best[at(i, j)] = kNoTriangulation;
      if (!ok[at(i, j)]) continue;
      const double chord = (gap == k - 1) ? 0.0 : std::sqrt(squared[at(i, j)]);
      double best_length = 0.0;
      for (std::size_t m = i + 1; m < j; ++m) {
        if (!ok[at(i, m)] || !ok[at(m, j)]) continue;
        const double left = best[at(i, m)], right = best[at(m, j)];
        if (left < 0.0 || right < 0.0) continue;
        // Ties (within rounding of symmetric configurations) go to the lighter triangulation.
        const double tolerance = 1e-12;
        // A candidate whose sub-polygons are already worse than the best found cannot win (its
        // quality is at most theirs): its triangle need not be measured.
        const double current = best[at(i, j)];
        if (current >= 0.0 && std::min(left, right) < current - tolerance) continue;
        if (orient2d(q[i], q[m], q[j]) <= 0) continue;
        const double quality =
            std::min({min_angle_sine(q[i], q[m], q[j], squared[at(i, m)], squared[at(m, j)], squared[at(i, j)]),
                      left, right});
        const double total = length[at(i, m)] + length[at(m, j)] + chord;
        const bool better = quality > current + tolerance ||
                            (quality >= current - tolerance && total < best_length - 1e-12 * total);
        if (current < 0.0 || better) {
          best[at(i, j)] = quality;
          best_length = total;
          split[at(i, j)] = static_cast<std::uint8_t>(m);
        }
      }
      length[at(i, j)] = best_length;
    }
  }
  if (best[at(0, k - 1)] < 0.0) return false;
  // Unwind the choices.
  std::array<std::pair<std::uint8_t, std::uint8_t>, kMaxPolygon> stack{};
  std::size_t top = 0;
  stack[top++] = {0, static_cast<std::uint8_t>(k - 1)};
  while (top > 0) {
    const auto [i, j] = stack[--top];
    if (j - i < 2) continue;
    const std::uint8_t m = split[at(i, j)];
    out.push_back({i, m, j});
    stack[top++] = {i, m};
    stack[top++] = {m, j};
  }
  quality_out = best[at(0, k - 1)];
  return true;
}

}  // namespace

bool triangulate_polygon(const std::vector<Point>& q, std::vector<std::array<std::uint8_t, 3>>& out) {
  double quality = 0.0;
  return max_min_triangulation(q, out, quality);
}

bool triangulate_polygon_quality(const std::vector<Point>& polygon,
                                 std::vector<std::array<std::uint8_t, 3>>& out, double& quality, bool general) {
  if (!general || polygon.size() < 4 || polygon.size() > kMaxPolygon) {
    return max_min_triangulation(polygon, out, quality);
  }
  return max_min_general(polygon, out, quality);
}

double triangulation_quality(const std::vector<Point>& polygon,
                             const std::vector<std::array<std::uint8_t, 3>>& triangles) {
  double q = std::numeric_limits<double>::infinity();
  for (const auto& t : triangles) q = std::min(q, min_angle_sine(polygon[t[0]], polygon[t[1]], polygon[t[2]]));
  return q;
}

bool centroid_fan(const std::vector<Point>& polygon, Point& centre, double& quality) {
  const std::size_t k = polygon.size();
  if (k < 3) return false;
  double x = 0.0, y = 0.0;
  for (const Point& p : polygon) {
    x += p.x;
    y += p.y;
  }
  centre = {x / static_cast<double>(k), y / static_cast<double>(k)};
  quality = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < k; ++i) {
    const Point& a = polygon[i];
    const Point& b = polygon[i + 1 == k ? 0 : i + 1];
    if (orient2d(centre, a, b) <= 0) return false;
    quality = std::min(quality, min_angle_sine(centre, a, b));
  }
  return true;
}

bool triangulate_piece(const std::vector<Point>& polygon, std::vector<std::array<std::uint8_t, 3>>& out,
                       Point& centre, bool& used_centre) {
  // Sine of 20°: below it the centre is tried.
  constexpr double kFanBelow = 0.34202014332566873;
  used_centre = false;
  const std::size_t start = out.size();
  // (The smallest-angle sine of the new triangles, from the program.)
  double quality = -1.0;
  const bool triangulated = max_min_triangulation(polygon, out, quality);
  if (!triangulated) quality = -1.0;
  double fan_quality = 0.0;
  if (quality < kFanBelow && polygon.size() < kMaxPolygon && centroid_fan(polygon, centre, fan_quality) &&
      fan_quality > quality) {
    out.resize(start);
    const auto k = static_cast<std::uint8_t>(polygon.size());
    for (std::uint8_t i = 0; i < k; ++i) out.push_back({k, i, static_cast<std::uint8_t>((i + 1) % k)});
    used_centre = true;
    return true;
  }
  return triangulated;
}

const std::array<std::vector<std::array<std::uint8_t, 3>>, 16>& quadtree_case_table() {
  static const auto table = [] {
    std::array<std::vector<std::array<std::uint8_t, 3>>, 16> t;
    // Slots around the unit square, counter-clockwise from the lower-left corner.
    constexpr Point kSlot[8] = {{0, 0}, {0.5, 0}, {1, 0}, {1, 0.5}, {1, 1}, {0.5, 1}, {0, 1}, {0, 0.5}};
    for (unsigned mask = 0; mask < 16; ++mask) {
      std::vector<Point> polygon;
      std::vector<std::uint8_t> slot_of;
      for (std::uint8_t s = 0; s < 8; ++s) {
        // Odd slots are the midpoints of sides (s - 1) / 2: bottom, right, top, left.
        if ((s & 1) != 0 && (mask & (1u << (s / 2))) == 0) continue;
        polygon.push_back(kSlot[s]);
        slot_of.push_back(s);
      }
      std::vector<std::array<std::uint8_t, 3>> local;
      triangulate_polygon(polygon, local);
      for (const auto& tri : local) t[mask].push_back({slot_of[tri[0]], slot_of[tri[1]], slot_of[tri[2]]});
    }
    return t;
  }();
  return table;
}

}  // namespace mwst::detail
