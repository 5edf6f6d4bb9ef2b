// algorithms/quadtree/tree.hpp — stage 2 of quadtree refinement: the balanced quadtree.
// Nodes live in one flat array (NodeArray); the four children of a node are consecutive (SW, SE,
// NW, NE: Morton order) and a node is addressed by (level, ix, iy), so every cell corner is the
// same double however it is reached. Each leaf keeps the features (vertex ranks in Morton order,
// then segment indices offset by the vertex count) meeting its extended cell. Neighbours are found
// from per-node hints without climbing (neighbour(), cell_at()). The steps, in order:
//   Tree()          the root square and the vertices' Morton ranks            (tree_build.cpp)
//   build()         split by BEG's feature rule, level by level               (tree_build.cpp)
//   finish()        balance and the warp rule to a fixed point, in lanes      (tree_balance.cpp)
//   leaves_in_order(), number_leaves(), lend_*(), give_node_storage()
//                   what the Builder reads, and the memory it takes over      (tree_build.cpp)
// The look-ups below are inline: they run per leaf and per check.
#pragma once

#include <algorithm>
#include <array>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "algorithms/quadtree/route.hpp"
#include "support/spare_room.hpp"

namespace mwst::qtr {

using support::SpareRoom;
using support::UninitializedAllocator;

// Reserves room for n elements up front: the big arrays are written once, and growing them by
// doubling would copy them (and touch their pages twice).
template <class T, class Allocator>
inline void reserve_room(std::vector<T, Allocator>& v, std::size_t n) {
  v.reserve(n);
}

// The four children's feature lists while a node is split: filter_children() makes room for a
// whole parent list in each and writes through pointers, so new room is left unwritten.
using FeatureList = std::vector<std::uint32_t, UninitializedAllocator<std::uint32_t>>;

// ---- nodes ---------------------------------------------------------------------------------------

constexpr std::uint8_t kFresh = 1;  // created after the first build: still to be checked
// Node::state bit (kBalanced << d): the hint in direction d is at the parent's level or there is
// no cell that way, so no edge neighbour that way is ever more than one level coarser (check()
// then skips reading the hint's node, a cache miss per leaf).
constexpr std::uint8_t kBalanced = 2;
// Node::state bit of a leaf whose feature list holds a segment (set where the list is written, so
// that the mesh passes find these leaves without reading every list).
constexpr std::uint8_t kHasSegment = 32;

// Node::child of a leaf has this bit set (kNone has it too): the Builder numbers the leaves there
// (Tree::number_leaves()), so a node's leaf ordinal is read from the node itself, with no array
// indexed by node.
constexpr std::uint32_t kLeafBit = 0x80000000u;

struct Node {
  std::int64_t ix = 0, iy = 0;         // cell index at its level
  std::uint32_t parent = kNone;
  std::uint32_t child = kNone;         // first of four consecutive children; for a leaf kNone, and
                                       // from Builder::number_vertices() on kLeafBit | its ordinal
  std::uint32_t feat_begin = 0;        // leaves: features meeting the closed B(C) in Tree::features
  std::uint32_t feat_count = 0;
  std::uint32_t vertex = kNone;        // leaves: the input vertex in the half-open cell, if any, as
                                       // its Morton rank (Tree::vertex_id, Tree::vertex_point)
  std::uint8_t level = 0;
  std::uint8_t state = 0;
};

struct Box {
  double x1, y1, x2, y2;
};

// The tree's nodes, kept in the address range that becomes the mesh's triangle array. The nodes
// are the largest array of the run (40 bytes per node, 1.3 nodes per leaf) and are dead once the
// Builder has read what it needs from them, just before the cells' triangles (2.4 per leaf, 24
// bytes each) are written: so they live in the capacity of a std::vector<Triangle> that the
// Builder hands to the mesh (Tree::give_node_storage()), and the triangles are written over pages
// the nodes already touched (the kernel clears each page of fresh memory on its first touch,
// which at a million points is a large part of the run). New elements of resize() are left
// unwritten, as with UninitializedAllocator: the arrays are sized up front for finish()'s lanes.
class NodeArray {
 public:
  static_assert(std::is_trivially_copyable_v<Node> && alignof(Node) <= alignof(std::max_align_t));
  NodeArray() = default;
  NodeArray(const NodeArray&) = delete;  // (a copy of the empty storage would alias the nodes)
  NodeArray& operator=(const NodeArray&) = delete;
  std::size_t size() const { return size_; }
  std::size_t capacity() const { return capacity_; }
  Node* data() { return data_; }
  const Node* data() const { return data_; }
  Node& operator[](std::size_t i) { return data_[i]; }
  const Node& operator[](std::size_t i) const { return data_[i]; }
  void clear() { size_ = 0; }
  void reserve(std::size_t n) {
    if (n <= capacity_) return;
    std::vector<Triangle> grown;
    grown.reserve((n * sizeof(Node) + sizeof(Triangle) - 1) / sizeof(Triangle));
    // The storage is raw room for nodes (the vector holds no Triangle until the mesh takes it).
    Node* const moved = reinterpret_cast<Node*>(grown.data());
    if (size_ > 0) std::memcpy(static_cast<void*>(moved), data_, size_ * sizeof(Node));
    storage_ = std::move(grown);
    data_ = moved;
    capacity_ = storage_.capacity() * sizeof(Triangle) / sizeof(Node);
  }
  void resize(std::size_t n) {
    if (n > capacity_) reserve(std::max(n, capacity_ / 2 * 3));
    size_ = n;
  }
  void push_back(const Node& node) {
    if (size_ == capacity_) reserve(std::max<std::size_t>(64, capacity_ * 2));
    std::memcpy(static_cast<void*>(data_ + size_), &node, sizeof(Node));
    ++size_;
  }
  // The storage, as an empty triangle array with its capacity: the nodes stay readable where they
  // are until that array is written (or freed), and the tree no longer owns them.
  std::vector<Triangle> give_storage() { return std::move(storage_); }

 private:
  std::vector<Triangle> storage_;  // size 0: only its capacity is used
  Node* data_ = nullptr;
  std::size_t size_ = 0, capacity_ = 0;
};
inline void reserve_room(NodeArray& v, std::size_t n) { v.reserve(n); }

// ---- the tree --------------------------------------------------------------------------------------

class Tree {
 public:
  // ---- the steps, in order ----
  // The root: a power-of-two square at least twice the bounding box; the vertices in Morton order.
  Tree(const CleanInput& in, const QuadtreeOptions& options, QuadtreeStats& stats);
  // First build: breadth first, splitting by the feature rule.
  void build();
  // Balance and warp rule, to a fixed point (two region lanes, then one over the whole tree).
  void finish();

  // QuadtreeOptions::max_leaves, resolved for a clean input of `features` vertices and segments.
  static std::size_t leaf_limit(const QuadtreeOptions& options, std::size_t features);

  // ---- for the Builder ----
  // Leaves in Morton (Z) order.
  std::vector<std::uint32_t> leaves_in_order() const;
  // Writes each leaf's ordinal in Morton order into its child field (kLeafBit | k).
  void number_leaves(const std::vector<std::uint32_t>& leaves, std::size_t threaded);
  // After finish(): lends the dead tails of the lanes' blocks to `room`.
  void lend_dead_room(SpareRoom& room);
  // After the last neighbour look-up: lends the hints to `room`; no look-up may follow.
  void lend_hints(SpareRoom& room);

  // The nodes' storage, for the mesh's triangles (NodeArray::give_storage()): the nodes may still
  // be read until the first triangle is written, and not after.
  std::vector<Triangle> give_node_storage() { return nodes.give_storage(); }

  // ---- look-ups (inline: they run per leaf, per check and per list entry) ----
  // Plane coordinates of grid line i at a level (i may lie one or two cells outside the root).
  // (The products are exact: an integer below 2^53 times a power of two.)
  double X(std::int64_t i, unsigned level) const { return x0_ + static_cast<double>(i) * step_[level]; }
  double Y(std::int64_t i, unsigned level) const { return y0_ + static_cast<double>(i) * step_[level]; }
  double cell_size(unsigned level) const { return step_[level]; }
  Box box(const Node& n) const {
    return {X(n.ix, n.level), Y(n.iy, n.level), X(n.ix + 1, n.level),
            Y(n.iy + 1, n.level)};
  }

  bool is_vertex(std::uint32_t f) const { return f < nv_; }
  const FeatureSegment& segment(std::uint32_t f) const { return in_.segments[f - nv_]; }
  std::uint32_t vertex_count() const { return nv_; }

  // Does feature f meet the closed box? Exact (a segment and a box are convex: separating axes
  // x, y and the segment's normal, the last decided by orient2d at the box corners).
  bool meets(std::uint32_t f, const Box& b) const {
    if (is_vertex(f)) {
      const Point& q = rank_point_[f];
      return b.x1 <= q.x && q.x <= b.x2 && b.y1 <= q.y && q.y <= b.y2;
    }
    const FeatureSegment& s = segment(f);
    const Point& p = pts_[s.a];
    const Point& q = pts_[s.b];
    if (std::max(p.x, q.x) < b.x1 || std::min(p.x, q.x) > b.x2 || std::max(p.y, q.y) < b.y1 ||
        std::min(p.y, q.y) > b.y2) {
      return false;
    }
    const int o1 = orient2d(p, q, {b.x1, b.y1}), o2 = orient2d(p, q, {b.x2, b.y1});
    const int o3 = orient2d(p, q, {b.x2, b.y2}), o4 = orient2d(p, q, {b.x1, b.y2});
    return !((o1 > 0 && o2 > 0 && o3 > 0 && o4 > 0) || (o1 < 0 && o2 < 0 && o3 < 0 && o4 < 0));
  }

  // BEG's rule: does the feature list of an extended cell meet the input simply? At most one
  // vertex; with one, only segments incident to it; with none, at most one segment.
  bool simple(const std::uint32_t* list, std::size_t count) const {
    std::uint32_t vertex = kNone;
    for (std::size_t i = 0; i < count; ++i) {
      if (!is_vertex(list[i])) continue;
      if (vertex != kNone) return false;
      vertex = rank_id_[list[i]];
    }
    // Without a vertex, several segments are still "one vertex and its segments" if they share an
    // endpoint (lying outside B(C)): they are incident features and do not lower the local
    // feature size; splitting them apart would only refine towards their common vertex forever.
    std::uint32_t common_a = kNone, common_b = kNone;
    for (std::size_t i = 0; i < count; ++i) {
      if (is_vertex(list[i])) continue;
      const FeatureSegment& s = segment(list[i]);
      if (vertex != kNone) {
        if (s.a != vertex && s.b != vertex) return false;
        continue;
      }
      if (common_a == kNone && common_b == kNone) {
        common_a = s.a;
        common_b = s.b;
        continue;
      }
      if (common_a != s.a && common_a != s.b) common_a = kNone;
      if (common_b != s.a && common_b != s.b) common_b = kNone;
      if (common_a == kNone && common_b == kNone) return false;
    }
    return true;
  }

  // Does a feature list hold a segment?
  bool has_segment(const std::uint32_t* list, std::size_t count) const {
    for (std::size_t i = 0; i < count; ++i) {
      if (!is_vertex(list[i])) return true;
    }
    return false;
  }

  bool meets_any(const Node& n, const std::uint32_t* list, std::size_t count) const {
    const Box b = box(n);
    for (std::size_t i = 0; i < count; ++i) {
      if (meets(list[i], b)) return true;
    }
    return false;
  }

  // Does the leaf have to be split by the feature rule? (Levels 0 and 1 always split.)
  bool feature_split(const Node& n, const std::uint32_t* list, std::size_t count) const {
    if (n.level < 2) return true;
    if (simple(list, count)) return false;
    return meets_any(n, list, count);
  }

  // The node covering cell (l, tx, ty): the cell itself if it exists (leaf or not), else the leaf
  // containing it; kNone outside the root. Climbs from `from`, then descends.
  std::uint32_t find(std::uint32_t from, unsigned l, std::int64_t tx, std::int64_t ty) const {
    const std::int64_t side = std::int64_t{1} << l;
    if (tx < 0 || ty < 0 || tx >= side || ty >= side) return kNone;
    std::uint32_t a = from;
    for (;;) {
      const Node& n = nodes[a];
      if (n.level <= l && (tx >> (l - n.level)) == n.ix && (ty >> (l - n.level)) == n.iy) break;
      a = n.parent;
    }
    while (nodes[a].level < l && (nodes[a].child & kLeafBit) == 0) {
      const unsigned d = l - nodes[a].level - 1u;
      a = nodes[a].child + static_cast<std::uint32_t>(((tx >> d) & 1) + 2 * ((ty >> d) & 1));
    }
    return a;
  }

  bool is_leaf(std::uint32_t a) const { return (nodes[a].child & kLeafBit) != 0; }
  // The leaf ordinal of node a (after number_leaves()), kNone for an inner node.
  std::uint32_t leaf_ordinal(std::uint32_t a) const {
    const std::uint32_t c = nodes[a].child;
    return (c & kLeafBit) != 0 ? c & ~kLeafBit : kNone;
  }

  // Edge directions: 0 east, 1 north, 2 west, 3 south.
  static constexpr int kDirX[4] = {1, 0, -1, 0};
  static constexpr int kDirY[4] = {0, 1, 0, -1};

  // Sibling groups among the first `node_count` nodes (after the root, nodes come in fours).
  static std::size_t groups(std::size_t node_count) { return node_count == 0 ? 0 : (node_count - 1) / 4; }
  // Node a's hint in direction d (see neighbour()): a node covering its same-size neighbour cell
  // when a was made. Across a side inside the parent that is the sibling there (no memory read);
  // across the parent's side, the parent's neighbour that way, kept once for the four siblings
  // (outer_hint_: 4 bytes per node, against 16 for a hint per node and direction).
  std::uint32_t hint(std::uint32_t a, unsigned d) const {
    assert(!hints_lent_ && "a look-up after Builder::build_loops() lent the hints away");
    if (a == 0) return kNone;
    const std::uint32_t k = (a - 1) & 3u;  // position among the siblings: SW, SE, NW, NE
    const std::uint32_t bit = (d & 1u) != 0 ? k >> 1 : k & 1u;  // north/south: row; east/west: column
    const std::uint32_t step = (d & 1u) != 0 ? 2u : 1u;
    if (d < 2 && bit == 0) return a + step;  // east of a west child, north of a south child
    if (d >= 2 && bit == 1) return a - step;
    return outer_hint_[(a - 1) >> 2][d];
  }

  // The node covering the same-size cell next to node a in direction d (what find(a, level,
  // ix + dx, iy + dy) returns), without climbing: each node keeps a hint, a node covering that
  // cell when the hint was set. Nodes are never removed, so a hint stays an ancestor of (or equal
  // to) the answer, and descending from it finds the answer in a step or two.
  std::uint32_t neighbour(std::uint32_t a, unsigned d) const {
    std::uint32_t h = hint(a, d);
    if (h == kNone) return kNone;
    const Node& n = nodes[a];
    const unsigned l = n.level;
    const std::int64_t tx = n.ix + kDirX[d], ty = n.iy + kDirY[d];
    while (nodes[h].level < l && (nodes[h].child & kLeafBit) == 0) {
      const unsigned shift = l - nodes[h].level - 1u;
      h = nodes[h].child + static_cast<std::uint32_t>(((tx >> shift) & 1) + 2 * ((ty >> shift) & 1));
    }
    return h;
  }

  // Passes that look up the neighbours of the leaves in Morton order (whose nodes lie scattered in
  // creation order) fetch ahead in two stages: a leaf's node and hints, then, once those are in
  // cache, the nodes its hints name (where neighbour() starts).
  void prefetch_node(std::uint32_t a) const {
    __builtin_prefetch(&nodes[a]);
    if (a != 0) __builtin_prefetch(&outer_hint_[(a - 1) >> 2]);
  }
  void prefetch_hinted(std::uint32_t a, unsigned d) const {
    const std::uint32_t h = hint(a, d);
    if (h != kNone) __builtin_prefetch(&nodes[h]);
  }

  // What find(a, level, ix + ox, iy + oy) returns for |ox|, |oy| ≤ 1, through the hints: an edge
  // neighbour directly, a diagonal one as the neighbour of a same-size edge neighbour (climbing
  // only when that edge neighbour is a coarser leaf).
  std::uint32_t cell_at(std::uint32_t a, int ox, int oy) const {
    if (ox == 0 && oy == 0) return a;
    if (oy == 0) return neighbour(a, ox > 0 ? 0u : 2u);
    if (ox == 0) return neighbour(a, oy > 0 ? 1u : 3u);
    const std::uint32_t side = neighbour(a, ox > 0 ? 0u : 2u);
    if (side == kNone) return kNone;
    return diagonal(a, side, ox, oy);
  }
  // cell_at(a, ox, oy) for a diagonal (|ox| = |oy| = 1), given side = neighbour(a, east or west as
  // ox says): the same-size neighbour of side, or found from side when side is a coarser leaf.
  std::uint32_t diagonal(std::uint32_t a, std::uint32_t side, int ox, int oy) const {
    const Node& n = nodes[a];
    if (nodes[side].level == n.level) return neighbour(side, oy > 0 ? 1u : 3u);
    return find(side, n.level, n.ix + ox, n.iy + oy);
  }

  // Sets the hints of the four new children of p (p's own hints are set).
  void set_child_hints(std::uint32_t p) {
    if (outer_hint_.size() < groups(nodes.size())) outer_hint_.resize(groups(nodes.size()));
    set_child_hints(p, edge_neighbours(p));
  }
  // neighbour(a, d) for the four directions.
  std::array<std::uint32_t, 4> edge_neighbours(std::uint32_t a) const {
    return {neighbour(a, 0), neighbour(a, 1), neighbour(a, 2), neighbour(a, 3)};
  }
  // The same, given p's edge neighbours (edge_neighbours(p)).
  void set_child_hints(std::uint32_t p, const std::array<std::uint32_t, 4>& outer) {
    const std::uint32_t c = nodes[p].child;
    std::array<bool, 4> outer_fine{};
    const unsigned parent_level = nodes[p].level;
    for (unsigned d = 0; d < 4; ++d) {
      outer_fine[d] = outer[d] == kNone || nodes[outer[d]].level == parent_level;
    }
    outer_hint_[(c - 1) >> 2] = outer;
    for (std::uint32_t k = 0; k < 4; ++k) {
      std::uint8_t state = nodes[c + k].state;
      for (unsigned d = 0; d < 4; ++d) {
        if (outer_fine[d]) state = static_cast<std::uint8_t>(state | (kBalanced << d));
      }
      nodes[c + k].state = state;
    }
  }

  // The input vertex of a leaf's Node::vertex rank, and its point (the Morton-ordered copy: ranks
  // of nearby leaves are close, so the reads stay in cache).
  VertexId vertex_id(std::uint32_t rank) const { return rank_id_[rank]; }
  const Point& vertex_point(std::uint32_t rank) const { return rank_point_[rank]; }

  // The input vertex in the half-open leaf [x1, x2) × [y1, y2), if any, as its rank.
  std::uint32_t vertex_in(const Node& n) const {
    return vertex_in(n, features.data() + n.feat_begin, n.feat_count);
  }
  // The same, from the leaf's list of features.
  std::uint32_t vertex_in(const Node& n, const std::uint32_t* list, std::size_t count) const {
    const Box b = box(n);
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint32_t f = list[i];
      if (!is_vertex(f)) continue;
      const Point& q = rank_point_[f];
      if (b.x1 <= q.x && q.x < b.x2 && b.y1 <= q.y && q.y < b.y2) return f;
    }
    return kNone;
  }

  // Corner of leaf n nearest to q, as 0 BL, 1 BR, 2 TR, 3 TL, with (qx, qy) its offsets.
  void nearest_corner(const Node& n, const Point& q, unsigned& qx, unsigned& qy) const {
    qx = q.x >= X(n.ix * 2 + 1, n.level + 1u) ? 1u : 0u;
    qy = q.y >= Y(n.iy * 2 + 1, n.level + 1u) ? 1u : 0u;
  }

  unsigned max_level() const { return max_level_; }
  // Leaves (1 + 3 per split: nodes come in fours) and the deepest level of any node.
  std::size_t leaf_count() const { return (nodes.size() - 1) / 4 * 3 + 1; }

  // Nodes in a tree of max_leaves_ leaves (each split turns one leaf into four nodes).
  std::size_t node_limit() const { return 1 + (max_leaves_ - 1) / 3 * 4; }
  void refuse_beyond_leaf_limit(std::size_t node_count) const {
    if (node_count <= node_limit()) return;
    throw RouteFailure{"the quadtree would need more than " + std::to_string(max_leaves_) +
                       " leaves (features very close for their extent, as in a long thin strip)"};
  }
  // The same refusal before the build, from CleanInput::leaf_lower_bound (size_bound.cpp): a tree
  // that needs far more leaves than the limit is not built up to the limit first.
  void refuse_beyond_leaf_limit_by_bound() const {
    if (!(in_.leaf_lower_bound > static_cast<double>(max_leaves_))) return;
    throw RouteFailure{"the quadtree would need more than " + std::to_string(max_leaves_) +
                       " leaves (features very close for their extent, as in a long thin strip; at least " +
                       std::to_string(static_cast<unsigned long long>(in_.leaf_lower_bound)) +
                       " along the segments)"};
  }
  unsigned deepest() const { return deepest_; }

  NodeArray nodes;
  std::vector<std::uint32_t, UninitializedAllocator<std::uint32_t>> features;  // the leaves' lists

 private:
  // build(): a frontier cell and its list of features in the level's pool.
  struct Item {
    std::uint32_t node, begin, count;
  };
  using ItemList = std::vector<Item, UninitializedAllocator<Item>>;
  // build(): scratch of one half of a level's frontier: a split's four lists, and (second half
  // only) its children's lists, appended to the first half's after both.
  struct HalfScratch {
    std::vector<std::uint32_t> pool;
    std::array<FeatureList, 4> lists;
  };

  // finish() works through lanes: a lane is a work list with its own room in the node, hint and
  // feature arrays. The two region lanes hold the leaves west and east of a vertical grid line
  // (chosen so that about as many leaves lie on each side) and run at the same time; a region lane
  // never reads or writes a node that the other may change, so their runs do not depend on each
  // other's timing (see finish()).
  struct Lane {
    int region = -1;  // 0 west, 1 east of the split line; -1 the whole tree (the arrays grow as needed)
    std::vector<std::uint32_t> work;
    std::vector<std::uint32_t> deferred;  // leaves whose check needs the other side (or more room)
    std::array<FeatureList, 4> lists;  // split(): the children's feature lists
    std::uint32_t node_begin = 0, node_next = 0, node_end = 0;  // region lanes: their block of node ids
    std::size_t feature_next = 0, feature_end = 0;     //   and of feature list entries
    bool full = false;                                 // a split found no room: stop the lane
    std::vector<std::uint32_t> split_before;           // split nodes made before the lane's block
    std::size_t splits_feature = 0, splits_balance = 0, splits_warp = 0;
    unsigned deepest = 0;
  };

  // The split line between the lanes: the left side of column lane_column_ of level lane_level_.
  // In cells of the level of n it lies at line / scale (whole cells at or below lane_level_).
  void split_line_at(const Node& n, std::int64_t& line, std::int64_t& scale) const {
    line = lane_column_;
    scale = 1;
    if (n.level >= lane_level_) {
      line <<= n.level - lane_level_;
    } else {
      scale = std::int64_t{1} << (lane_level_ - n.level);
    }
  }
  // Does the split line cross the columns ix − 1 … ix + 1 of the cell's level (the only cells
  // check() and split() reach from it, besides coarser leaves covering them and ancestors)? Such a
  // cell is left to the whole-tree lane. A cell off the line lies, with all it reaches, on one
  // side; a coarser leaf covering a reached cell either lies on that side too or is crossed by the
  // line (and then no region lane splits it), so the lanes never write what the other reads.
  bool near_split_line(const Node& n) const {
    std::int64_t line = 0, scale = 1;
    split_line_at(n, line, scale);
    return (n.ix - 1) * scale < line && line < (n.ix + 2) * scale;
  }
  // The side of the split line a cell lies on (0 west, 1 east), or -1 if the line crosses it.
  int side_of_split_line(const Node& n) const {
    std::int64_t line = 0, scale = 1;
    split_line_at(n, line, scale);
    if ((n.ix + 1) * scale <= line) return 0;
    if (n.ix * scale >= line) return 1;
    return -1;
  }
  // The column of level lane_level_ a leaf lies in (its first, if it is coarser).
  std::size_t lane_column_of(const Node& n) const {
    return static_cast<std::size_t>(n.level >= lane_level_ ? n.ix >> (n.level - lane_level_)
                                                           : n.ix << (lane_level_ - n.level));
  }

  // ---- private steps: build (tree_build.cpp), per level ----
  struct Level;
  void decide_splits(Level& level) const;  // 1. which frontier cells split
  void place_level(Level& level);          // 2. places of new nodes and lists, by prefix sums
  void fill_level(Level& level);           // 3. leaves' lists, children and their lists
  // The features of the parent's list that meet each child's extended cell, appended to `out`.
  void filter_children(const Node& parent, const std::uint32_t* list, std::size_t count,
                       std::array<FeatureList, 4>& out) const;

  // ---- private steps: finish (tree_balance.cpp), in the order they run ----
  // The lanes' split line: about half of the leaves on each side.
  void choose_split_line(const std::array<std::vector<std::uint32_t>, 2>& leaves_per_column);
  // Would check(a) split anything now? (Read only: the first round, on two threads.)
  bool fails_check(std::uint32_t a) const;
  // Works through a lane's list, last in first out.
  void run(Lane& lane);
  // One leaf: the feature rule (if fresh), balance, the warp rule.
  void check(std::uint32_t a, Lane& lane);
  // Splits b for the check of a, or defers a where the lane may not split b.
  bool split_for(Lane& lane, std::uint32_t a, std::uint32_t b, std::size_t& counter);
  // May the lane split leaf b (off the split line, within its room)?
  bool may_split(Lane& lane, std::uint32_t b);
  // Splits leaf a, filtering its list into the children's, and queues what the split affects.
  void split(std::uint32_t a, Lane& lane);
  // After the region lanes: the east block moves down to follow the west one.
  void join_lanes(std::size_t node_count, std::size_t feature_count, std::size_t node_room, std::size_t feature_room,
                  std::array<Lane, 2>& lanes);
  // Leaves at the deepest level that still break the feature rule or the warp rule.
  std::size_t count_unresolved() const;

  const CleanInput& in_;
  const std::vector<Point>& pts_;
  std::uint32_t nv_;
  unsigned max_level_;
  QuadtreeStats& stats_;
  std::size_t max_leaves_;
  Clock::time_point deadline_;                       // QuadtreeOptions::deadline (check_deadline())
  double x0_ = 0.0, y0_ = 0.0;
  int exponent_ = 0;
  std::array<double, 64> step_{};  // cell size at each level
  unsigned deepest_ = 0;                             // deepest level of any node made so far
  unsigned lane_level_ = 1;                          // finish(): the split line between the lanes
  std::int64_t lane_column_ = 1;
  // Per group of four siblings (nodes 4g + 1 … 4g + 4): their parent's edge neighbours (east,
  // north, west, south) when they were made; see hint().
  std::vector<std::array<std::uint32_t, 4>, UninitializedAllocator<std::array<std::uint32_t, 4>>> outer_hint_;
  bool hints_lent_ = false;                          // lend_hints() was called (checked by assert)
  std::pair<std::size_t, std::size_t> east_group_block_{0, 0};    // join_lanes(): the east lane's old
  std::pair<std::size_t, std::size_t> east_feature_block_{0, 0};  //   blocks (see lend_dead_room())
  std::vector<VertexId> rank_id_;                    // vertex feature (Morton rank) → vertex id
  std::vector<Point> rank_point_;                    // vertex feature → its point
  std::size_t threaded_items_;                       // build(): frontier size for two threads
  std::size_t threaded_nodes_;                       // finish(): tree size for two threads
};

}  // namespace mwst::qtr
