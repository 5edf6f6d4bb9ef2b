// src/algorithms/refine/clean_queries.hpp — bundle removal's memory of skinny triangles in no
// K-bundle between its exact tests (internal): CleanQueries, and kCleanQueriesFrom.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include "algorithms/triangle_key.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst::brh {

// Skinny triangles the exact test found in no K-bundle, kept across passes while nothing near them
// changes. Sound because vertices are only added: if a disk D (vertex-empty after a pass, hence
// before it) puts such a triangle t in a K-bundle after the pass, D met fewer than K triangles
// before it, so it meets a triangle the pass made; while the hull is unchanged that triangle lies
// in the convex hull, where D meets only triangles inside t's reach box (KBundleCache::reach), so
// the box of the made triangle meets t's box. A pass that changes the hull forgets every entry.
class CleanQueries {
 public:
  bool empty() const { return boxes_.empty(); }
  bool contains(const std::array<VertexId, 3>& triple) const { return boxes_.count(triple) != 0; }
  void add(const std::array<VertexId, 3>& triple, const std::array<double, 4>& box) {
    if (box[0] <= box[2] && box[1] <= box[3]) boxes_[triple] = box;  // an empty box: not kept
  }
  void clear() { boxes_.clear(); }

  // Before a pass: the triangles as they are.
  void snapshot(const Mesh& m) {
    before_v_.resize(m.triangles.size());
    for (TriangleId t = 0; t < m.triangles.size(); ++t) before_v_[t] = m.triangles[t].v;
    before_flags_ = m.flags;
  }

  // After the pass: forgets the entries whose box meets the box of a triangle the pass made (a
  // slot whose corners or flags changed; conservative when a triangle merely moved slot).
  void update(const Mesh& m) {
    made_.clear();
    std::array<double, 4> all{kInf, kInf, -kInf, -kInf};
    for (TriangleId t = 0; t < m.triangles.size(); ++t) {
      if (t < before_v_.size() && before_v_[t] == m.triangles[t].v && before_flags_[t] == m.flags[t]) continue;
      if (m.is_dead(t)) continue;
      if (m.is_ghost(t)) {  // the hull changed
        boxes_.clear();
        return;
      }
      std::array<double, 4> b{kInf, kInf, -kInf, -kInf};
      for (const VertexId v : m.triangles[t].v) {
        const Point& p = m.points[v];
        b = {std::min(b[0], p.x), std::min(b[1], p.y), std::max(b[2], p.x), std::max(b[3], p.y)};
      }
      all = {std::min(all[0], b[0]), std::min(all[1], b[1]), std::max(all[2], b[2]), std::max(all[3], b[3])};
      made_.push_back(b);
    }
    if (made_.empty()) return;
    // A grid over the made boxes: the cells each covers are marked; an entry is forgotten if its box
    // covers a marked cell. Cell indices are monotone in the coordinate, so two closed boxes that
    // meet share a cell. Marking a box and asking about one cost O(1), not their areas in cells
    // (a fan's slivers reach across the grid, as do the boxes of their disks: walking the cells
    // was 22% of BRH on `mwst generate fan` 40k): the boxes' corners go into a difference table,
    // whose prefix sums count the made boxes over each cell, and the prefix sums of the marked
    // cells (a summed-area table) give the marked cells under any box.
    const double sx = all[2] > all[0] ? kGrid / (all[2] - all[0]) : 0.0;
    const double sy = all[3] > all[1] ? kGrid / (all[3] - all[1]) : 0.0;
    auto cell = [](double v, double v0, double scale) {
      return static_cast<std::size_t>(std::clamp(std::floor((v - v0) * scale), 0.0, kGrid - 1.0));
    };
    constexpr auto n = static_cast<std::size_t>(kGrid) + 1;  // a row of either table
    table_.assign(n * n, 0);
    for (const auto& b : made_) {  // +1 over the box's cells, in the difference table
      const std::size_t x0 = cell(b[0], all[0], sx), x1 = cell(b[2], all[0], sx) + 1;
      const std::size_t y0 = cell(b[1], all[1], sy), y1 = cell(b[3], all[1], sy) + 1;
      ++table_[y0 * n + x0];
      --table_[y0 * n + x1];
      --table_[y1 * n + x0];
      ++table_[y1 * n + x1];
    }
    // table_[y][x] becomes the number of made boxes over cell (x, y) (two-dimensional prefix
    // sums), then the number of marked cells (x' < x, y' < y): cell (x, y) moves to (x + 1, y + 1).
    for (std::size_t y = 0; y < n; ++y) {
      for (std::size_t x = 0; x < n; ++x) {
        if (x > 0) table_[y * n + x] += table_[y * n + x - 1];
        if (y > 0) table_[y * n + x] += table_[(y - 1) * n + x];
        if (x > 0 && y > 0) table_[y * n + x] -= table_[(y - 1) * n + x - 1];
      }
    }
    for (std::size_t y = n - 1; y-- > 0;) {
      for (std::size_t x = n - 1; x-- > 0;) table_[(y + 1) * n + x + 1] = table_[y * n + x] > 0 ? 1 : 0;
    }
    for (std::size_t i = 0; i < n; ++i) table_[i] = table_[i * n] = 0;
    for (std::size_t y = 1; y < n; ++y) {
      for (std::size_t x = 1; x < n; ++x) {
        table_[y * n + x] += table_[y * n + x - 1] + table_[(y - 1) * n + x] - table_[(y - 1) * n + x - 1];
      }
    }
    std::erase_if(boxes_, [&](const auto& entry) {
      const auto& b = entry.second;
      if (b[2] < all[0] || b[0] > all[2] || b[3] < all[1] || b[1] > all[3]) return false;
      const std::size_t x0 = cell(b[0], all[0], sx), x1 = cell(b[2], all[0], sx) + 1;
      const std::size_t y0 = cell(b[1], all[1], sy), y1 = cell(b[3], all[1], sy) + 1;
      return table_[y1 * n + x1] - table_[y0 * n + x1] - table_[y1 * n + x0] + table_[y0 * n + x0] > 0;
    });
  }

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  static constexpr double kGrid = 256.0;
  std::unordered_map<std::array<VertexId, 3>, std::array<double, 4>, detail::TripleHash> boxes_;
  std::vector<std::array<VertexId, 3>> before_v_;
  std::vector<std::uint8_t> before_flags_;
  std::vector<std::array<double, 4>> made_;
  std::vector<std::int64_t> table_;  // update()'s difference table, then its summed-area table
};

// Below this many skinny triangles the exact test is local and cheap: no clean-list bookkeeping.
constexpr std::size_t kCleanQueriesFrom = 1024;

}  // namespace mwst::brh
