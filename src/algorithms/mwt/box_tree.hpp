// src/algorithms/mwt/box_tree.hpp — range queries for the exact MWT (a bounding-volume tree with
// median splits, robust to clustered inputs) and its two exact segment tests. Internal (not
// installed); inline, because the candidate and skeleton searches run them per pair of edges.
#pragma once

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>
#include <vector>

#include "algorithms/mwt/domain.hpp"
#include "mwst/geometry/geometry.hpp"

namespace mwst::mwt {

// ---- box queries: a bounding-volume tree (median splits), robust to clustered inputs ----------

struct Box {
  double xmin, ymin, xmax, ymax;
};

class BoxTree {
 public:
  explicit BoxTree(std::vector<Box> boxes) : boxes_(std::move(boxes)) {
    order_.resize(boxes_.size());
    std::iota(order_.begin(), order_.end(), Index{0});
    if (!boxes_.empty()) build(0, static_cast<Index>(order_.size()));
  }

  // Calls f(i) for every item whose box meets q, until f returns false.
  template <class F>
  void query(const Box& q, F&& f) const {
    if (nodes_.empty()) return;
    Index stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (!meets(node.box, q)) continue;
      if (node.left == kNone) {
        for (Index k = node.begin; k < node.end; ++k) {
          if (meets(boxes_[order_[k]], q) && !f(order_[k])) return;
        }
        continue;
      }
      stack[top++] = node.left;
      stack[top++] = node.right;
    }
  }

 private:
  struct Node {
    Box box;
    Index begin, end, left, right;
  };
  static bool meets(const Box& a, const Box& b) {
    return a.xmin <= b.xmax && b.xmin <= a.xmax && a.ymin <= b.ymax && b.ymin <= a.ymax;
  }
  Index build(Index begin, Index end) {
    Box box = boxes_[order_[begin]];
    for (Index k = begin + 1; k < end; ++k) {
      const Box& b = boxes_[order_[k]];
      box = {std::min(box.xmin, b.xmin), std::min(box.ymin, b.ymin), std::max(box.xmax, b.xmax), std::max(box.ymax, b.ymax)};
    }
    const auto id = static_cast<Index>(nodes_.size());
    nodes_.push_back({box, begin, end, kNone, kNone});
    if (end - begin <= 8) return id;
    const bool by_x = box.xmax - box.xmin >= box.ymax - box.ymin;
    const Index mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end, [&](Index a, Index b) {
      const Box& A = boxes_[a];
      const Box& B = boxes_[b];
      return by_x ? A.xmin + A.xmax < B.xmin + B.xmax : A.ymin + A.ymax < B.ymin + B.ymax;
    });
    const Index left = build(begin, mid);
    const Index right = build(mid, end);
    nodes_[id].left = left;
    nodes_[id].right = right;
    return id;
  }

  std::vector<Box> boxes_;
  std::vector<Index> order_;
  std::vector<Node> nodes_;  // depth ≤ log2(n / 8) + 1 (median splits), well inside the stack
};

class PointGrid {
 public:
  explicit PointGrid(const std::vector<Point>& p) : tree_(boxes(p)) {
    double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
    for (const Point& q : p) {
      x0 = std::min(x0, q.x), y0 = std::min(y0, q.y);
      x1 = std::max(x1, q.x), y1 = std::max(y1, q.y);
    }
    diagonal_ = std::hypot(x1 - x0, y1 - y0);
    magnitude_ = std::max({std::fabs(x0), std::fabs(x1), std::fabs(y0), std::fabs(y1)});
  }
  double diagonal() const { return diagonal_; }
  double magnitude() const { return magnitude_; }

  // Calls f(i) for every point in the box, until f returns false.
  template <class F>
  void for_each_in_box(double xmin, double ymin, double xmax, double ymax, F&& f) const {
    tree_.query(Box{xmin, ymin, xmax, ymax}, std::forward<F>(f));
  }

 private:
  static std::vector<Box> boxes(const std::vector<Point>& p) {
    std::vector<Box> b;
    b.reserve(p.size());
    for (const Point& q : p) b.push_back({q.x, q.y, q.x, q.y});
    return b;
  }
  BoxTree tree_;
  double diagonal_ = 0, magnitude_ = 0;
};

// Exact: does p lie on the open segment uv (p ≠ u, v)?
inline bool on_open_segment(const Point& u, const Point& v, const Point& p) {
  if (orient2d(u, v, p) != 0) return false;
  if (u.x != v.x) return std::min(u.x, v.x) < p.x && p.x < std::max(u.x, v.x);
  return std::min(u.y, v.y) < p.y && p.y < std::max(u.y, v.y);
}

// Exact: do the segments ab and cd cross at a point interior to both (no shared endpoint)?
inline bool properly_cross(const Point& a, const Point& b, const Point& c, const Point& d) {
  const int o1 = orient2d(a, b, c), o2 = orient2d(a, b, d);
  if (o1 == 0 || o2 == 0 || o1 == o2) return false;
  const int o3 = orient2d(c, d, a), o4 = orient2d(c, d, b);
  return o3 != 0 && o4 != 0 && o3 != o4;
}
}  // namespace mwst::mwt
