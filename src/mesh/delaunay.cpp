// Delaunay triangulation of a point set: incremental insertion (Lawson flips) in Hilbert-curve
// order with a walking point location that starts at the previous insertion.
//
// Why this algorithm: Amenta, Choi and Rote ("Incremental constructions con BRIO", 2003) and
// Buchin's analysis show that inserting along a space-filling curve keeps walks O(1) on average, and
// CGAL's spatial-sort + walk measured twice as fast as Triangle's divide and conquer on our
// machines. Points are copied in curve order so that the vertices a walk touches are neighbours
// in memory; ids are mapped back to the input order at the end. The triangle array is reserved
// exactly (2n − 2 triangles, ghosts included, for n vertices) so it never reallocates.
#include <algorithm>
#include <chrono>
#include <cstring>
#include <limits>
#include <numeric>

#include "mwst/delaunay.hpp"
#include "mwst/error.hpp"

namespace mwst {

namespace {

// Position of the cell (x, y) along the Hilbert curve of a 2^16 × 2^16 grid. The curve's state is
// one of four symmetries of the square (swap the axes, reflect both), which commute and are
// involutions, so a 2-bit state and a 16-entry table replace the branches of the textbook loop.
struct HilbertTable {
  std::uint8_t digit[16];
  std::uint8_t next[16];
  constexpr HilbertTable() : digit(), next() {
    for (unsigned state = 0; state < 4; ++state) {
      for (unsigned q = 0; q < 4; ++q) {
        unsigned bx = q >> 1, by = q & 1;
        if (state & 1) std::swap(bx, by);  // swap the axes
        if (state & 2) {                   // reflect both
          bx ^= 1;
          by ^= 1;
        }
        digit[state * 4 + q] = static_cast<std::uint8_t>((3 * bx) ^ by);
        unsigned ns = state;
        if (by == 0) ns ^= 1u | (bx ? 2u : 0u);
        next[state * 4 + q] = static_cast<std::uint8_t>(ns);
      }
    }
  }
};
inline constexpr HilbertTable kHilbert{};

inline std::uint32_t hilbert_index16(std::uint32_t x, std::uint32_t y) {
  std::uint32_t d = 0, state = 0;
  for (int level = 15; level >= 0; --level) {
    const std::uint32_t q = (((x >> level) & 1u) << 1) | ((y >> level) & 1u);
    const std::uint32_t k = (state << 2) | q;
    d = (d << 2) | kHilbert.digit[k];
    state = kHilbert.next[k];
  }
  return d;
}

// Sorts idx[0, count) along the Hilbert curve of the bounding box of their points, stably.
// Cells that receive many points (clustered inputs such as Kuzmin's distribution, where most points
// fall into one cell of a grid over the whole bounding box) are sorted again inside their own box,
// so the order adapts to any distribution (an adaptive variant of the multiscale sort of
// Amenta–Choi–Rote and CGAL's spatial_sort).
void hilbert_sort(const Point* pts, std::uint32_t* idx, std::size_t count,
                  std::vector<std::uint64_t>& words, std::vector<std::uint64_t>& buffer, int depth) {
  if (count < 2) return;
  double xmin = pts[idx[0]].x, xmax = xmin, ymin = pts[idx[0]].y, ymax = ymin;
  for (std::size_t i = 1; i < count; ++i) {
    const Point& p = pts[idx[i]];
    xmin = std::min(xmin, p.x);
    xmax = std::max(xmax, p.x);
    ymin = std::min(ymin, p.y);
    ymax = std::max(ymax, p.y);
  }
  // Halving before subtracting keeps the extent finite near the coordinate range limit.
  const double extent = std::max(xmax * 0.5 - xmin * 0.5, ymax * 0.5 - ymin * 0.5);
  if (!(extent > 0.0)) return;  // all points coincide
  const double cells = 65535.0;
  const double scale = cells / extent * 0.5;
  words.resize(count);
  buffer.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Point& p = pts[idx[i]];
    const double fx = (p.x * 0.5 - xmin * 0.5) * scale;
    const double fy = (p.y * 0.5 - ymin * 0.5) * scale;
    const auto gx = static_cast<std::uint32_t>(std::min(cells, std::max(0.0, fx)));
    const auto gy = static_cast<std::uint32_t>(std::min(cells, std::max(0.0, fy)));
    words[i] = (static_cast<std::uint64_t>(hilbert_index16(gx, gy)) << 32) | idx[i];
  }
  if (count < (std::size_t{1} << 14)) {
    std::sort(words.begin(), words.begin() + static_cast<std::ptrdiff_t>(count));
  } else {
    // LSD radix sort on the 32-bit key, 16 bits per pass (stable: ties keep index order).
    std::vector<std::uint32_t> count_lo(1u << 16, 0u), count_hi(1u << 16, 0u);
    for (std::size_t i = 0; i < count; ++i) {
      ++count_lo[(words[i] >> 32) & 0xFFFFu];
      ++count_hi[words[i] >> 48];
    }
    std::uint32_t sum_lo = 0, sum_hi = 0;
    for (unsigned k = 0; k < (1u << 16); ++k) {
      const std::uint32_t a = count_lo[k], b = count_hi[k];
      count_lo[k] = sum_lo;
      count_hi[k] = sum_hi;
      sum_lo += a;
      sum_hi += b;
    }
    for (std::size_t i = 0; i < count; ++i) buffer[count_lo[(words[i] >> 32) & 0xFFFFu]++] = words[i];
    for (std::size_t i = 0; i < count; ++i) words[count_hi[buffer[i] >> 48]++] = buffer[i];
  }
  for (std::size_t i = 0; i < count; ++i) idx[i] = static_cast<std::uint32_t>(words[i]);
  // Re-sort crowded cells inside their own bounding box.
  constexpr std::size_t kCrowded = 64;
  constexpr int kMaxDepth = 6;
  if (depth >= kMaxDepth) return;
  std::vector<std::pair<std::size_t, std::size_t>> runs;
  for (std::size_t i = 0; i < count;) {
    std::size_t j = i + 1;
    while (j < count && (words[j] >> 32) == (words[i] >> 32)) ++j;
    if (j - i > kCrowded) runs.emplace_back(i, j - i);
    i = j;
  }
  for (const auto& [start, length] : runs) {
    hilbert_sort(pts, idx + start, length, words, buffer, depth + 1);
  }
}

// Returns the input indices in adaptive Hilbert-curve order.
std::vector<std::uint32_t> hilbert_order(const std::vector<Point>& points) {
  std::vector<std::uint32_t> order(points.size());
  std::iota(order.begin(), order.end(), 0u);
  std::vector<std::uint64_t> words, buffer;
  hilbert_sort(points.data(), order.data(), order.size(), words, buffer, 0);
  return order;
}

// Builds the first real triangle on vertices (a, b, c), counter-clockwise, with its three ghosts.
void make_first_triangle(Mesh& m, VertexId a, VertexId b, VertexId c) {
  const TriangleId t = m.new_triangle();
  const TriangleId gab = m.new_triangle(), gbc = m.new_triangle(), gca = m.new_triangle();
  auto& T = m.triangles;
  T[t].v = {a, b, c};
  T[gab].v = {b, a, kInfinite};
  T[gbc].v = {c, b, kInfinite};
  T[gca].v = {a, c, kInfinite};
  auto link = [&](Handle x, Handle y) {
    T[x >> 2].n[x & 3] = y;
    T[y >> 2].n[y & 3] = x;
  };
  link(make_handle(t, 2), make_handle(gab, 2));  // a→b / b→a
  link(make_handle(t, 0), make_handle(gbc, 2));  // b→c / c→b
  link(make_handle(t, 1), make_handle(gca, 2));  // c→a / a→c
  link(make_handle(gab, 0), make_handle(gca, 1));  // a→∞ / ∞→a
  link(make_handle(gab, 1), make_handle(gbc, 0));  // ∞→b / b→∞
  link(make_handle(gbc, 1), make_handle(gca, 0));  // ∞→c / c→∞
}

}  // namespace

Mesh delaunay(std::vector<Point> points, DelaunayStats* stats) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const std::size_t n = points.size();
  if (n >= std::numeric_limits<std::uint32_t>::max() / 4) {
    throw InputError("", 0, "too many points (" + std::to_string(n) + ")");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!in_supported_range(points[i])) {
      throw InputError("", 0,
                       "point " + std::to_string(i + 1) +
                           " has a coordinate outside the supported range (0 or magnitude in "
                           "[1e-50, 1e50])");
    }
  }
  if (n < 3) throw InputError("", 0, "fewer than three points (" + std::to_string(n) + ")");

  const std::vector<std::uint32_t> order = hilbert_order(points);
  const auto t1 = Clock::now();

  // Work on a copy in curve order (vertex id i here = order[i] in the input).
  Mesh m;
  m.points.resize(n);
  for (std::size_t i = 0; i < n; ++i) m.points[i] = points[order[i]];
  m.triangles.reserve(2 * n);
  m.flags.reserve(2 * n);

  // The first triangle: the first point, the next distinct one, the next not collinear with them.
  std::size_t second = 1;
  while (second < n && m.points[second] == m.points[0]) ++second;
  if (second == n) throw InputError("", 0, "fewer than three distinct points (all points coincide)");
  std::size_t third = second + 1;
  while (third < n && orient2d(m.points[0], m.points[second], m.points[third]) == 0) ++third;
  if (third == n) {
    // Distinguish "two distinct points" from "collinear".
    std::size_t distinct = 2;
    for (std::size_t i = second + 1; i < n && distinct < 3; ++i) {
      if (!(m.points[i] == m.points[0]) && !(m.points[i] == m.points[second])) distinct = 3;
    }
    throw InputError("", 0, distinct < 3 ? "fewer than three distinct points"
                                         : "all points are collinear");
  }
  const auto s = static_cast<VertexId>(second), r = static_cast<VertexId>(third);
  if (orient2d(m.points[0], m.points[s], m.points[r]) > 0) {
    make_first_triangle(m, 0, s, r);
  } else {
    make_first_triangle(m, 0, r, s);
  }

  std::vector<VertexId> kept(n, kNone);  // for duplicates: the curve-order id they merge into
  kept[0] = 0;
  kept[s] = s;
  kept[r] = r;
  Handle hint = make_handle(0, 0);
  for (VertexId v = 1; v < n; ++v) {
    if (v == s || v == r) continue;
    kept[v] = m.insert_vertex(v, hint, &hint);
  }
  const auto t2 = Clock::now();

  // Map the ids back to the input numbering.
  for (Triangle& t : m.triangles) {
    for (VertexId& v : t.v) {
      if (v != kInfinite) v = order[v];
    }
  }
  m.points = std::move(points);
  m.vertex_kind.assign(n, VertexKind::kInput);
  m.vertex_marker.assign(n, 0);
  m.input_vertex_count = static_cast<std::uint32_t>(n);
  for (VertexId v = 0; v < n; ++v) {
    if (kept[v] != v) {
      m.vertex_kind[order[v]] = VertexKind::kDuplicate;
      m.duplicates.emplace_back(order[v], order[kept[v]]);
    }
  }
  std::sort(m.duplicates.begin(), m.duplicates.end());
  if (stats) {
    stats->duplicates = m.duplicates.size();
    stats->seconds_sort = std::chrono::duration<double>(t1 - t0).count();
    stats->seconds_insert = std::chrono::duration<double>(t2 - t1).count();
  }
  return m;
}

}  // namespace mwst
