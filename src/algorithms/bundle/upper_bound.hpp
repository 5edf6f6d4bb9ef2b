// src/algorithms/bundle/upper_bound.hpp — bundle_number's upper bound when a candidate budget cut
// lists short (internal; docs/algorithms/bundle-number.md, "Budget").
//   bound_cut_pencils   — per pencil not swept: the triangles whose bounding boxes meet a box
//                         holding both of its circumdisks (every disk of the pencil lies in their
//                         union), counted for all of them at once; then the pencils of the largest
//                         bounds swept exactly from full floods, largest first, within a budget
//   BoxCounter          — how many triangles' bounding boxes meet each of many query boxes
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "algorithms/bundle/shared.hpp"
#include "algorithms/bundle/worker.hpp"
#include "mwst/algorithms/bundle.hpp"

namespace mwst::bundle {

// A closed axis-parallel box: x0, y0, x1, y1 (floats, 16 bytes: the boxes of every triangle are held
// at once; rounded outward from doubles, so that a box only grows, and the counts only grow).
using Box = std::array<float, 4>;

// The box [x0, x1] × [y0, y1] of doubles rounded outward to floats (beyond float's range: ±∞).
Box outward_box(double x0, double y0, double x1, double y1);

// A box [x0, x1] × [y0, y1] holding the open circumdisk of a, b, c (counter-clockwise), with the
// rounding of its centre and radius bounded rigorously; false if rounding cannot place it (a nearly
// flat triangle: the caller then counts every triangle).
bool circumdisk_box(const Point& a, const Point& b, const Point& c, std::array<double, 4>& out);

// How many of a set of boxes (the bounding boxes of the triangles) meet each query box, offline:
// a box misses the query iff it lies wholly left of it (L), right (R), below (D) or above (U); L
// and R exclude each other, so do D and U, and by inclusion and exclusion
//   meeting = all − L − R − D − U + LD + LU + RD + RU,
// the one-sided counts by binary search, the corner counts by two sweeps over x with Fenwick trees
// over y (dominance counting). O((n + q) log n) for n boxes and q queries.
class BoxCounter {
 public:
  // The ranks of y1 and of y0, and the orders by x1 and by x0, on up to `threads` threads.
  explicit BoxCounter(const std::vector<Box>& boxes, unsigned threads = 1);
  // The number of boxes meeting each query box (closed boxes; touching counts). The two sweeps
  // (left, right) run on up to `threads` threads. Not thread-safe (scratch is kept from call to
  // call).
  std::vector<std::uint32_t> count(const std::vector<Box>& queries, unsigned threads = 1) const;

 private:
  struct Keyed {
    float x;
    std::uint32_t y_top, y_bottom;  // ranks of the box's y1 (in ys_top_) and y0 (in ys_bottom_)
  };
  std::size_t n_ = 0;
  std::vector<float> ys_top_, ys_bottom_;  // every box's y1 / y0, ascending
  std::vector<Keyed> by_right_;             // by x1 ascending
  std::vector<Keyed> by_left_;              // by x0 descending
  // count()'s scratch, per sweep (left, right): the Fenwick trees over the ranks of y1 and y0.
  mutable std::array<std::vector<std::uint32_t>, 2> fenwick_top_, fenwick_bottom_;
};

// With lists cut at the budget's cap (sh.truncated), replaces the upper bound "every triangle" by
// the largest of: the best count found (result.lower_bound) and, per pencil not swept because a
// list of it was cut, the number of triangles whose bounding boxes meet a box holding both of its
// circumdisks. Then sweeps those pencils exactly from full floods, largest bound first, as long as
// their bounds exceed the best count and the floods stay within `work_budget` triangles in all; a
// sweep that beats the lower bound replaces it and its witness. result.exact if the bounds meet.
// The box counts run on up to `threads` threads; the sweeps on `worker`.
void bound_cut_pencils(Shared& sh, Worker& worker, std::size_t work_budget, unsigned threads, BundleResult& result);

}  // namespace mwst::bundle
