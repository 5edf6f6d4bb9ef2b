// algorithms/quadtree/tree_balance.cpp — Tree::finish(): balance (edge-adjacent leaves differ by at
// most one level) and the warp rule (the four leaves around the corner a vertex will take have the
// vertex's leaf size), to a fixed point. A last-in-first-out work list whose result depends on its
// order; on large trees two region lanes (west and east of a split line) run at once and a last
// lane over the whole tree finishes the leaves they deferred, in the order one thread would use.
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "algorithms/quadtree/tree.hpp"

namespace mwst::qtr {

// ==== the lanes begins here ======================================================================

// Balance and warp rule, to a fixed point.
//
// The work list's result depends on its order (the warp rule can ask for a split that a later
// split would have made unnecessary), so the order is fixed whatever the number of threads:
// first the west lane and the east lane, each with the leaves on its side of the split line (a
// vertical grid line with about half of the leaves on each side); a region lane reads and
// writes only nodes on its side (and ancestors and leaves the line crosses, which it never
// changes), defers every leaf whose check would reach across the line (a cell in the column
// next to it, or a split of one), and allocates in its own block of the arrays; then the blocks
// are joined and one lane over the whole tree works through the deferred leaves. The two region
// lanes run at the same time on large inputs and one after the other on small ones; the tree is
// the same.
void Tree::finish() {
  // The first round checks every leaf, and almost all pass: that round is done as a read-only
  // scan in two halves on two threads, and only the leaves that fail it are queued, in the same
  // order. This changes nothing: a leaf that passed at the start and is changed later is queued
  // again by the change (below) and checked after it, so its first-round check would have been
  // a no-op too.
  // The same scan counts the leaves per column of level lane_level_ (at most 10), to place the
  // lanes' split line.
  const auto node_count = static_cast<std::uint32_t>(nodes.size());
  std::vector<std::uint8_t> fails(node_count, 0);
  lane_level_ = std::min(10u, max_level_);
  std::array<std::vector<std::uint32_t>, 2> leaves_per_column;
  for (auto& count : leaves_per_column) count.assign(std::size_t{1} << lane_level_, 0);
  support::parallel_ranges(workers_for(node_count, threaded_nodes_), node_count,
      [&](std::size_t half, std::size_t begin, std::size_t end) {
    std::vector<std::uint32_t>& count = leaves_per_column[half];
    for (auto a = static_cast<std::uint32_t>(begin); a < end; ++a) {
      check_deadline_at(a - begin, deadline_);
      if (!is_leaf(a)) continue;
      ++count[lane_column_of(nodes[a])];
      fails[a] = fails_check(a) ? 1 : 0;
    }
  });
  choose_split_line(leaves_per_column);
  // Each region lane gets room for as many nodes and list entries as the tree has now (a
  // uniform point set needs about 0.7 of that in the busier half; a lane that runs out defers
  // the rest of its list). The room is never written unless used.
  const std::size_t feature_count = features.size();
  const std::size_t id_limit = std::numeric_limits<std::uint32_t>::max() - 8u;
  // (Never beyond the leaf limit: a lane that fills its room defers, and the last lane refuses.)
  const std::size_t node_room =
      std::min({std::size_t{node_count} + 64u, (id_limit - node_count) / 2, (node_limit() - node_count) / 2}) / 4 * 4;
  const std::size_t feature_room = std::min<std::size_t>(feature_count + 256u, (id_limit - feature_count) / 2);
  nodes.resize(node_count + 2 * node_room);
  outer_hint_.resize(groups(node_count + 2 * node_room));
  features.resize(feature_count + 2 * feature_room);
  std::array<Lane, 2> lanes;
  for (unsigned r = 0; r < 2; ++r) {
    Lane& lane = lanes[r];
    lane.region = static_cast<int>(r);
    lane.node_begin = static_cast<std::uint32_t>(node_count + r * node_room);
    lane.node_next = lane.node_begin;
    lane.node_end = static_cast<std::uint32_t>(lane.node_next + node_room);
    lane.feature_next = feature_count + r * feature_room;
    lane.feature_end = lane.feature_next + feature_room;
    reserve_room(lane.work, node_count / 2 + 64);
  }
  for (std::uint32_t a = 0; a < node_count; ++a) {
    if (!fails[a]) continue;
    const int region = side_of_split_line(nodes[a]);
    if (region < 0) {
      lanes[0].deferred.push_back(a);
    } else {
      lanes[static_cast<unsigned>(region)].work.push_back(a);
    }
  }
  std::vector<std::uint8_t>().swap(fails);
  // The work lists are complete: a balance violation needs a new leaf (each new leaf is
  // queued), and a warp-rule violation needs a split of one of the cells around the vertex's
  // corner (split() queues the vertex leaves whose corner cells it splits); a deferred leaf
  // stays queued for the last lane.
  const std::size_t threshold = node_count >= threaded_nodes_ ? 0 : std::numeric_limits<std::size_t>::max();
  support::parallel_ranges(workers_for(2, threshold), 2, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t r = begin; r < end; ++r) run(lanes[r]);
  });
  join_lanes(node_count, feature_count, node_room, feature_room, lanes);
  Lane whole;
  whole.work = std::move(lanes[0].deferred);
  whole.work.insert(whole.work.end(), lanes[1].deferred.begin(), lanes[1].deferred.end());
  run(whole);
  for (const Lane* lane : {&lanes[0], &lanes[1], &whole}) {
    stats_.splits_feature += lane->splits_feature;
    stats_.splits_balance += lane->splits_balance;
    stats_.splits_warp += lane->splits_warp;
    deepest_ = std::max(deepest_, lane->deepest);
  }
  stats_.unresolved = count_unresolved();
  // (The nodes stay in creation order, breadth first and then split by split: copying them depth
  // first for locality cost more than it saved later, 1.0–1.5 s of 14 at a million points.)
}

// After the region lanes: moves the east lane's block of nodes and list entries down to follow
// the west lane's, renumbering the references into it on the way, and trims the arrays. Only
// the east lane's nodes and the older nodes it split (their child) refer to its block: the
// west lane's hints point into its own half, and older nodes' hints are older nodes.
void Tree::join_lanes(std::size_t node_count, std::size_t feature_count, std::size_t node_room,
                      std::size_t feature_room, std::array<Lane, 2>& lanes) {
  const std::size_t used0 = lanes[0].node_next - node_count;
  const std::size_t base1 = lanes[1].node_begin;
  const std::size_t used1 = lanes[1].node_next - base1;
  const std::size_t shift = node_room - used0;
  const std::size_t feature_used0 = lanes[0].feature_next - feature_count;
  const std::size_t feature_base1 = feature_count + feature_room;
  const std::size_t feature_used1 = lanes[1].feature_next - feature_base1;
  const auto feature_shift = static_cast<std::uint32_t>(feature_room - feature_used0);
  const auto renumber = [&](std::uint32_t& id) {
    if (id != kNone && id >= base1) id -= static_cast<std::uint32_t>(shift);
  };
  // In rounds of `shift` nodes, so that no round writes where it or a later one still reads;
  // each round in two halves.
  for (std::size_t round = 0; shift > 0 && round < used1; round += shift) {
    const std::size_t count = std::min(shift, used1 - round);
    support::parallel_ranges(workers_for(count, threaded_nodes_), count,
        [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t i = round + begin; i < round + end; ++i) {
        Node n = nodes[base1 + i];
        renumber(n.parent);
        renumber(n.child);
        n.feat_begin -= feature_shift;
        nodes[base1 + i - shift] = n;
        if (i % 4 == 0) {  // the first of a group of siblings (base1 − 1 and shift are multiples of 4)
          std::array<std::uint32_t, 4> h = outer_hint_[(base1 + i - 1) / 4];
          for (std::uint32_t& id : h) renumber(id);
          outer_hint_[(base1 + i - shift - 1) / 4] = h;
        }
      }
    });
  }
  for (const std::uint32_t a : lanes[1].split_before) renumber(nodes[a].child);
  std::copy(features.begin() + static_cast<std::ptrdiff_t>(feature_base1),
            features.begin() + static_cast<std::ptrdiff_t>(feature_base1 + feature_used1),
            features.begin() + static_cast<std::ptrdiff_t>(feature_count + feature_used0));
  nodes.resize(node_count + used0 + used1);
  outer_hint_.resize(groups(node_count + used0 + used1));
  features.resize(feature_count + feature_used0 + feature_used1);
  east_group_block_ = {(base1 - 1) / 4, (base1 - 1 + used1) / 4};
  east_feature_block_ = {feature_base1, feature_base1 + feature_used1};
  for (Lane& lane : lanes) {
    for (std::uint32_t& id : lane.deferred) renumber(id);
  }
}

// Chooses the split line: the column boundary of level lane_level_ with about half of the
// leaves (a proxy for the work of the lanes) on each side, given the leaves per column (two
// counts, one per half of the first round of checks).
void Tree::choose_split_line(const std::array<std::vector<std::uint32_t>, 2>& leaves_per_column) {
  const std::size_t columns = leaves_per_column[0].size();
  std::size_t total = 0;
  for (std::size_t k = 0; k < columns; ++k) total += std::size_t{leaves_per_column[0][k]} + leaves_per_column[1][k];
  std::size_t below = 0;
  lane_column_ = static_cast<std::int64_t>(columns / 2);
  for (std::size_t k = 1; k < columns; ++k) {
    below += std::size_t{leaves_per_column[0][k - 1]} + leaves_per_column[1][k - 1];
    if (2 * below >= total) {
      lane_column_ = static_cast<std::int64_t>(k);
      break;
    }
  }
}

// Would check(a) split anything now? (The same tests, read only.)
bool Tree::fails_check(std::uint32_t a) const {
  const Node& n = nodes[a];
  const unsigned l = n.level;
  if (n.state & kFresh) return true;
  if (l > 0) {
    const bool odd_x = (n.ix & 1) != 0, odd_y = (n.iy & 1) != 0;
    for (unsigned d = 0; d < 4; ++d) {
      const bool sibling = d == 0 ? !odd_x : d == 2 ? odd_x : d == 1 ? !odd_y : odd_y;
      if (sibling || (n.state & (kBalanced << d)) != 0) continue;
      const std::uint32_t h = hint(a, d);
      if (h == kNone || nodes[h].level + 1u >= l) continue;
      const std::uint32_t b = neighbour(a, d);
      if (b != kNone && nodes[b].level + 1u < l) return true;
    }
  }
  const std::uint32_t v = n.vertex;
  if (v == kNone) return false;
  unsigned qx = 0, qy = 0;
  nearest_corner(n, rank_point_[v], qx, qy);
  for (int dy = -1; dy <= 0; ++dy) {
    for (int dx = -1; dx <= 0; ++dx) {
      const std::uint32_t b = cell_at(a, static_cast<int>(qx) + dx, static_cast<int>(qy) + dy);
      if (b == kNone || b == a) continue;
      if (nodes[b].level < l) return true;
      if (is_leaf(b)) continue;
      return l < max_level_;
    }
  }
  return false;
}

// Works through the lane's list, last in first out (what it touches stays in cache). A region
// lane that runs out of room defers the rest of its list.
void Tree::run(Lane& lane) {
  for (std::size_t checks = 0; !lane.work.empty(); ++checks) {
    check_deadline_at(checks, deadline_);  // (both region lanes check: each stops on its own)
    if (lane.full) {
      lane.deferred.insert(lane.deferred.end(), lane.work.begin(), lane.work.end());
      lane.work.clear();
      break;
    }
    const std::uint32_t a = lane.work.back();
    lane.work.pop_back();
    // (Most checks pass after a few reads: the next leaf's node and hints are fetched early.)
    if (!lane.work.empty()) {
      __builtin_prefetch(&nodes[lane.work.back()]);
      const std::uint32_t next = lane.work.back();
      if (next != 0) __builtin_prefetch(&outer_hint_[(next - 1) >> 2]);
    }
    check(a, lane);
  }
}

// ==== the lanes ends here ========================================================================

// ==== checking and splitting one leaf begins here ================================================

// Checks leaf a against the feature rule (if fresh), balance and the warp rule, splitting what
// must be split. A region lane defers a (leaves it for the whole-tree lane) where that would
// reach across the split line or past its room.
void Tree::check(std::uint32_t a, Lane& lane) {
  if (!is_leaf(a)) return;
  if (lane.region >= 0 && near_split_line(nodes[a])) {
    lane.deferred.push_back(a);
    return;
  }
  const unsigned l = nodes[a].level;
  if (nodes[a].state & kFresh) {
    const Node& n = nodes[a];
    if (l < max_level_ && feature_split(n, features.data() + n.feat_begin, n.feat_count)) {
      if (split_for(lane, a, a, lane.splits_feature)) {
        nodes[a].state = static_cast<std::uint8_t>(nodes[a].state & ~kFresh);
      }
      return;
    }
    nodes[a].state = static_cast<std::uint8_t>(nodes[a].state & ~kFresh);
  }
  bool changed = false;
  // Balance: an edge neighbour more than one level coarser is split. Two of a's edge neighbours
  // are its siblings (never coarser); across the other two, the hint covers the parent's
  // neighbour cell, and a hint at level l − 1 already proves the neighbour fine enough.
  const bool odd_x = (nodes[a].ix & 1) != 0, odd_y = (nodes[a].iy & 1) != 0;  // (nodes may move when b splits)
  const std::uint8_t state = nodes[a].state;
  for (unsigned d = 0; d < 4; ++d) {
    if (l == 0) break;
    const bool sibling = d == 0 ? !odd_x : d == 2 ? odd_x : d == 1 ? !odd_y : odd_y;
    if (sibling || (state & (kBalanced << d)) != 0) continue;
    const std::uint32_t h = hint(a, d);
    if (h == kNone || nodes[h].level + 1u >= l) continue;
    const std::uint32_t b = neighbour(a, d);
    if (b != kNone && nodes[b].level + 1u < l) {
      if (!split_for(lane, a, b, lane.splits_balance)) return;
      changed = true;
    }
  }
  if (changed) return;
  // Warp rule: the four leaves around the corner the vertex will move have a's size. A finer
  // one means a is split (the vertex gets a smaller leaf); a coarser one is split itself.
  const std::uint32_t v = nodes[a].vertex;
  if (v != kNone) {
    unsigned qx = 0, qy = 0;
    nearest_corner(nodes[a], rank_point_[v], qx, qy);
    // The cells around corner (ix + qx, iy + qy).
    for (int dy = -1; dy <= 0; ++dy) {
      for (int dx = -1; dx <= 0; ++dx) {
        const std::uint32_t b = cell_at(a, static_cast<int>(qx) + dx, static_cast<int>(qy) + dy);
        if (b == kNone || b == a) continue;
        if (nodes[b].level < l) {
          split_for(lane, a, b, lane.splits_warp);
          return;
        }
        if (is_leaf(b)) continue;
        if (l >= max_level_) return;  // counted by count_unresolved()
        split_for(lane, a, a, lane.splits_warp);
        return;
      }
    }
  }
}

// Splits leaf b for the check of leaf a (counted in `counter`) and queues a again if it is still
// a leaf; returns false, with a deferred instead, where the lane may not split b.
bool Tree::split_for(Lane& lane, std::uint32_t a, std::uint32_t b, std::size_t& counter) {
  if (!may_split(lane, b)) {
    lane.deferred.push_back(a);
    return false;
  }
  ++counter;
  split(b, lane);
  if (b != a) lane.work.push_back(a);
  return true;
}

// May the lane split leaf b? A region lane splits only cells off the split line, within its room.
bool Tree::may_split(Lane& lane, std::uint32_t b) {
  if (lane.region < 0) return true;
  const Node& n = nodes[b];
  if (near_split_line(n)) return false;
  if (lane.node_next + 4u > lane.node_end || lane.feature_next + 4u * std::size_t{n.feat_count} > lane.feature_end) {
    lane.full = true;
    return false;
  }
  return true;
}

// Splits leaf a; children get the features of a's list that meet their extended cells.
void Tree::split(std::uint32_t a, Lane& lane) {
  const Node n = nodes[a];
  auto& lists = lane.lists;
  for (auto& list : lists) list.clear();
  // (The parent's list is read in place: filtering writes only to the lane's lists.)
  filter_children(n, features.data() + n.feat_begin, n.feat_count, lists);
  std::size_t list_total = 0;
  for (const auto& list : lists) list_total += list.size();
  std::uint32_t first = 0;
  std::size_t place = 0;
  if (lane.region < 0) {
    if (nodes.size() + 4u >= kNone || features.size() + list_total > std::numeric_limits<std::uint32_t>::max()) {
      throw RouteFailure{"too many quadtree nodes"};
    }
    refuse_beyond_leaf_limit(nodes.size() + 4u);
    first = static_cast<std::uint32_t>(nodes.size());
    nodes.resize(first + 4u);
    outer_hint_.resize(groups(first + 4u));
    place = features.size();
    features.resize(place + list_total);
  } else {
    first = lane.node_next;
    lane.node_next += 4u;
    place = lane.feature_next;
    lane.feature_next += list_total;
  }
  nodes[a].child = first;
  if (lane.region >= 0 && a < lane.node_begin) lane.split_before.push_back(a);
  lane.deepest = std::max(lane.deepest, n.level + 1u);
  for (unsigned k = 0; k < 4; ++k) {
    Node c;
    c.ix = 2 * n.ix + (k & 1);
    c.iy = 2 * n.iy + (k >> 1);
    c.parent = a;
    c.level = static_cast<std::uint8_t>(n.level + 1);
    c.state = has_segment(lists[k].data(), lists[k].size()) ? kFresh | kHasSegment : kFresh;
    c.feat_begin = static_cast<std::uint32_t>(place);
    c.feat_count = static_cast<std::uint32_t>(lists[k].size());
    std::copy(lists[k].begin(), lists[k].end(), features.begin() + static_cast<std::ptrdiff_t>(place));
    place += lists[k].size();
    c.vertex = vertex_in(c, lists[k].data(), lists[k].size());
    nodes[first + k] = c;
    lane.work.push_back(first + k);
  }
  // a's edge neighbours, for the children's hints and for the look below (the children lie
  // inside a, so they change none of them).
  const std::array<std::uint32_t, 4> edge = edge_neighbours(a);
  set_child_hints(a, edge);
  // A leaf around a that this split can make fail its check is looked at again (the edge
  // neighbours, then the diagonal ones, found from the east and west neighbours). Only the warp
  // rule can newly fail: a split makes no leaf coarser, so no balance test of a neighbour turns
  // false, and the children (fresh) are queued above. It fails for a leaf b of a's size whose
  // vertex will take a corner of a: a is one of the four cells around that corner and is no
  // longer a leaf. A leaf already failing is queued already. (Queueing every neighbour made
  // 21.7M checks instead of 12.2M at a million uniform points, nearly all of them passing.)
  const auto warp_corner_touches_a = [&](std::uint32_t b) {
    if (b == kNone) return false;
    const Node& m = nodes[b];
    if ((m.child & kLeafBit) == 0 || m.vertex == kNone || m.level != n.level) return false;
    unsigned qx = 0, qy = 0;
    nearest_corner(m, rank_point_[m.vertex], qx, qy);
    const std::int64_t cx = m.ix + qx, cy = m.iy + qy;  // the corner, in grid lines of the level
    return (n.ix == cx - 1 || n.ix == cx) && (n.iy == cy - 1 || n.iy == cy);
  };
  for (unsigned d = 0; d < 4; ++d) {
    if (warp_corner_touches_a(edge[d])) lane.work.push_back(edge[d]);
  }
  for (const int dx : {1, -1}) {
    const std::uint32_t side = edge[dx > 0 ? 0u : 2u];
    if (side == kNone) continue;
    for (const int dy : {1, -1}) {
      const std::uint32_t b = diagonal(a, side, dx, dy);
      if (warp_corner_touches_a(b)) lane.work.push_back(b);
    }
  }
}

// ==== checking and splitting one leaf ends here ==================================================

// Leaves at the deepest level that still break the feature rule or the warp rule.
std::size_t Tree::count_unresolved() const {
  if (deepest_ < max_level_) return 0;  // (no leaf at the deepest level: skip the pass over the nodes)
  std::size_t count = 0;
  for (std::uint32_t a = 0; a < nodes.size(); ++a) {
    if (!is_leaf(a) || nodes[a].level < max_level_) continue;
    const Node& n = nodes[a];
    bool bad = feature_split(n, features.data() + n.feat_begin, n.feat_count);
    const std::uint32_t v = n.vertex;
    if (!bad && v != kNone) {
      unsigned qx = 0, qy = 0;
      nearest_corner(n, rank_point_[v], qx, qy);
      for (int dy = -1; dy <= 0; ++dy) {
        for (int dx = -1; dx <= 0; ++dx) {
          const std::uint32_t b = find(a, n.level, n.ix + qx + dx, n.iy + qy + dy);
          if (b != kNone && b != a && (nodes[b].level != n.level || !is_leaf(b))) bad = true;
        }
      }
    }
    count += bad ? 1 : 0;
  }
  return count;
}

}  // namespace mwst::qtr
