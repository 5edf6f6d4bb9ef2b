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
    // meet share a cell.
    const double sx = all[2] > all[0] ? kGrid / (all[2] - all[0]) : 0.0;
    const double sy = all[3] > all[1] ? kGrid / (all[3] - all[1]) : 0.0;
    auto cell = [](double v, double v0, double scale) {
      return static_cast<std::size_t>(std::clamp(std::floor((v - v0) * scale), 0.0, kGrid - 1.0));
    };
    marks_.assign(static_cast<std::size_t>(kGrid * kGrid), 0);
    for (const auto& b : made_) {
      for (std::size_t y = cell(b[1], all[1], sy); y <= cell(b[3], all[1], sy); ++y) {
        for (std::size_t x = cell(b[0], all[0], sx); x <= cell(b[2], all[0], sx); ++x) {
          marks_[y * static_cast<std::size_t>(kGrid) + x] = 1;
        }
      }
    }
    std::erase_if(boxes_, [&](const auto& entry) {
      const auto& b = entry.second;
      if (b[2] < all[0] || b[0] > all[2] || b[3] < all[1] || b[1] > all[3]) return false;
      for (std::size_t y = cell(b[1], all[1], sy); y <= cell(b[3], all[1], sy); ++y) {
        for (std::size_t x = cell(b[0], all[0], sx); x <= cell(b[2], all[0], sx); ++x) {
          if (marks_[y * static_cast<std::size_t>(kGrid) + x]) return true;
        }
      }
      return false;
    });
  }

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  static constexpr double kGrid = 256.0;
  std::unordered_map<std::array<VertexId, 3>, std::array<double, 4>, detail::TripleHash> boxes_;
  std::vector<std::array<VertexId, 3>> before_v_;
  std::vector<std::uint8_t> before_flags_;
  std::vector<std::array<double, 4>> made_;
  std::vector<std::uint8_t> marks_;
};

// Below this many skinny triangles the exact test is local and cheap: no clean-list bookkeeping.
constexpr std::size_t kCleanQueriesFrom = 1024;

}  // namespace mwst::brh
