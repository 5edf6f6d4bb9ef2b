// Delaunay triangulation of a point set: incremental insertion (Lawson flips) in Hilbert-curve
// order with a walking point location that starts at the previous insertion.
//
// Why this algorithm: Amenta, Choi and Rote ("Incremental constructions con BRIO", 2003) and
// Buchin's analysis show that inserting along a space-filling curve keeps walks O(1) on average, and
// CGAL's spatial-sort + walk measured twice as fast as Triangle's divide and conquer on our
// machines. Points are copied in curve order so that the vertices a walk touches are neighbours
// in memory; ids are mapped back to the input order at the end. The triangle array is reserved
// exactly (2n − 2 triangles, ghosts included, for n vertices) so it never reallocates.
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <thread>
#include <utility>

#include "mwst/mesh/delaunay.hpp"
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
                  std::vector<std::uint64_t>& words, std::vector<std::uint64_t>& buffer, int depth);

// The grid of the sort keys: 65536² cells over the bounding box of the points.
struct KeyGrid {
  double xmin = 0.0, ymin = 0.0, scale = 0.0;
};
constexpr double kGridCells = 65535.0;

// The key grid of idx[0, count)'s points; false if all points coincide.
bool key_grid(const Point* pts, const std::uint32_t* idx, std::size_t count, KeyGrid& grid) {
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
  if (!(extent > 0.0)) return false;
  // Coordinates are halved before subtracting (fx below), and extent is a half extent: the grid
  // spans [0, kGridCells] in the longer direction.
  grid = {xmin, ymin, kGridCells / extent};
  return true;
}

// The sort key of idx[i] for i in [begin, end): its Hilbert index on the grid (high 32 bits) and
// its index (low 32 bits).
void fill_keys(const Point* pts, const std::uint32_t* idx, std::size_t begin, std::size_t end,
               const KeyGrid& grid, std::uint64_t* words) {
  for (std::size_t i = begin; i < end; ++i) {
    const Point& p = pts[idx[i]];
    const double fx = (p.x * 0.5 - grid.xmin * 0.5) * grid.scale;
    const double fy = (p.y * 0.5 - grid.ymin * 0.5) * grid.scale;
    const auto gx = static_cast<std::uint32_t>(std::min(kGridCells, std::max(0.0, fx)));
    const auto gy = static_cast<std::uint32_t>(std::min(kGridCells, std::max(0.0, fy)));
    words[i] = (static_cast<std::uint64_t>(hilbert_index16(gx, gy)) << 32) | idx[i];
  }
}

// Sorts words[0, count) (keys of fill_keys; buffer is scratch of the same size), writes the
// order to idx, and re-sorts crowded cells inside their own bounding box.
void sort_keys_and_refine(const Point* pts, std::uint32_t* idx, std::size_t count, std::uint64_t* words,
                          std::uint64_t* buffer, int depth) {
  if (count < (std::size_t{1} << 14)) {
    std::sort(words, words + count);
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
  std::vector<std::uint64_t> run_words, run_buffer;
  for (const auto& [start, length] : runs) {
    hilbert_sort(pts, idx + start, length, run_words, run_buffer, depth + 1);
  }
}

void hilbert_sort(const Point* pts, std::uint32_t* idx, std::size_t count,
                  std::vector<std::uint64_t>& words, std::vector<std::uint64_t>& buffer, int depth) {
  if (count < 2) return;
  words.resize(count);
  buffer.resize(count);
  KeyGrid grid;
  if (!key_grid(pts, idx, count, grid)) return;  // all points coincide
  fill_keys(pts, idx, 0, count, grid, words.data());
  sort_keys_and_refine(pts, idx, count, words.data(), buffer.data(), depth);
}

// Biased randomized insertion order (BRIO; Amenta, Choi, Rote, "Incremental constructions con
// BRIO", SoCG 2003): rounds of random samples, each round in curve order. Each point draws its round
// from a hash of its input index (so the order depends only on the input): with probability 3/4 the
// last round, 3/16 the one before, and so on; a stable counting sort of the curve order by round
// keeps every round in curve order. The rounds make the order random at every scale (short walks
// still, since each round follows the curve) where pure curve order would insert points lying on
// circles or lines next to each other and flip long fans of near-cocircular triangles each time
// (13 flips and 30 incircle tests per point on the CDT benchmark's circles, against 4 and 12 for
// uniform points). Sorting first and partitioning after keeps the point reads sequential.
void brio_rounds(std::uint32_t* idx, std::size_t count) {
  constexpr unsigned kRounds = 12;  // earliest round: probability 4^-11, a handful of points
  auto round_of = [](std::uint32_t i) {
    std::uint64_t z = i + 0x9E3779B97F4A7C15ull;  // splitmix64 of the index
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    unsigned level = 0;  // how many times a 1-in-4 event happened in a row
    while (level + 1 < kRounds && (z & 3u) == 0) {
      ++level;
      z >>= 2;
    }
    return kRounds - 1 - level;  // round 0 is inserted first
  };
  std::size_t start[kRounds + 1] = {};
  for (std::size_t i = 0; i < count; ++i) ++start[round_of(idx[i]) + 1];
  for (unsigned r = 0; r < kRounds; ++r) start[r + 1] += start[r];
  std::vector<std::uint32_t> sorted(count);
  for (std::size_t i = 0; i < count; ++i) sorted[start[round_of(idx[i])]++] = idx[i];
  std::copy(sorted.begin(), sorted.end(), idx);
}

// Inputs of at least this many points are sorted and triangulated in two halves on two threads.
constexpr std::size_t kParallelThreshold = 1u << 15;

// Runs `beside` and `here` — on two threads if `parallel`, else one after the other — and returns
// when both are done. The work is split the same way either way, so results never depend on it.
template <class Beside, class Here>
void run_both(bool parallel, Beside&& beside, Here&& here) {
  if (!parallel) {
    here();
    beside();
    return;
  }
  std::jthread worker(std::forward<Beside>(beside));
  here();
  worker.join();
}

// Returns the input indices in insertion order: BRIO rounds (brio_rounds) of the adaptive Hilbert
// curve order. Large inputs are first split at the median x coordinate (left: x below it; right:
// the rest, so the halves are separated by a vertical line as merge_halves needs) and each half is
// ordered in its own bounding box on its own thread; *left_count receives the left half's size
// (0: no split). The median, not the middle of the bounding box, keeps the halves balanced when a
// few outliers stretch the box (Kuzmin's distribution).
std::vector<std::uint32_t> hilbert_order(const std::vector<Point>& points, std::size_t* left_count, bool parallel) {
  const std::size_t n = points.size();
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  *left_count = 0;
  if (n >= kParallelThreshold) {
    std::vector<double> xs(n);
    for (std::size_t i = 0; i < n; ++i) xs[i] = points[i].x;
    std::nth_element(xs.begin(), xs.begin() + static_cast<std::ptrdiff_t>(n / 2), xs.end());
    const double median = xs[n / 2];
    xs = std::vector<double>();
    std::size_t left = 0;
    for (const Point& p : points) left += p.x < median ? 1 : 0;
    if (left >= n / 8 && n - left >= n / 8) {
      std::size_t l = 0, r = left;
      for (std::uint32_t i = 0; i < n; ++i) order[points[i].x < median ? l++ : r++] = i;
      run_both(
          parallel,
          [&] {
            std::vector<std::uint64_t> words, buffer;
            hilbert_sort(points.data(), order.data() + left, n - left, words, buffer, 0);
            brio_rounds(order.data() + left, n - left);
          },
          [&] {
            std::vector<std::uint64_t> words, buffer;
            hilbert_sort(points.data(), order.data(), left, words, buffer, 0);
            brio_rounds(order.data(), left);
          });
      *left_count = left;
      return order;
    }
  }
  std::vector<std::uint64_t> words, buffer;
  hilbert_sort(points.data(), order.data(), n, words, buffer, 0);
  brio_rounds(order.data(), n);
  return order;
}

// Advises the kernel to back the reserved (not yet touched) storage of v with transparent huge
// pages. The insertion walks and flips touch triangles and points all over arrays of tens of
// megabytes, so with 4 KiB pages nearly every access misses the TLB; 2 MiB pages also cut the page
// faults of first touch 512-fold. Advice only: without THP (or if it fails) nothing changes.
template <class T>
void advise_huge_pages(const std::vector<T>& v) {
#ifdef MADV_HUGEPAGE
  constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
  const auto begin = reinterpret_cast<std::uintptr_t>(v.data());
  const std::uintptr_t end = begin + v.capacity() * sizeof(T);
  const std::uintptr_t first = (begin + kHuge - 1) / kHuge * kHuge, last = end / kHuge * kHuge;
  if (last > first) ::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#else
  (void)v;
#endif
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

namespace {

enum class Degeneracy { kValid, kCoincident, kTwoDistinct, kCollinear };

// Builds the Delaunay triangulation of m.points (in insertion order) into m, with ghosts.
// kept[v] receives the vertex v was merged into (v itself unless v duplicates an earlier point).
Degeneracy build_incremental(Mesh& m, std::vector<VertexId>& kept) {
  const std::size_t n = m.points.size();
  kept.assign(n, kNone);
  m.triangles.reserve(2 * n);
  m.flags.reserve(2 * n);
  advise_huge_pages(m.triangles);
  // The first triangle: the first point, the next distinct one, the next not collinear with them.
  std::size_t second = 1;
  while (second < n && m.points[second] == m.points[0]) ++second;
  if (second >= n) return Degeneracy::kCoincident;
  std::size_t third = second + 1;
  while (third < n && orient2d(m.points[0], m.points[second], m.points[third]) == 0) ++third;
  if (third >= n) {
    for (std::size_t i = second + 1; i < n; ++i) {
      if (!(m.points[i] == m.points[0]) && !(m.points[i] == m.points[second])) {
        return Degeneracy::kCollinear;
      }
    }
    return Degeneracy::kTwoDistinct;
  }
  const auto s = static_cast<VertexId>(second), r = static_cast<VertexId>(third);
  if (orient2d(m.points[0], m.points[s], m.points[r]) > 0) {
    make_first_triangle(m, 0, s, r);
  } else {
    make_first_triangle(m, 0, r, s);
  }
  kept[0] = 0;
  kept[s] = s;
  kept[r] = r;
  Handle hint = make_handle(0, 0);
  for (VertexId v = 1; v < n; ++v) {
    if (v == s || v == r) continue;
    kept[v] = m.insert_vertex(v, hint, &hint);
  }
  return Degeneracy::kValid;
}

// Merges the Delaunay triangulation `right` into `left`, where every point of right lies strictly
// right (larger x) of every point of left. Right's vertex ids are offset by left's vertex count.
// The two hulls are joined by a ladder of triangles between their facing chains, built upwards
// from the lower common tangent (as in Guibas and Stolfi's divide-and-conquer merge, but choosing
// only among hull neighbours); Lawson flips then restore the Delaunay property near the seam.
void merge_halves(Mesh& left, Mesh&& right) {
  const auto nl = static_cast<VertexId>(left.points.size());
  const auto tl = static_cast<TriangleId>(left.triangles.size());
  left.points.insert(left.points.end(), right.points.begin(), right.points.end());
  std::vector<Point>().swap(right.points);
  left.flags.insert(left.flags.end(), right.flags.begin(), right.flags.end());
  std::vector<std::uint8_t>().swap(right.flags);
  // The triangles are copied in chunks, and each copied chunk of the source is handed back to the
  // kernel at once, so that the peak memory is the merged mesh plus one chunk rather than plus the
  // whole right half (the source is never read again; the vector frees its block at the end).
  left.triangles.reserve(left.triangles.size() + right.triangles.size() + 2);
  constexpr std::size_t kChunkBytes = std::size_t{1} << 20;
  const std::size_t page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  const auto* base = reinterpret_cast<const unsigned char*>(right.triangles.data());
  std::size_t released = 0;  // bytes of the source already released, from its start
  for (std::size_t i = 0; i < right.triangles.size(); ++i) {
    Triangle c = right.triangles[i];
    for (VertexId& v : c.v) {
      if (v != kInfinite) v += nl;
    }
    for (Handle& h : c.n) h += 4 * tl;
    left.triangles.push_back(c);
    const std::size_t done = (i + 1) * sizeof(Triangle);
    if (done - released >= kChunkBytes) {
      // Whole pages strictly inside [base + released, base + done).
      const auto first = (reinterpret_cast<std::uintptr_t>(base) + released + page - 1) / page * page;
      const auto last = (reinterpret_cast<std::uintptr_t>(base) + done) / page * page;
      if (last > first) ::madvise(reinterpret_cast<void*>(first), last - first, MADV_DONTNEED);
      released = done;
    }
  }
  right = Mesh();
  Mesh& m = left;
  const auto& P = m.points;

  // Hull navigation from the ghosts: ghost (a, b, ∞) is the hull edge b→a (counter-clockwise).
  // Each hull vertex starts one hull edge and ends one, so both tables are sorted (vertex, ghost)
  // pairs searched by vertex (hulls can be large: all the points of a circle).
  using GhostOf = std::vector<std::pair<VertexId, TriangleId>>;
  GhostOf from_pairs, to_pairs;  // keyed by b, resp. a
  auto finite_pair = [&](TriangleId g, VertexId& a, VertexId& b) {
    const Triangle& G = m.triangles[g];
    unsigned k = 0;
    while (G.v[k] != kInfinite) ++k;
    a = G.v[next3(k)];
    b = G.v[prev3(k)];
  };
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    // (A dead slot's corners are kNone, which equals kInfinite: skip it before asking is_ghost.)
    if (m.is_dead(t) || !m.is_ghost(t)) continue;
    VertexId a, b;
    finite_pair(t, a, b);
    from_pairs.emplace_back(b, t);
    to_pairs.emplace_back(a, t);
  }
  std::sort(from_pairs.begin(), from_pairs.end());
  std::sort(to_pairs.begin(), to_pairs.end());
  struct GhostTable {
    const GhostOf& pairs;
    TriangleId at(VertexId v) const {
      const auto it = std::lower_bound(pairs.begin(), pairs.end(), std::pair<VertexId, TriangleId>{v, 0});
      if (it == pairs.end() || it->first != v) throw InternalError("merge_halves: vertex not on the hull");
      return it->second;
    }
  };
  const GhostTable ghost_from{from_pairs}, ghost_to{to_pairs};
  auto ccw = [&](VertexId v) {
    VertexId a, b;
    finite_pair(ghost_from.at(v), a, b);
    return a;
  };
  auto cw = [&](VertexId v) {
    VertexId a, b;
    finite_pair(ghost_to.at(v), a, b);
    return b;
  };
  auto lex_less = [&](VertexId u, VertexId v) {
    return P[u].x < P[v].x || (P[u].x == P[v].x && P[u].y < P[v].y);
  };
  auto strictly_between = [&](VertexId a, VertexId b, VertexId q) {  // q collinear with a, b
    const Point &pa = P[a], &pb = P[b], &pq = P[q];
    if (pa.x != pb.x) return (pa.x < pq.x && pq.x < pb.x) || (pb.x < pq.x && pq.x < pa.x);
    return (pa.y < pq.y && pq.y < pb.y) || (pb.y < pq.y && pq.y < pa.y);
  };
  VertexId l = kNone, r = kNone;
  for (const auto& [v, g] : from_pairs) {
    (void)g;
    if (v < nl) {
      if (l == kNone || lex_less(l, v)) l = v;
    } else if (r == kNone || lex_less(v, r)) {
      r = v;
    }
  }
  // A common tangent of the two hulls, walked from the innermost pair (l, r) found above. The
  // lower one has every point on or left of l→r: l walks clockwise and r counter-clockwise while
  // the next vertex lies right of l→r. The upper one is the mirror image (every point on or right
  // of l→r). Then, so that no vertex lies on the open bridge, each end slides along a collinear
  // hull edge towards the other.
  auto next_on_hull = [&](VertexId v, bool counter_clockwise) { return counter_clockwise ? ccw(v) : cw(v); };
  auto common_tangent = [&](bool lower) {
    const int outside = lower ? -1 : 1;  // the side of l→r no point may lie on
    VertexId a = l, b = r;
    for (bool moved = true; moved;) {
      moved = false;
      while (orient2d(P[a], P[b], P[next_on_hull(a, !lower)]) == outside) {
        a = next_on_hull(a, !lower);
        moved = true;
      }
      while (orient2d(P[a], P[b], P[next_on_hull(b, lower)]) == outside) {
        b = next_on_hull(b, lower);
        moved = true;
      }
    }
    for (bool moved = true; moved;) {
      moved = false;
      const VertexId lc = next_on_hull(a, lower), rc = next_on_hull(b, !lower);
      if (orient2d(P[a], P[b], P[lc]) == 0 && strictly_between(a, b, lc)) {
        a = lc;
        moved = true;
      } else if (orient2d(P[a], P[b], P[rc]) == 0 && strictly_between(a, b, rc)) {
        b = rc;
        moved = true;
      }
    }
    return std::pair<VertexId, VertexId>{a, b};
  };
  const auto [l0, r0] = common_tangent(true);
  const auto [lt, rt] = common_tangent(false);
  l = l0;
  r = r0;
  // The ladder is Guibas and Stolfi's merge ("Primitives for the manipulation of general
  // subdivisions", 1985, section 9): each rung joins l and r, and its apex is the first candidate
  // above l→r on the facing boundary of L (resp. R) whose circle through l, r is empty. A triangle
  // of a half whose circumcircle contains the next candidate is deleted first, which exposes its
  // two other edges as the new boundary. Every rung is then Delaunay, so the work is linear in
  // the size of the seam (joining hull neighbours only and repairing with Lawson flips can need a
  // quadratic number of flips, e.g. between a tiny inner arc and a cocircular outer arc).
  //
  // A facing boundary is a chain of directed edges with the half's triangle on their left: L's
  // runs counter-clockwise from l (edges l→lc), R's clockwise from r (edges rc→r, as handles in
  // the triangle of R on that side). Edges exposed by deletions are kept on a stack (the chain
  // near l or r); below the stack the chain is the original hull, read from the ghosts.
  const TriangleId below_l0 = ghost_to.at(l0);    // (l0, p, ∞): hull edge p→l0 (stays unless pinched)
  const TriangleId after_r0 = ghost_from.at(r0);  // (q, r0, ∞): hull edge r0→q (stays unless pinched)
  auto corner_of = [&](TriangleId t, VertexId v) {
    unsigned k = 0;
    while (m.triangles[t].v[k] != v) ++k;
    return k;
  };
  auto link = [&](Handle x, Handle y) {
    m.triangles[x >> 2].n[x & 3] = y;
    m.triangles[y >> 2].n[y & 3] = x;
  };
  // The bottom ghost B = (r0, l0, ∞) for the new hull edge l0→r0.
  const TriangleId bottom = m.new_triangle();
  m.triangles[bottom].v = {r0, l0, kInfinite};
  link(make_handle(bottom, 0), make_handle(below_l0, corner_of(below_l0, cw(l0))));   // l0→∞
  link(make_handle(bottom, 1), make_handle(after_r0, corner_of(after_r0, ccw(r0))));  // ∞→r0
  std::vector<Handle> left_exposed, right_exposed;
  std::vector<TriangleId> freed;          // slots of deleted triangles and consumed ghosts
  std::vector<std::uint8_t> ghost_consumed(m.triangles.size(), 0);  // (its slot may hold a rung now)
  auto hull_edge_inside = [&](TriangleId g) { return m.triangles[g].n[corner_of(g, kInfinite)]; };
  // kNone once a pinched half's chain has gone round its whole hull.
  auto left_front = [&] {
    if (!left_exposed.empty()) return left_exposed.back();
    const TriangleId g = ghost_from.at(l);
    return ghost_consumed[g] ? kNone : hull_edge_inside(g);
  };
  auto right_front = [&] {
    if (!right_exposed.empty()) return right_exposed.back();
    const TriangleId g = ghost_to.at(r);
    return ghost_consumed[g] ? kNone : hull_edge_inside(g);
  };
  auto pop_left = [&] {
    if (!left_exposed.empty()) {
      left_exposed.pop_back();
    } else {
      const TriangleId g = ghost_from.at(l);
      ghost_consumed[g] = 1;
      freed.push_back(g);
    }
  };
  auto pop_right = [&] {
    if (!right_exposed.empty()) {
      right_exposed.pop_back();
    } else {
      const TriangleId g = ghost_to.at(r);
      ghost_consumed[g] = 1;
      freed.push_back(g);
    }
  };
  auto origin = [&](Handle h) { return m.triangles[h >> 2].v[next3(h & 3)]; };
  auto target = [&](Handle h) { return m.triangles[h >> 2].v[prev3(h & 3)]; };
  auto apex = [&](Handle h) { return m.triangles[h >> 2].v[h & 3]; };
  auto take_slot = [&] {
    if (freed.empty()) return m.new_triangle();
    const TriangleId t = freed.back();
    freed.pop_back();
    return t;
  };
  Handle pending = make_handle(bottom, 2);  // r0→l0: the twin of the next triangle's base l→r
  std::vector<Handle> suspects;
  const std::size_t limit = m.triangles.size();
  for (std::size_t step = 0;; ++step) {
    if (step > limit) throw InternalError("merge_halves: ladder does not terminate");
    Handle lf = left_front(), rf = right_front();
    VertexId lc = lf == kNone ? kNone : target(lf), rc = rf == kNone ? kNone : origin(rf);
    bool l_valid = lc != kNone && orient2d(P[l], P[r], P[lc]) > 0;
    bool r_valid = rc != kNone && orient2d(P[l], P[r], P[rc]) > 0;
    // Delete the triangles of L left of l→lc while their apex lies inside the circle (l, r, lc).
    while (l_valid) {
      const VertexId x = apex(lf);
      if (x == kInfinite || incircle(P[l], P[r], P[lc], P[x]) <= 0) break;
      const TriangleId t = lf >> 2;
      const unsigned k = lf & 3;
      const Handle lc_x = m.sym(make_handle(t, next3(k))), x_l = m.sym(make_handle(t, prev3(k)));
      pop_left();
      left_exposed.push_back(lc_x);  // x→lc
      left_exposed.push_back(x_l);  // l→x
      freed.push_back(t);
      lf = x_l;
      lc = x;
      l_valid = orient2d(P[l], P[r], P[lc]) > 0;
    }
    // The mirror image on R: triangles right of rc→r whose apex lies inside (l, r, rc).
    while (r_valid) {
      const VertexId y = apex(rf);
      if (y == kInfinite || incircle(P[l], P[r], P[rc], P[y]) <= 0) break;
      const TriangleId t = rf >> 2;
      const unsigned k = rf & 3;
      const Handle r_y = m.sym(make_handle(t, next3(k))), y_rc = m.sym(make_handle(t, prev3(k)));
      pop_right();
      right_exposed.push_back(y_rc);  // rc→y
      right_exposed.push_back(r_y);   // y→r
      freed.push_back(t);
      rf = r_y;
      rc = y;
      r_valid = orient2d(P[l], P[r], P[rc]) > 0;
    }
    if (l == lt && r == rt) break;  // (l, r) is the upper common tangent
    if (!l_valid && !r_valid) throw InternalError("merge_halves: no valid ladder step");
    // Both candidates possible: take the Delaunay choice (rc not inside the circle of (l, r, lc)).
    const bool take_left = l_valid && (!r_valid || incircle(P[l], P[r], P[lc], P[rc]) <= 0);
    if (take_left) {
      // The triangle (l, r, lc) on the boundary edge l→lc.
      pop_left();
      const TriangleId g = take_slot();
      m.triangles[g].v = {l, r, lc};
      link(make_handle(g, 1), lf);       // lc→l
      link(make_handle(g, 2), pending);  // l→r
      pending = make_handle(g, 0);       // r→lc, twin of the next base lc→r
      suspects.push_back(make_handle(g, 1));
      suspects.push_back(make_handle(g, 2));
      l = lc;
    } else {
      // The triangle (l, r, rc) on the boundary edge rc→r.
      pop_right();
      const TriangleId g = take_slot();
      m.triangles[g].v = {l, r, rc};
      link(make_handle(g, 0), rf);       // r→rc
      link(make_handle(g, 2), pending);  // l→r
      pending = make_handle(g, 1);       // rc→l, twin of the next base l→rc
      suspects.push_back(make_handle(g, 0));
      suspects.push_back(make_handle(g, 2));
      r = rc;
    }
  }
  // A half is pinched when its whole hull faced the gap: its chain went round the full cycle and
  // the hull edge after l (before r) was consumed; the top bridge then meets the bottom one.
  auto consumed = [&](TriangleId g) { return ghost_consumed[g] != 0; };
  const bool left_pinched = consumed(ghost_from.at(l)), right_pinched = consumed(ghost_to.at(r));
  // The top ghost U = (l, r, ∞) for the new hull edge r→l.
  const TriangleId top = m.new_triangle();
  m.triangles[top].v = {l, r, kInfinite};
  // The hull edges around the top bridge r→l: before r, s→r of R (or, if R is pinched, the bottom
  // bridge l0→r0 itself); after l, l→u of L (or, if L is pinched, the bottom bridge).
  if (right_pinched) {
    link(make_handle(top, 0), make_handle(bottom, 1));  // r→∞ with ∞→r0
  } else {
    const TriangleId below_r = ghost_to.at(r);  // (r, s, ∞): hull edge s→r, stays
    link(make_handle(top, 0), make_handle(below_r, corner_of(below_r, cw(r))));  // r→∞
  }
  if (left_pinched) {
    link(make_handle(top, 1), make_handle(bottom, 0));  // ∞→l with l0→∞
  } else {
    const TriangleId after_l = ghost_from.at(l);  // (u, l, ∞): hull edge l→u, stays
    link(make_handle(top, 1), make_handle(after_l, corner_of(after_l, ccw(l))));  // ∞→l
  }
  for (const TriangleId t : freed) m.kill_triangle(t);  // (none left unless deletions outnumber rungs)
  link(make_handle(top, 2), pending);  // l→r
  suspects.push_back(pending);
  restore_delaunay(m, suspects);
}

}  // namespace

void restore_delaunay(Mesh& m, std::vector<Handle>& stack) {
  while (!stack.empty()) {
    const Handle h = stack.back();
    stack.pop_back();
    if (m.is_dead(h >> 2) || m.is_segment(h) || !m.is_locally_non_delaunay(h)) continue;
    const Handle diag = m.flip(h);  // d→c in (c, a, d); the other triangle is (d, b, c)
    const Handle other = m.sym(diag);
    stack.push_back(Mesh::lnext(diag));
    stack.push_back(Mesh::lprev(diag));
    stack.push_back(Mesh::lnext(other));
    stack.push_back(Mesh::lprev(other));
  }
}

Mesh delaunay(std::vector<Point> points, DelaunayStats* stats, unsigned threads) {
  const bool parallel = threads != 1;
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

  std::size_t left_count = 0;
  std::vector<std::uint32_t> order = hilbert_order(points, &left_count, parallel);
  const auto t1 = Clock::now();

  // Work on copies in curve order (vertex id i here = order[i] in the input). Large inputs are
  // split into the two x-separated halves of the curve, triangulated on two threads and merged;
  // the split depends only on the input (never on the machine), so output is deterministic.
  Mesh m;
  std::vector<VertexId> kept;
  bool done = false;
  if (n >= kParallelThreshold && left_count >= n / 8 && n - left_count >= n / 8) {
    Mesh right;
    std::vector<VertexId> kept_right;
    // The left half's arrays are reserved for the whole mesh, so that merging the right half in
    // appends in place: no reallocation, and pages are touched only as they are used.
    m.points.reserve(n);
    m.triangles.reserve(2 * n + 16);
    m.flags.reserve(2 * n + 16);
    advise_huge_pages(m.points);
    m.points.resize(left_count);
    right.points.reserve(n - left_count);
    advise_huge_pages(right.points);
    right.points.resize(n - left_count);
    Degeneracy dl = Degeneracy::kValid, dr = Degeneracy::kValid;
    run_both(
        parallel,
        [&] {
          for (std::size_t i = left_count; i < n; ++i) right.points[i - left_count] = points[order[i]];
          dr = build_incremental(right, kept_right);
        },
        [&] {
          for (std::size_t i = 0; i < left_count; ++i) m.points[i] = points[order[i]];
          dl = build_incremental(m, kept);
        });
    if (dl == Degeneracy::kValid && dr == Degeneracy::kValid) {
      merge_halves(m, std::move(right));
      kept.reserve(n);
      for (const VertexId v : kept_right) kept.push_back(v + static_cast<VertexId>(left_count));
      done = true;
    } else {
      m = Mesh();  // a degenerate half: fall back to one sequential construction
    }
  }
  if (!done) {
    m.points.resize(n);
    for (std::size_t i = 0; i < n; ++i) m.points[i] = points[order[i]];
    switch (build_incremental(m, kept)) {
      case Degeneracy::kValid:
        break;
      case Degeneracy::kCoincident:
        throw InputError("", 0, "fewer than three distinct points (all points coincide)");
      case Degeneracy::kTwoDistinct:
        throw InputError("", 0, "fewer than three distinct points");
      case Degeneracy::kCollinear:
        throw InputError("", 0, "all points are collinear");
    }
  }
  const auto t2 = Clock::now();

  // Duplicate points: the insertion order is random, so the copy that made it into the mesh need not
  // be the first in the input. Each group of equal points is represented by its smallest input
  // index (the documented contract): order[] is rewritten so that the kept vertex of a group maps
  // to that index and every other member is listed as its duplicate.
  bool any_duplicate = false;
  for (VertexId v = 0; v < n && !any_duplicate; ++v) any_duplicate = kept[v] != v;
  std::vector<std::uint32_t> member;  // input index of each curve-order vertex (order before rewriting)
  if (any_duplicate) {
    member = order;
    std::vector<std::uint32_t>& representative = order;  // rewritten in place for kept vertices
    for (VertexId v = 0; v < n; ++v) {
      if (kept[v] != v) representative[kept[v]] = std::min(representative[kept[v]], member[v]);
    }
  }
  // Map the ids back to the input numbering (two threads for large meshes).
  auto map_back = [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t) {
      for (VertexId& v : m.triangles[t].v) {
        if (v != kInfinite) v = order[v];
      }
    }
  };
  const std::size_t triangle_count = m.triangles.size();
  if (n >= kParallelThreshold) {
    run_both(
        parallel, [&] { map_back(triangle_count / 2, triangle_count); }, [&] { map_back(0, triangle_count / 2); });
  } else {
    map_back(0, triangle_count);
  }
  m.points = std::move(points);
  m.vertex_kind.assign(n, VertexKind::kInput);
  m.vertex_marker.assign(n, 0);
  m.input_vertex_count = static_cast<std::uint32_t>(n);
  if (any_duplicate) {
    for (VertexId v = 0; v < n; ++v) {
      const std::uint32_t group = order[kept[v]];  // the group's smallest input index
      if (member[v] != group) {
        m.vertex_kind[member[v]] = VertexKind::kDuplicate;
        m.duplicates.emplace_back(member[v], group);
      }
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
