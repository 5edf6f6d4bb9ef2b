// algorithms/quadtree/builder_segments.cpp — segments in the grid: corners lying exactly on a
// segment join its chain; BEG's warp towards segments moves corners close to a segment onto it
// (onto an edge's crossing point, or onto the projection); every leaf edge a segment still crosses
// properly gets a crossing point, shared by both sides; and each segment becomes a chain of
// subsegments through the vertices on it, by position.
#include <algorithm>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "algorithms/quadtree/builder.hpp"
#include "mesh/keys.hpp"

namespace mwst::qtr {

// ==== segments in the grid begins here ==============================================================

// Corners onto segments, crossing points, and the chains of subsegments, over the leaves that have
// a segment in their list (the only ones these passes look at, listed by build_loops()).
void Builder::segments_pass() {
  if (in_.segments.empty()) return;
  gon_segment_.reserve(gpos_.capacity());
  gon_segment_.assign(grid_count_, false);
  gsegment_.clear();
  std::vector<std::uint32_t> near = std::move(near_segment_[0]);
  near.insert(near.end(), near_segment_[1].begin(), near_segment_[1].end());
  for (auto& half : near_segment_) std::vector<std::uint32_t>().swap(half);
  corners_on_segments(near);
  snap_corners_to_segments(near);
  add_crossing_points(near);
  check_deadline(options_.deadline);
  build_chains();
}

// 1. Corners exactly on a segment join its chain where they are.
void Builder::corners_on_segments(const std::vector<std::uint32_t>& near) {
  for_each_leaf_segment(near, [&](std::uint32_t, const std::array<std::uint32_t, 8>& loop, std::uint32_t s,
                                  const Point& a, const Point& b) {
    for (unsigned slot = 0; slot < 8; ++slot) {
      const std::uint32_t g = loop[slot];
      if (g == kNone || gwarped_[g] || gon_segment_[g]) continue;
      const Point& p = gpos_[g];
      if (orient2d(a, b, p) != 0) continue;
      const bool between = a.x != b.x ? ((a.x < p.x && p.x < b.x) || (b.x < p.x && p.x < a.x))
                                      : ((a.y < p.y && p.y < b.y) || (b.y < p.y && p.y < a.y));
      if (!between) continue;
      set_segment(g, s);
      ++stats_.on_segment;
    }
  });
}

// 2. BEG's warp towards segments: corners close to a segment move onto it, so that no sliver
//    is cut off a cell. Two moves, scored as a fraction of the leaf size; a corner takes the
//    best-scoring one (each corner moves at most once):
//    X. a segment crosses an edge uc of a leaf of size S at x with |x − c| < snap_fraction·S and
//       |x − c| < |uc|/2: c moves to x, along the edge (the leaves on both sides of the edge keep
//       at least half of it; the others only grow);
//    P. a corner lies nearer to a segment than snap_fraction × its largest incident leaf and
//       0.4 × its smallest: it moves to its projection (a segment running almost along the cell
//       edges crosses none near the corner). Two ends of one edge can both move only if the
//       edge meets the segment at less than asin(0.8), so they stay 0.3 of the edge apart.
// Moving corners changes which edges a segment crosses (a corner left beside the moved neighbours
// may now lie right next to the segment), so the two rules run to a fixed point; every corner
// moves at most once.
void Builder::snap_corners_to_segments(const std::vector<std::uint32_t>& near) {
  SnapChoices choice;
  for (int round = 0; round < 4; ++round) {
    choice.clear();
    offer_crossing_snaps(near, choice);
    offer_projection_snaps(near, choice);
    for (const auto& [g, c] : choice) {
      set_segment(g, c.segment);
      gpos_[g] = c.target;
      gmoved_[g] = true;
      ++stats_.snapped;
    }
    if (choice.empty()) break;
  }
}

// Offers corner c the move `candidate`; a corner keeps the best-scoring one (the smaller fraction,
// then the smaller segment).
void Builder::offer_snap(SnapChoices& choice, std::uint32_t c, const SnapChoice& candidate) {
  const auto [it, fresh] = choice.emplace(c, candidate);
  if (!fresh && (candidate.fraction < it->second.fraction ||
                 (candidate.fraction == it->second.fraction && candidate.segment < it->second.segment))) {
    it->second = candidate;
  }
}

// 2a. Rule X: the ends of leaf edges that a segment crosses close to them.
void Builder::offer_crossing_snaps(const std::vector<std::uint32_t>& near, SnapChoices& choice) {
  for_each_crossed_edge(near, [&](std::uint32_t k, unsigned, std::uint32_t u, std::uint32_t w, std::uint32_t s,
                                  const Point& a, const Point& b) {
    // (The exact crossing rounded: a corner moved there lies on the segment within rounding.)
    const Point x = exact_crossing(gpos_[std::min(u, w)], gpos_[std::max(u, w)], a, b);
    const double length = distance(gpos_[u], gpos_[w]);
    const double size = tree_.cell_size(tree_.nodes[leaves_[k]].level);
    for (const std::uint32_t c : {u, w}) {
      if (gwarped_[c] || gon_segment_[c]) continue;
      const double along = distance(gpos_[c], x);
      if (!(along < options_.snap_fraction * size) || !(along < 0.5 * length)) continue;
      offer_snap(choice, c, {s, along / size, x});
    }
  });
}

// 2b. Rule P: corners close to a segment running almost along the cell edges.
void Builder::offer_projection_snaps(const std::vector<std::uint32_t>& near, SnapChoices& choice) const {
  for_each_leaf_segment(near, [&](std::uint32_t, const std::array<std::uint32_t, 8>& loop, std::uint32_t s,
                                  const Point& a, const Point& b) {
    const double dx = b.x - a.x, dy = b.y - a.y;
    for (unsigned slot = 0; slot < 8; ++slot) {
      const std::uint32_t g = loop[slot];
      if (g == kNone || gwarped_[g] || gon_segment_[g]) continue;
      const Point& p = gpos_[g];
      const double t = ((p.x - a.x) * dx + (p.y - a.y) * dy) / (dx * dx + dy * dy);
      if (!(t > 0.0 && t < 1.0)) continue;
      const Point proj{a.x + t * dx, a.y + t * dy};
      const double d = distance(p, proj);
      const double size = tree_.cell_size(gtop_[g]);
      if (!(d < options_.snap_fraction * size) || !(d < 0.4 * tree_.cell_size(glevel_[g])) ||
          !(d < distance(proj, a)) || !(d < distance(proj, b))) {
        continue;
      }
      offer_snap(choice, g, {s, d / size, proj});
    }
  });
}

// 3. Crossing points: every leaf edge properly crossed by a segment of the leaf's list (edges
//    ending on that segment only touch it). One vertex per (edge, segment), shared by both sides.
void Builder::add_crossing_points(const std::vector<std::uint32_t>& near) {
  std::unordered_map<std::uint64_t, std::vector<std::pair<std::uint32_t, std::uint32_t>>> made;
  for_each_crossed_edge(near, [&](std::uint32_t k, unsigned slot, std::uint32_t u, std::uint32_t w, std::uint32_t s,
                                  const Point& a, const Point& b) {
    const std::uint64_t key = undirected_key(u, w);
    auto& list = made[key];
    std::uint32_t x = kNone;
    for (const auto& [seg, vertex] : list) {
      if (seg == s) x = vertex;
    }
    if (x == kNone) {
      x = static_cast<std::uint32_t>(gpos_.size());
      const Point& lo = gpos_[std::min(u, w)];
      const Point& hi = gpos_[std::max(u, w)];
      // The exact crossing rounded, as the CDT places crossings. A coordinate it puts below the
      // supported range (segment_intersection snapped it to 0, off the segment by more than the
      // rounding of its coordinates) sends the input to the fallback (out_of_range_vertex).
      gpos_.push_back(exact_crossing(lo, hi, a, b));
      gon_segment_.push_back(true);
      gsegment_[x] = s;
      gwarped_.push_back(false);
      gmoved_.push_back(true);
      list.emplace_back(s, x);
      ++stats_.crossings;
    }
    crossings_.push_back({k, slot, x});
  });
  std::sort(crossings_.begin(), crossings_.end(), [](const EdgeCrossing& p, const EdgeCrossing& q) {
    return p.leaf != q.leaf ? p.leaf < q.leaf : p.slot != q.slot ? p.slot < q.slot : p.vertex < q.vertex;
  });
  crossings_.erase(std::unique(crossings_.begin(), crossings_.end(),
                               [](const EdgeCrossing& p, const EdgeCrossing& q) {
                                 return p.leaf == q.leaf && p.slot == q.slot && p.vertex == q.vertex;
                               }),
                   crossings_.end());
}

// 4. Chains: along each segment, its endpoints and the vertices on it, by position.
void Builder::build_chains() {
  std::vector<std::vector<std::uint32_t>> on(in_.segments.size());
  {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> placed(gsegment_.begin(), gsegment_.end());
    std::sort(placed.begin(), placed.end());  // (by vertex: the map's order is unspecified)
    for (const auto& [g, s] : placed) on[s].push_back(g);
  }
  for (std::uint32_t s = 0; s < in_.segments.size(); ++s) {
    const FeatureSegment& seg = in_.segments[s];
    const Point& a = pts_[seg.a];
    const Point& b = pts_[seg.b];
    const double dx = b.x - a.x, dy = b.y - a.y;
    auto param = [&](std::uint32_t g) { return (gpos_[g].x - a.x) * dx + (gpos_[g].y - a.y) * dy; };
    auto& list = on[s];
    std::sort(list.begin(), list.end(), [&](std::uint32_t p, std::uint32_t q) { return param(p) < param(q); });
    const std::uint32_t first = input_gv_[seg.a], last = input_gv_[seg.b];
    list.insert(list.begin(), first);
    list.push_back(last);
    for (std::size_t i = 0; i + 1 < list.size(); ++i) {
      if (!(param(list[i]) < param(list[i + 1]))) {
        throw RouteFailure{"two vertices at the same place on a segment"};
      }
      chain_links_.push_back({list[i], list[i + 1], s});
      chain_links_.push_back({list[i + 1], list[i], s});
      ++subsegment_count_;
    }
  }
  std::stable_sort(chain_links_.begin(), chain_links_.end(),
                   [](const ChainLink& p, const ChainLink& q) { return p.vertex < q.vertex; });
}

// ==== segments in the grid ends here ================================================================

}  // namespace mwst::qtr
