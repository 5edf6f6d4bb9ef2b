// src/mesh/insertion_order.cpp — the insertion order of delaunay() (insertion_order.hpp): an
// adaptive Hilbert curve sort (radix sort of 32-bit curve keys, crowded cells re-sorted in their own
// box) and BRIO rounds over it.
#include "mesh/insertion_order.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace mwst::insertion_order {

namespace {

// ==== the Hilbert curve sort begins here =========================================================

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

// ==== the Hilbert curve sort ends here ===========================================================

}  // namespace

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

}  // namespace mwst::insertion_order
