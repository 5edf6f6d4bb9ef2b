// algorithms/quadtree/builder_grid.cpp — the grid of the subdivision: the leaves in Morton order,
// the vertices each leaf owns (its lower-left corner, the midpoints of its left and bottom sides,
// and on the root's border its other corners), their ids and positions; each leaf's loop of up to
// 8 vertices; and BEG's warp of the corner nearest each input vertex onto it.
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "algorithms/quadtree/builder.hpp"
#include "support/page_faulter.hpp"

namespace mwst::qtr {

// ==== grid vertices begins here ==================================================================

// The ownership block's size (see own_storage_).
std::size_t Builder::own_storage_bytes() const {
  return leaves_.size() * std::max(sizeof(std::uint32_t) + 1, sizeof(CellBound));
}

// The leaves in Morton order; which grid vertices each leaf owns (its lower-left corner, the
// midpoints of its left and bottom sides where the neighbours there are split, and on the root's
// top and right border its other corners), their ids by a prefix sum and their positions.
void Builder::number_vertices() {
  tree_.lend_dead_room(spare_);
  leaves_ = tree_.leaves_in_order();
  check_deadline(options_.deadline);
  // (The two largest borrowers first: the regions lent so far are the tree's dead blocks.)
  west_south_ = make_spare_array<std::array<std::uint32_t, 2>>(spare_, leaves_.size());
  leaf_shape_ = make_spare_array<std::uint16_t>(spare_, leaves_.size());
  tree_.number_leaves(leaves_, threaded_leaves_);
  own_storage_ = std::make_unique_for_overwrite<std::byte[]>(own_storage_bytes());
  own_base_ = reinterpret_cast<std::uint32_t*>(own_storage_.get());
  own_mask_ = reinterpret_cast<std::uint8_t*>(own_storage_.get() + leaves_.size() * sizeof(std::uint32_t));
  // Which vertices each leaf owns (neighbour look-ups: two threads), then their ids by a prefix
  // sum in leaf order, then their positions (two threads).
  split_half_ = leaves_.size();
  support::parallel_ranges(workers_for(leaves_.size(), threaded_leaves_), leaves_.size(),
      [&](std::size_t half, std::size_t begin, std::size_t end) {
    auto& split_pairs = split_across_[half];
    split_pairs.clear();
    if (begin != 0) split_half_ = begin;
    for (std::size_t k = begin; k < end; ++k) {
      check_deadline_at(k - begin, options_.deadline);
      prefetch_neighbours(k, end, 2, 3);  // west, south
      own_vertices_of_leaf(k, split_pairs);
    }
  });
  std::uint32_t next = 0;
  for (std::size_t k = 0; k < leaves_.size(); ++k) {
    own_base_[k] = next;
    next += support::set_bits(own_mask_[k]);
  }
  grid_count_ = next;
  check_deadline(options_.deadline);
  gpos_.clear();
  // (Room for the crossing points and centres made later, and for the duplicate input points: the
  // array becomes the mesh's points in run(), without being copied.)
  reserve_room(gpos_, std::max<std::size_t>(grid_count_, leaves_.size() + leaves_.size() / 2) +
                          (pts_.size() - in_.vertices.size()) + 16);
  // resize() zero-fills, and so faults in, every page of the positions on this thread (16 bytes
  // per grid vertex: 0.3–0.6 s at a million points, the kernel clearing each page); both threads
  // fault them in first, and the fill then writes pages that are there.
  if (leaves_.size() >= threaded_leaves_) {
    support::PageFaulter pages;
    pages.add(gpos_.data(), grid_count_ * sizeof(Point));
    support::parallel_ranges(2, 2, [&](std::size_t, std::size_t, std::size_t) { pages.work(); });
  }
  gpos_.resize(grid_count_);
  support::parallel_ranges(workers_for(leaves_.size(), threaded_leaves_), leaves_.size(),
                           [&](std::size_t, std::size_t begin, std::size_t end) { place_owned_vertices(begin, end); });
}

// Which vertices leaf k owns (own_mask_; Own bits), and for link_cell() what lies across its west
// and south sides (west_south_, leaf_shape_); split pairs go to this half's split_pairs.
void Builder::own_vertices_of_leaf(std::size_t k, std::vector<std::array<std::uint32_t, 2>>& split_pairs) {
  const std::uint32_t a = leaves_[k];
  const Node& n = tree_.nodes[a];
  const unsigned l = n.level;
  const std::int64_t side = std::int64_t{1} << l;
  unsigned mask = 1u << kOwnLL;
  const std::uint32_t w = tree_.neighbour(a, 2);
  if (w != kNone && tree_.nodes[w].level == l && !tree_.is_leaf(w)) mask |= 1u << kOwnLeftMid;
  const std::uint32_t s = tree_.neighbour(a, 3);
  if (s != kNone && tree_.nodes[s].level == l && !tree_.is_leaf(s)) mask |= 1u << kOwnBottomMid;
  // For link_cell(): the leaves across the west and south sides as leaf ordinals (bits 12, 13 of
  // the shape) when they are a leaf, or the two children of a split cell along the side that
  // follow each other as usual in Morton order (east column: SE, NE two apart; north row: NW,
  // NE next to each other).
  const auto leaf_across = [&](std::uint32_t b, unsigned own_bit, unsigned near_child, unsigned step,
                               std::uint32_t& out) {
    if (b == kNone) return false;
    if (tree_.is_leaf(b)) {
      out = leaf_of(b);
      return true;
    }
    if (((mask >> own_bit) & 1u) == 0) return false;
    const std::uint32_t c = tree_.nodes[b].child;
    const std::uint32_t first = leaf_of(c + near_child);
    if (first == kNone || leaf_of(c + 3) != first + step) return false;
    out = first;
    return true;
  };
  // Otherwise (a split cell whose two leaves along the side are not next to each other) the
  // place of their two ordinals in this half's split_across_ (link_cell() reads no node: the
  // nodes' storage is the triangle array it writes, see NodeArray).
  const auto split_pair = [&](std::uint32_t b, unsigned near_child) {
    const std::uint32_t c = tree_.nodes[b].child;
    split_pairs.push_back({leaf_of(c + near_child), leaf_of(c + 3)});
    return static_cast<std::uint32_t>(split_pairs.size() - 1);
  };
  unsigned across = 0;
  std::uint32_t west = kNone, south = kNone;
  if (leaf_across(w, kOwnLeftMid, 1, 2, west)) {
    across |= 1u;
  } else if (w != kNone) {
    west = split_pair(w, 1);
  }
  if (leaf_across(s, kOwnBottomMid, 2, 1, south)) {
    across |= 2u;
  } else if (s != kNone) {
    south = split_pair(s, 2);
  }
  west_south_[k] = {west, south};
  const bool top = n.iy + 1 == side, right = n.ix + 1 == side;
  if (top) mask |= 1u << kOwnUL;
  if (right) mask |= 1u << kOwnLR;
  if (top && right) mask |= 1u << kOwnUR;
  own_mask_[k] = static_cast<std::uint8_t>(mask);
  const unsigned border = (n.iy == 0 ? 1u : 0u) | (right ? 2u : 0u) | (top ? 4u : 0u) | (n.ix == 0 ? 8u : 0u);
  leaf_shape_[k] = static_cast<std::uint16_t>(l | ((mask >> kOwnLeftMid) & 1u) << 6 |
                                              ((mask >> kOwnBottomMid) & 1u) << 7 | border << 8 |
                                              across << 12);
}

// The positions of the vertices that leaves [begin, end) own, at their ids.
void Builder::place_owned_vertices(std::size_t begin, std::size_t end) {
  for (std::size_t k = begin; k < end; ++k) {
    const Node& n = tree_.nodes[leaves_[k]];
    const unsigned l = n.level;
    const std::int64_t ix = n.ix, iy = n.iy;
    const unsigned mask = own_mask_[k];
    Point* out = gpos_.data() + own_base_[k];
    *out++ = {tree_.X(ix, l), tree_.Y(iy, l)};
    if ((mask >> kOwnLeftMid) & 1u) *out++ = {tree_.X(ix, l), tree_.Y(2 * iy + 1, l + 1)};
    if ((mask >> kOwnBottomMid) & 1u) *out++ = {tree_.X(2 * ix + 1, l + 1), tree_.Y(iy, l)};
    if ((mask >> kOwnUL) & 1u) *out++ = {tree_.X(ix, l), tree_.Y(iy + 1, l)};
    if ((mask >> kOwnLR) & 1u) *out++ = {tree_.X(ix + 1, l), tree_.Y(iy, l)};
    if ((mask >> kOwnUR) & 1u) *out++ = {tree_.X(ix + 1, l), tree_.Y(iy + 1, l)};
  }
}

// ==== grid vertices ends here ====================================================================

// ==== loops begins here ==========================================================================

// Each leaf's loop of up to 8 grid vertices (packed, see PackedLoop), the deepest and shallowest
// leaf level around each grid vertex, and the leaves with an input vertex or a segment.
void Builder::build_loops() {
  for (auto& half : with_vertex_) half.clear();
  for (auto& half : near_segment_) half.clear();
  if (grid_count_ > kLoopIdMask) throw RouteFailure{"too many grid vertices"};
  loops_ = std::make_unique_for_overwrite<PackedLoop[]>(leaves_.size());
  // With the loops, the deepest and shallowest leaf level around each grid vertex: each thread
  // updates the vertices that the leaves of its half own (ids are given in leaf order, so they are
  // a range); the few vertices owned by a leaf of the other half, near where the halves meet, are
  // set after both (max and min do not depend on the order).
  glevel_.assign(grid_count_, 0);
  gtop_.assign(grid_count_, 255);
  const std::size_t leaf_count = leaves_.size();
  std::array<std::vector<std::pair<std::uint32_t, std::uint8_t>>, 2> across_halves;
  std::array<std::vector<std::array<std::uint32_t, 2>>, 2> both_mids_per_half;
  support::parallel_ranges(workers_for(leaf_count, threaded_leaves_), leaf_count,
      [&](std::size_t half, std::size_t begin, std::size_t end) {
    auto& with_vertex = with_vertex_[half];
    auto& near_segment = near_segment_[half];
    auto& both_mids = both_mids_per_half[half];
    const std::uint32_t lo = own_base_[begin], hi = end == leaf_count ? grid_count_ : own_base_[end];
    auto& later = across_halves[half];
    for (auto k = static_cast<std::uint32_t>(begin); k < end; ++k) {
      check_deadline_at(k - begin, options_.deadline);
      prefetch_neighbours(k, end, 0, 1);  // east, north
      const std::uint32_t a = leaves_[k];
      const Node& n = tree_.nodes[a];
      if (n.vertex != kNone) with_vertex.push_back(k);
      if ((n.state & kHasSegment) != 0) near_segment.push_back(k);
      const std::array<std::uint32_t, 8> loop = find_loop(k);
      const unsigned l = n.level;
      // Packed (see PackedLoop): the own midpoints follow the corner's id.
      std::uint32_t head = loop[kBL];
      if (loop[kLeft] != kNone) head |= kHasLeftMid;
      if (loop[kBottom] != kNone) head |= kHasBottomMid;
      if (loop[kRight] != kNone) head |= kHasRightMid;
      if (loop[kTop] != kNone) head |= kHasTopMid;
      if (loop[kRight] != kNone && loop[kTop] != kNone) both_mids.push_back({k, loop[kTop]});
      loops_[k] = {head, loop[kBR], loop[kTR], loop[kTL], loop[kRight] != kNone ? loop[kRight] : loop[kTop]};
      const auto level = static_cast<std::uint8_t>(l);
      for (unsigned slot = 0; slot < 8; ++slot) {
        const std::uint32_t g = loop[slot];
        if (g == kNone) continue;
        if (g < lo || g >= hi) {
          later.emplace_back(g, level);
          continue;
        }
        glevel_[g] = std::max(glevel_[g], level);
        gtop_[g] = std::min(gtop_[g], level);
      }
    }
  });
  for (const auto& list : across_halves) {
    for (const auto& [g, l] : list) {
      glevel_[g] = std::max(glevel_[g], l);
      gtop_[g] = std::min(gtop_[g], l);
    }
  }
  both_mids_ = std::move(both_mids_per_half[0]);
  both_mids_.insert(both_mids_.end(), both_mids_per_half[1].begin(), both_mids_per_half[1].end());
  // Dead from here on (own() is never called again; neither are the tree's look-ups, whose last
  // use is above): lent to the arrays made later (final_id_, cell_bound_, ...).
  spare_.lend(own_storage_.get(), own_storage_bytes());
  tree_.lend_hints(spare_);
}

// Leaf k's loop: its own vertices, and the others through the same-size cells east, north and
// north-east (each looked up once), as slots kBL … kLeft.
std::array<std::uint32_t, 8> Builder::find_loop(std::uint32_t k) const {
  const std::uint32_t a = leaves_[k];
  const Node& n = tree_.nodes[a];
  const unsigned l = n.level;
  const std::int64_t side = std::int64_t{1} << l, ix = n.ix, iy = n.iy;
  const bool top = iy + 1 == side, right = ix + 1 == side;
  std::array<std::uint32_t, 8> loop;
  loop.fill(kNone);
  loop[kBL] = own(k, kOwnLL);
  if ((own_mask_[k] >> kOwnBottomMid) & 1u) loop[kBottom] = own(k, kOwnBottomMid);
  if ((own_mask_[k] >> kOwnLeftMid) & 1u) loop[kLeft] = own(k, kOwnLeftMid);
  // The same-size cells east and north (each looked up once).
  const std::uint32_t r = right ? kNone : tree_.neighbour(a, 0);
  const std::uint32_t t = top ? kNone : tree_.neighbour(a, 1);
  loop[kBR] = right ? own(k, kOwnLR) : vertex_at(leaf_sw(r), l, ix + 1, iy);
  if (top && right) {
    loop[kTR] = own(k, kOwnUR);
  } else if (top) {
    // The leaf to the east along the root's top border: (xR, yT) is its upper-left corner.
    std::uint32_t d = r;
    while (!tree_.is_leaf(d)) d = tree_.nodes[d].child + 2;
    loop[kTR] = own(leaf_of(d), kOwnUL);
  } else if (right) {
    std::uint32_t d = t;
    while (!tree_.is_leaf(d)) d = tree_.nodes[d].child + 1;
    loop[kTR] = own(leaf_of(d), kOwnLR);
  } else {
    // (Tree::cell_at(a, 1, 1), from the east cell found above.)
    loop[kTR] = vertex_at(leaf_sw(tree_.diagonal(a, r, 1, 1)), l, ix + 1, iy + 1);
  }
  loop[kTL] = top ? own(k, kOwnUL) : vertex_at(leaf_sw(t), l, ix, iy + 1);
  if (!right) {
    if (tree_.nodes[r].level == l && !tree_.is_leaf(r)) {
      const std::uint32_t nw = tree_.nodes[r].child + 2;
      if (!tree_.is_leaf(nw)) throw RouteFailure{"unbalanced quadtree"};
      loop[kRight] = own(leaf_of(nw), kOwnLL);
    }
  }
  if (!top) {
    if (tree_.nodes[t].level == l && !tree_.is_leaf(t)) {
      const std::uint32_t se = tree_.nodes[t].child + 1;
      if (!tree_.is_leaf(se)) throw RouteFailure{"unbalanced quadtree"};
      loop[kTop] = own(leaf_of(se), kOwnLL);
    }
  }
  return loop;
}

// ==== loops ends here ============================================================================

// ==== warping onto input vertices begins here ====================================================

// BEG's warp: the corner of its leaf nearest each input vertex moves onto it.
void Builder::warp() {
  gwarped_.reserve(gpos_.capacity());
  gwarped_.assign(grid_count_, false);
  gmoved_.reserve(gpos_.capacity());
  gmoved_.assign(grid_count_, false);
  reserve_room(input_gv_, pts_.size());
  input_gv_.assign(pts_.size(), kNone);
  // Each leaf knows the input vertex in its half-open square (at most one: the splitting rule);
  // build_loops() listed the leaves with one, in order.
  for (const auto& half : with_vertex_) {
    for (const std::uint32_t k : half) {
      const Node& n = tree_.nodes[leaves_[k]];
      const VertexId v = tree_.vertex_id(n.vertex);
      const Point& q = tree_.vertex_point(n.vertex);
      unsigned qx = 0, qy = 0;
      tree_.nearest_corner(n, q, qx, qy);
      static constexpr unsigned kCornerSlot[2][2] = {{kBL, kTL}, {kBR, kTR}};  // [qx][qy]
      const std::uint32_t g = loop_of(k)[kCornerSlot[qx][qy]];
      if (gwarped_[g] || input_gv_[v] != kNone) throw RouteFailure{"two input vertices warp the same corner"};
      gwarped_[g] = true;
      gmoved_[g] = true;
      gpos_[g] = q;
      input_gv_[v] = g;
      ++stats_.warped;
    }
  }
  for (auto& half : with_vertex_) std::vector<std::uint32_t>().swap(half);
  for (VertexId v : in_.vertices) {
    if (input_gv_[v] == kNone) throw RouteFailure{"an input vertex lies in no leaf"};
  }
}

// ==== warping onto input vertices ends here ======================================================

}  // namespace mwst::qtr
