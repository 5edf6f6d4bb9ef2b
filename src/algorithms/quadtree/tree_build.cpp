// algorithms/quadtree/tree_build.cpp — the quadtree's first build: the root square, the vertices'
// Morton ranks, and the level-by-level split by BEG's feature rule (a leaf is split until its
// extended cell meets the input simply); then what the Builder reads from the finished tree.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "algorithms/quadtree/tree.hpp"

namespace mwst::qtr {

// ==== the root and the ranks begins here =========================================================

Tree::Tree(const CleanInput& in, const QuadtreeOptions& options, QuadtreeStats& stats)
    : in_(in), pts_(in.vertices_only.points), nv_(static_cast<std::uint32_t>(pts_.size())),
      max_level_(std::min(options.max_depth, 52u)), stats_(stats),
      max_leaves_(leaf_limit(options, in.vertices.size() + in.segments.size())), deadline_(options.deadline),
      threaded_items_(threads_from(options, 8192)), threaded_nodes_(threads_from(options, 65536)) {
  // Root: a power-of-two square at least twice the bounding box, its corner aligned to 1/16 of
  // its side, so every vertex lies at least 3/16 of the root inside it: a warp target or a corner
  // moved onto a segment is never on the root's border (which must stay the convex hull).
  double xmin = std::numeric_limits<double>::infinity(), ymin = xmin;
  double xmax = -xmin, ymax = -xmin;
  for (VertexId v : in.vertices) {
    xmin = std::min(xmin, pts_[v].x);
    xmax = std::max(xmax, pts_[v].x);
    ymin = std::min(ymin, pts_[v].y);
    ymax = std::max(ymax, pts_[v].y);
  }
  const double span = std::max(xmax - xmin, ymax - ymin);
  int e = 0;
  std::frexp(span, &e);  // span < 2^e
  e += 1;
  for (;;) {
    const double side = std::ldexp(1.0, e), grid = std::ldexp(1.0, e - 4);
    x0_ = std::floor((0.5 * (xmin + xmax) - 0.5 * side) / grid) * grid;
    y0_ = std::floor((0.5 * (ymin + ymax) - 0.5 * side) / grid) * grid;
    const double margin = std::ldexp(1.0, e - 3);
    if (xmin - x0_ > margin && x0_ + side - xmax > margin && ymin - y0_ > margin &&
        y0_ + side - ymax > margin) {
      break;
    }
    ++e;
  }
  exponent_ = e;
  for (unsigned l = 0; l < step_.size(); ++l) step_[l] = std::ldexp(1.0, e - static_cast<int>(l));
  // Vertex features are ranks in Morton order of the root's 2^16 × 2^16 grid, with their points
  // copied in that order: the feature lists are scanned once per level, and input order would
  // make every point a cache miss.
  const double scale = 65536.0 / step_[0];
  auto cell = [&](double v, double origin) {
    return static_cast<std::uint64_t>(std::clamp(std::floor((v - origin) * scale), 0.0, 65535.0));
  };
  auto spread = [](std::uint64_t v) {
    v = (v | (v << 8)) & 0x00FF00FFu;
    v = (v | (v << 4)) & 0x0F0F0F0Fu;
    v = (v | (v << 2)) & 0x33333333u;
    return (v | (v << 1)) & 0x55555555u;
  };
  // Sorted by (Morton key, vertex): the keys have 32 bits and in.vertices is in increasing
  // order, so a stable two-pass radix sort on 16-bit digits gives exactly that order.
  using Keyed = std::pair<std::uint64_t, VertexId>;
  std::vector<Keyed> order;
  order.reserve(in.vertices.size());
  for (VertexId v : in.vertices) {
    order.emplace_back((spread(cell(pts_[v].y, y0_)) << 1) | spread(cell(pts_[v].x, x0_)), v);
  }
  {
    std::vector<Keyed> scratch(order.size());
    std::vector<std::uint32_t> bucket(65537);
    for (const unsigned shift : {0u, 16u}) {
      std::fill(bucket.begin(), bucket.end(), 0u);
      for (const Keyed& o : order) ++bucket[((o.first >> shift) & 0xFFFFu) + 1];
      for (std::size_t b = 1; b < bucket.size(); ++b) bucket[b] += bucket[b - 1];
      for (const Keyed& o : order) scratch[bucket[(o.first >> shift) & 0xFFFFu]++] = o;
      order.swap(scratch);
    }
  }
  rank_id_.resize(order.size());
  rank_point_.resize(order.size());
  for (std::size_t r = 0; r < order.size(); ++r) {
    rank_id_[r] = order[r].second;
    rank_point_[r] = pts_[order[r].second];
  }
}

// ==== the root and the ranks ends here ===========================================================

// ==== the first build begins here ================================================================

// Appends to `out` the features of the parent's list that meet each child's extended cell.
// (Written through raw pointers into room made first: this runs for every list entry of every
// level, and push_back's growth check was a call per entry.)
void Tree::filter_children(const Node& parent, const std::uint32_t* list, std::size_t count,
                           std::array<FeatureList, 4>& out) const {
  // Vertices: each child grown by half its size (one grid step of level parent + 2), columns
  // 4ix − 1 … 4ix + 3 and 4ix + 1 … 4ix + 5, the same for rows.
  const unsigned h = parent.level + 2u;
  const std::int64_t qx = parent.ix * 4, qy = parent.iy * 4;
  const double xa1 = X(qx - 1, h), xa2 = X(qx + 3, h), xb1 = X(qx + 1, h), xb2 = X(qx + 5, h);
  const double ya1 = Y(qy - 1, h), ya2 = Y(qy + 3, h), yb1 = Y(qy + 1, h), yb2 = Y(qy + 5, h);
  // Segments: each child grown by its size, columns cx − 1 … cx + 2 and cx … cx + 3.
  const unsigned l = parent.level + 1u;
  const std::int64_t cx = parent.ix * 2, cy = parent.iy * 2;
  const double sa1 = X(cx - 1, l), sa2 = X(cx + 2, l), sb1 = X(cx, l), sb2 = X(cx + 3, l);
  const double ta1 = Y(cy - 1, l), ta2 = Y(cy + 2, l), tb1 = Y(cy, l), tb2 = Y(cy + 3, l);
  const Box boxes[4] = {{sa1, ta1, sa2, ta2}, {sb1, ta1, sb2, ta2}, {sa1, tb1, sa2, tb2}, {sb1, tb1, sb2, tb2}};
  std::size_t used[4];
  std::uint32_t* w[4];
  for (unsigned k = 0; k < 4; ++k) {
    used[k] = out[k].size();
    out[k].resize(used[k] + count);
    w[k] = out[k].data();
  }
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t f = list[i];
    if (is_vertex(f)) {
      const Point& q = rank_point_[f];
      const bool col0 = xa1 <= q.x && q.x <= xa2, col1 = xb1 <= q.x && q.x <= xb2;
      const bool row0 = ya1 <= q.y && q.y <= ya2, row1 = yb1 <= q.y && q.y <= yb2;
      if (col0 && row0) w[0][used[0]++] = f;
      if (col1 && row0) w[1][used[1]++] = f;
      if (col0 && row1) w[2][used[2]++] = f;
      if (col1 && row1) w[3][used[3]++] = f;
    } else {
      for (unsigned k = 0; k < 4; ++k) {
        if (meets(f, boxes[k])) w[k][used[k]++] = f;
      }
    }
  }
  for (unsigned k = 0; k < 4; ++k) out[k].resize(used[k]);
}

// build(): one level of the breadth-first build: its frontier (cells with their lists in `pool`),
// the next level's, and per frontier item whether it splits and its place.
struct Tree::Level {
  ItemList frontier, next;
  std::vector<std::uint32_t> pool, next_pool;
  std::vector<std::uint32_t> place;  // per frontier item: first child, or its list's place in features
  std::vector<std::uint8_t> splits;
  std::array<HalfScratch, 2> half;
  std::uint32_t node_base = 0;                 // the first new node
  std::size_t second_half_first_child = 0;     // in `next`: the second half's first item
};

// First build: breadth first, splitting by the feature rule. Each level runs in three steps:
// decide which frontier cells split, give every new node and leaf list its place by prefix
// sums in frontier order, then fill them in; the first and last steps run in two halves of the
// frontier on two threads (they only read the levels above and write their own places), and the
// result is the same arrays, index for index, as one pass in frontier order.
void Tree::build() {
  refuse_beyond_leaf_limit_by_bound();
  nodes.clear();
  // Room for what a uniform point set needs, so that the big arrays are not copied while they
  // grow: finish() sizes them to three times what this build makes (about 7 nodes and 7 list
  // entries per point) for its lanes' blocks. Unused room is never touched. The nodes get a
  // little more, 1200 bytes per feature: their storage becomes the mesh's triangle array, which
  // the cells want with room for 4 triangles (96 bytes) per leaf, 11.6 leaves per point.
  const std::size_t feature_count = rank_id_.size() + in_.segments.size();
  reserve_room(nodes, 30 * feature_count + 256);
  reserve_room(outer_hint_, 6 * feature_count + 64);
  reserve_room(features, 30 * feature_count + 64);
  nodes.push_back(Node{});
  outer_hint_.clear();
  Level level;
  // A level's lists hold each vertex up to four times (its cell and the neighbours whose grown
  // cells reach it) and each segment once per cell along it.
  reserve_room(level.pool, 4 * feature_count + 64);
  reserve_room(level.next_pool, 4 * feature_count + 64);
  for (std::uint32_t r = 0; r < rank_id_.size(); ++r) level.pool.push_back(r);
  for (std::uint32_t s = 0; s < in_.segments.size(); ++s) level.pool.push_back(nv_ + s);
  level.frontier = ItemList{{0, 0, static_cast<std::uint32_t>(level.pool.size())}};
  reserve_room(level.frontier, 4 * feature_count + 64);
  reserve_room(level.next, 4 * feature_count + 64);
  // (Room for the largest level up front: grown by doubling, every new block is fresh pages and
  // the old one is copied and freed; unused room is never touched.)
  reserve_room(level.half[1].pool, 8 * feature_count + 64);
  while (!level.frontier.empty()) {
    check_deadline(deadline_);
    decide_splits(level);
    place_level(level);
    fill_level(level);
    if (!level.next.empty()) deepest_ = std::max(deepest_, static_cast<unsigned>(nodes[level.next.front().node].level));
    level.frontier.swap(level.next);
    level.pool.swap(level.next_pool);
  }
}

// 1. Which frontier cells split (by the feature rule, above the deepest level).
void Tree::decide_splits(Level& level) const {
  const std::size_t count = level.frontier.size();
  level.splits.resize(count);
  level.place.resize(count);
  support::parallel_ranges(workers_for(count, threaded_items_), count,
      [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      check_deadline_at(i - begin, deadline_);
      const Item& item = level.frontier[i];
      const Node& n = nodes[item.node];
      level.splits[i] =
          n.level < max_level_ && feature_split(n, level.pool.data() + item.begin, item.count) ? 1 : 0;
    }
  });
}

// 2. Places, in frontier order: four new nodes per split, a list in `features` per leaf; the arrays
// are sized for them. The next frontier is the new nodes, in order (four per split, placed in
// frontier order).
void Tree::place_level(Level& level) {
  const std::size_t count = level.frontier.size();
  auto next_node = static_cast<std::uint32_t>(nodes.size());
  std::size_t next_feature = features.size();
  for (std::size_t i = 0; i < count; ++i) {
    if (level.splits[i]) {
      if (nodes[level.frontier[i].node].level >= 2) ++stats_.splits_feature;
      level.place[i] = next_node;
      next_node += 4;
    } else {
      level.place[i] = static_cast<std::uint32_t>(next_feature);
      next_feature += level.frontier[i].count;
    }
  }
  if (next_feature > std::numeric_limits<std::uint32_t>::max()) throw RouteFailure{"too many feature list entries"};
  refuse_beyond_leaf_limit(next_node);
  level.node_base = static_cast<std::uint32_t>(nodes.size());
  level.next.resize(next_node - level.node_base);
  level.next_pool.clear();
  level.half[1].pool.clear();
  level.second_half_first_child = level.next.size();
  nodes.resize(next_node);
  outer_hint_.resize(groups(next_node));
  features.resize(next_feature);
}

// 3. Leaves and children: a leaf's list is copied to its place; a split cell's children get their
// nodes, hints and lists. Each child's item goes to its node's place in `next`, and its list to
// next_pool, where the first half writes directly and the second half's lists follow after both.
void Tree::fill_level(Level& level) {
  constexpr std::size_t kLookAhead = 8;
  const ItemList& frontier = level.frontier;
  const std::uint32_t node_base = level.node_base;
  support::parallel_ranges(workers_for(frontier.size(), threaded_items_), frontier.size(),
      [&](std::size_t half, std::size_t begin, std::size_t end) {
    HalfScratch& out = level.half[half];
    std::vector<std::uint32_t>& lists_out = begin == 0 ? level.next_pool : out.pool;
    bool first_split = true;
    for (std::size_t i = begin; i < end; ++i) {
      check_deadline_at(i - begin, deadline_);
      // (A split reads the nodes its hints name, scattered over the level above: they are
      // fetched a few items ahead.)
      if (i + kLookAhead < end && level.splits[i + kLookAhead]) {
        const std::uint32_t ahead = frontier[i + kLookAhead].node;
        for (unsigned d = 0; d < 4; ++d) {
          const std::uint32_t h = hint(ahead, d);
          if (h != kNone) __builtin_prefetch(&nodes[h]);
        }
      }
      const Item& item = frontier[i];
      const std::uint32_t* list = level.pool.data() + item.begin;
      if (!level.splits[i]) {
        Node& leaf = nodes[item.node];
        leaf.feat_begin = level.place[i];
        leaf.feat_count = item.count;
        std::copy(list, list + item.count, features.begin() + level.place[i]);
        leaf.vertex = vertex_in(leaf);
        if (has_segment(list, item.count)) leaf.state = static_cast<std::uint8_t>(leaf.state | kHasSegment);
        continue;
      }
      const Node n = nodes[item.node];
      for (auto& l : out.lists) l.clear();
      filter_children(n, list, item.count, out.lists);
      const std::uint32_t first = level.place[i];
      if (begin != 0 && first_split) level.second_half_first_child = first - node_base;
      first_split = false;
      nodes[item.node].child = first;
      for (unsigned k = 0; k < 4; ++k) {
        Node& c = nodes[first + k];
        c = Node{};
        c.ix = 2 * n.ix + (k & 1);
        c.iy = 2 * n.iy + (k >> 1);
        c.parent = item.node;
        c.level = static_cast<std::uint8_t>(n.level + 1);
        if (lists_out.size() + out.lists[k].size() > std::numeric_limits<std::uint32_t>::max()) {
          throw RouteFailure{"too many feature list entries"};
        }
        level.next[first + k - node_base] = {first + k, static_cast<std::uint32_t>(lists_out.size()),
                                             static_cast<std::uint32_t>(out.lists[k].size())};
        lists_out.insert(lists_out.end(), out.lists[k].begin(), out.lists[k].end());
      }
      set_child_hints(item.node);
    }
  });
  const std::vector<std::uint32_t>& second = level.half[1].pool;
  if (level.next_pool.size() + second.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw RouteFailure{"too many feature list entries"};
  }
  const auto offset = static_cast<std::uint32_t>(level.next_pool.size());
  for (std::size_t j = level.second_half_first_child; j < level.next.size(); ++j) level.next[j].begin += offset;
  level.next_pool.insert(level.next_pool.end(), second.begin(), second.end());
}

// QuadtreeOptions::max_leaves, resolved: the automatic limit grows with the input (1024 leaves
// per feature; the 13 data sets need at most 26, uniform points 11.5) between 2^20 and 2^26 (about
// 240 bytes per leaf at the peak: 16 GB). BEG's tree has O(Σ 1/lfs²) leaves, unbounded in the
// number of features: two segments 30 apart running 3e15 long would need 1e14.
std::size_t Tree::leaf_limit(const QuadtreeOptions& options, std::size_t features) {
  if (options.max_leaves > 0) return options.max_leaves;
  constexpr std::size_t kPerFeature = 1024, kLeast = std::size_t{1} << 20, kMost = std::size_t{1} << 26;
  return std::clamp(kPerFeature * features, kLeast, kMost);
}

// ==== the first build ends here ==================================================================

// ==== handing over to the Builder begins here ====================================================

// Leaves in Morton (Z) order.
std::vector<std::uint32_t> Tree::leaves_in_order() const {
  // The nodes at level 3 (and the leaves above it) in depth-first order are the roots of
  // subtrees whose leaves follow each other in the answer: two threads walk the first and the
  // second half of them, and the two lists are joined in order.
  std::vector<std::uint32_t> tops, stack{0};
  while (!stack.empty()) {
    const std::uint32_t a = stack.back();
    stack.pop_back();
    if (is_leaf(a) || nodes[a].level >= 3) {
      tops.push_back(a);
      continue;
    }
    for (int k = 3; k >= 0; --k) stack.push_back(nodes[a].child + static_cast<std::uint32_t>(k));
  }
  const std::size_t leaf_room = nodes.size() - nodes.size() / 4 + 1;  // 4 children per inner node: ¾ leaves
  std::array<std::vector<std::uint32_t>, 2> part;
  const std::size_t threshold = nodes.size() >= threaded_nodes_ ? 0 : std::numeric_limits<std::size_t>::max();
  support::parallel_ranges(workers_for(tops.size(), threshold), tops.size(),
      [&](std::size_t half, std::size_t begin, std::size_t end) {
    std::vector<std::uint32_t>& out = part[half];
    reserve_room(out, begin == 0 ? leaf_room : leaf_room / 2 + 64);
    std::vector<std::uint32_t> walk;
    for (std::size_t i = begin; i < end; ++i) {
      walk.push_back(tops[i]);
      while (!walk.empty()) {
        const std::uint32_t a = walk.back();
        walk.pop_back();
        if (is_leaf(a)) {
          out.push_back(a);
          continue;
        }
        for (int k = 3; k >= 0; --k) walk.push_back(nodes[a].child + static_cast<std::uint32_t>(k));
      }
    }
  });
  std::vector<std::uint32_t> out = std::move(part[0]);
  out.insert(out.end(), part[1].begin(), part[1].end());
  return out;
}

// Writes each leaf's ordinal in Morton order into its child field (kLeafBit | k).
void Tree::number_leaves(const std::vector<std::uint32_t>& leaves, std::size_t threaded) {
  if (nodes.size() >= kLeafBit || leaves.size() >= kLeafBit - 1) throw RouteFailure{"too many nodes"};
  support::parallel_ranges(workers_for(leaves.size(), threaded), leaves.size(),
      [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) nodes[leaves[k]].child = kLeafBit | static_cast<std::uint32_t>(k);
  });
}

// After finish(): the east lane's old block (written while the lane ran, moved down by
// join_lanes()) is dead where it lies past the arrays' final ends; the tree never grows after
// finish(), so those pages of the arrays' capacity are lent (the lists' and the hints'; the
// nodes' storage becomes the mesh's triangle array, see NodeArray).
void Tree::lend_dead_room(SpareRoom& room) {
  const auto lend_tail = [&](auto& array, std::pair<std::size_t, std::size_t> block) {
    const std::size_t begin = std::max(block.first, array.size());
    if (begin < block.second && block.second <= array.capacity()) {
      room.lend(array.data() + begin, (block.second - begin) * sizeof(array[0]));
    }
  };
  lend_tail(features, east_feature_block_);
  // (The hints' dead block usually follows their live part: lent with it, as one region.)
  if (east_group_block_.first > outer_hint_.size()) lend_tail(outer_hint_, east_group_block_);
}

// After the last neighbour() / diagonal() look-up (Builder::build_loops()): the hints are dead
// (4 bytes per node), and no look-up may follow.
void Tree::lend_hints(SpareRoom& room) {
  std::size_t end = outer_hint_.size();
  const auto [dead_begin, dead_end] = east_group_block_;
  if (dead_begin <= end && dead_end <= outer_hint_.capacity()) end = std::max(end, dead_end);
  room.lend(outer_hint_.data(), end * sizeof(outer_hint_[0]));
  hints_lent_ = true;
}

// ==== handing over to the Builder ends here ======================================================

}  // namespace mwst::qtr
