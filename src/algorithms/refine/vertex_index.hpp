// src/algorithms/refine/vertex_index.hpp — which vertices of a growing mesh lie near a disk
// (internal, BRH's local test). The refinement only appends vertices (Mesh::points grows), so the
// index is a logarithmic family of static kd-trees (Bentley and Saxe, "Decomposable searching
// problems I: static-to-dynamic transformation", J. Algorithms 1980): blocks of 2^i vertices, each
// a kd-tree stored implicitly (the median of a range at its middle), merged like a binary counter,
// so an insertion costs O(log² n) amortised and a query visits each block's tree.
//
// It answers one question for the local test on constrained meshes: does any vertex lie strictly
// inside the open circumdisk of corners a, b, c? Floating point only prunes (a kd box farther from
// the computed centre than the computed radius plus a generous slack holds no vertex of the disk);
// of the vertices it visits, those nearer the circle than the disk's own rounding bound are
// decided by the exact incircle sign, the others by their computed distance. Disks too flat for
// the computed centre to be trusted are not asked (the caller floods them as before).
#pragma once

#include <algorithm>
#include <limits>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mwst/geometry/geometry.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst::brh {

class VertexIndex {
 public:
  // What the last query cost: kd nodes and pending vertices looked at (for the tests).
  std::size_t last_visits() const { return visits_; }
  // The vertex the last query found strictly inside (kNone if it found none).
  VertexId last_found() const { return found_; }

  // Indexes points[indexed_, points.size()).
  void sync(const std::vector<Point>& points) {
    while (indexed_ < points.size()) {
      pending_.push_back(static_cast<VertexId>(indexed_++));
      if (pending_.size() == kPending) flush(points);
    }
  }

  enum class Disk : std::uint8_t { kEmpty, kHoldsVertex, kUnknown };

  // Is a vertex (other than a, b, c) strictly inside the open circumdisk of a, b, c? kUnknown when
  // the disk is too flat for its computed centre, or when the search passes kMaxVisits (then the
  // caller must look at the whole disk).
  // `inside(x)` is the exact test of vertex x (sign > 0: strictly inside). Only the vertices with
  // ids from `from` on are asked: a caller that knows the disk held none of the older ones (the
  // refinement only appends vertices) skips the kd subtrees that hold only older ones. (Fewer
  // visits: a disk whose full search passes kMaxVisits may be shown empty of the newer ones.)
  template <class ExactInside>
  Disk strictly_inside(const std::vector<Point>& points, const std::array<VertexId, 3>& cv, ExactInside inside,
                       VertexId from = 0) {
    visits_ = 0;
    found_ = kNone;
    if (!set_disk(points, cv)) return Disk::kUnknown;
    const double band2 = band2_;
    auto check = [&](VertexId x, const Point& p) {
      if (x < from || x == cv[0] || x == cv[1] || x == cv[2]) return false;
      const double dx = p.x - center_.x, dy = p.y - center_.y;
      if (!(dx * dx + dy * dy < band2) || !inside(x)) return false;
      found_ = x;
      return true;
    };
    for (const VertexId x : pending_) {
      if (x < from) continue;
      ++visits_;
      if (check(x, points[x])) return Disk::kHoldsVertex;
    }
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const Cell whole{-kInf, kInf, -kInf, kInf};
    for (const Block& blk : blocks_) {
      if (!blk.nodes.empty() && search(blk, 0, blk.nodes.size(), 0, whole, from, check)) return Disk::kHoldsVertex;
    }
    return visits_ > kMaxVisits ? Disk::kUnknown : Disk::kEmpty;
  }

  // Would strictly_inside(points, cv, inside) over every vertex (from 0) answer kHoldsVertex or
  // kUnknown, never kEmpty? True if more than kMaxVisits vertices lie within its pruning radius:
  // each such vertex lies in its kd node's cell, so that node and its ancestors pass the search's
  // distance test, and the search visits them all unless it stops earlier (on a vertex inside, or
  // past kMaxVisits). The distances are the ones the search computes (rounding is monotone, so a
  // cell's computed distance is at most that of any vertex in it), and a subtree whose bounding
  // box lies within that radius at its farthest corner is counted whole. Costs far fewer node
  // reads than the search when thousands of vertices crowd the disk's rim: on a fan of narrow
  // wedges, the slivers' disks pass within 10^-4 r of ~7,500 rim vertices each.
  bool crowded(const std::vector<Point>& points, const std::array<VertexId, 3>& cv) {
    crowd_reads_ = 0;
    if (!set_disk(points, cv)) return false;
    // count: vertices found within reach; possible: count plus the vertices not yet ruled out.
    // The count stops once either settles the answer, or after kMaxCrowdReads box reads (then
    // the answer is no: the search runs, as without this shortcut).
    std::size_t count = 0, possible = indexed_;
    for (const VertexId x : pending_) {
      const double dx = points[x].x - center_.x, dy = points[x].y - center_.y;
      if (dx * dx + dy * dy < reach2_) {
        ++count;
      } else {
        --possible;
      }
    }
    // The largest blocks first: a small disk rules out most of a block in a few reads (one half per
    // level of its kd-tree), so the blocks left may add up to kMaxVisits or less before the small
    // ones are read at all.
    for (auto blk = blocks_.rbegin(); blk != blocks_.rend(); ++blk) {
      if (!blk->nodes.empty() && !count_within(*blk, 0, blk->nodes.size(), count, possible)) break;
    }
    return count > kMaxVisits;
  }
  // Box reads of the last crowded() (for the tests).
  std::size_t last_crowd_reads() const { return crowd_reads_; }

 private:
  // Computes the centre of the circumdisk of cv and the radii the search prunes with (reach_) and
  // asks the exact sign within (band2_); false if the disk is too flat for its computed centre.
  bool set_disk(const std::vector<Point>& points, const std::array<VertexId, 3>& cv) {
    const Point& a = points[cv[0]];
    const Point& b = points[cv[1]];
    const Point& c = points[cv[2]];
    const double bx = b.x - a.x, by = b.y - a.y, cx = c.x - a.x, cy = c.y - a.y;
    const double d = 2.0 * (bx * cy - by * cx);
    const double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
    // |d| / (|ab| |ac|) is twice the sine of the angle at a: the centre's rounding error grows as
    // its inverse. Below 1e-9 (angles under ~1e-7°) the disk is not asked.
    const double longest = std::max({b2, c2, (c.x - b.x) * (c.x - b.x) + (c.y - b.y) * (c.y - b.y)});
    if (!(std::fabs(d) > 1e-9 * longest)) return false;
    const double ux = (cy * b2 - by * c2) / d, uy = (bx * c2 - cx * b2) / d;
    center_ = {a.x + ux, a.y + uy};
    // At that flatness the centre's offset from a is within ~1e-6 r of the true one (the numerators'
    // rounding is eps·L³ against r·|d| ≥ L/2 · 1e-9 L²); 1e-4 r is a margin. The absolute term
    // covers the rounding of a + u and of the differences to it, relative to the coordinates'
    // magnitude (tiny disks far from the origin).
    const double r = std::sqrt(ux * ux + uy * uy);
    const double magnitude = std::fabs(a.x) + std::fabs(a.y) + std::fabs(ux) + std::fabs(uy);
    reach_ = r * (1.0 + 1e-4) + 1e-13 * magnitude + 1e-300;
    reach2_ = reach_ * reach_;
    // The band a vertex must lie in to be asked the exact incircle sign is narrower, from this
    // disk's own error bound: the numerators' rounding (and that of the differences to a, a
    // perturbation of the corners by eps L) moves the centre by ~eps L³ / |d|, the rounding of d
    // (absolute ~eps L²) by ~eps L² |u| / |d|; 64 times both is the margin (at the flatness
    // limit still below the pruning's 1e-4 r). The radius is off by at most the centre's error, the
    // computed distances by a relative 1e-12 and the absolute term above. Most vertices in the
    // pruning's band lie outside this one and are rejected without an incircle determinant (on a
    // fan of narrow wedges, slivers' disks pass near thousands of rim vertices). The pruning, and
    // so the count of visits, is unchanged.
    const double error = 64.0 * std::numeric_limits<double>::epsilon() * longest * (std::sqrt(longest) + r) / std::fabs(d);
    const double band = std::min(reach_, (r + 2.0 * error) * (1.0 + 1e-12) + 1e-13 * magnitude + 1e-300);
    band2_ = band * band;
    return true;
  }

  static constexpr std::size_t kPending = 32;
  // A query gives up (kUnknown) after this many visits: many vertices near the circle (a fan's
  // rim, points on a circle) are visited one by one, and the flood the caller falls back to is
  // capped.
  static constexpr std::size_t kMaxVisits = 4096;
  // crowded() gives up (answers no) after this many box reads: on the fan's crowded disks it
  // needs ~130, and a disk it cannot settle so is searched as before.
  static constexpr std::size_t kMaxCrowdReads = 1024;
  // A kd-tree node: its vertex, with the vertex's coordinates (a search reads them in the node
  // it visits, not at random in the mesh's point array), and the largest id in its subtree (a merge
  // mixes old and new vertices, so a search for the newer ones skips the subtrees holding only
  // older ones).
  struct Node {
    Point p;
    VertexId id;
    VertexId newest;
  };
  // The bounding box of a kd subtree's vertices, in floats rounded outwards (it holds them all).
  struct Box {
    float x0, x1, y0, y1;
  };
  struct Block {
    std::vector<Node> nodes;  // a kd-tree: the median of [lo, hi) at (lo + hi) / 2, x then y
    std::vector<Box> boxes;   // per node, its subtree's bounding box (crowded())
  };

  // Merges the pending vertices with the blocks of the sizes below them (a binary counter).
  void flush(const std::vector<Point>& points) {
    std::vector<VertexId> ids = std::move(pending_);
    pending_.clear();
    std::size_t i = 0;
    for (; i < blocks_.size() && !blocks_[i].nodes.empty(); ++i) {
      for (const Node& n : blocks_[i].nodes) ids.push_back(n.id);
      blocks_[i].nodes.clear();
      blocks_[i].nodes.shrink_to_fit();
      blocks_[i].boxes.clear();
      blocks_[i].boxes.shrink_to_fit();
    }
    if (i == blocks_.size()) blocks_.emplace_back();
    build(points, ids, 0, ids.size(), 0);
    std::vector<Node>& nodes = blocks_[i].nodes;
    nodes.resize(ids.size());
    for (std::size_t j = 0; j < ids.size(); ++j) nodes[j] = {points[ids[j]], ids[j], 0};
    newest_in(nodes, 0, nodes.size());
    blocks_[i].boxes.resize(nodes.size());
    box_of(blocks_[i], 0, nodes.size());
  }

  static float below(double x) {
    float f = static_cast<float>(x);
    if (static_cast<double>(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    return f;
  }
  static float above(double x) {
    float f = static_cast<float>(x);
    if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
    return f;
  }
  // Fills boxes[mid] for the subtree of nodes[lo, hi) and its descendants; returns it.
  static Box box_of(Block& blk, std::size_t lo, std::size_t hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    const Point& p = blk.nodes[mid].p;
    Box b{below(p.x), above(p.x), below(p.y), above(p.y)};
    for (const auto& [l, h] : {std::pair{lo, mid}, std::pair{mid + 1, hi}}) {
      if (h <= l) continue;
      const Box c = box_of(blk, l, h);
      b = {std::min(b.x0, c.x0), std::max(b.x1, c.x1), std::min(b.y0, c.y0), std::max(b.y1, c.y1)};
    }
    blk.boxes[mid] = b;
    return b;
  }

  // Adds to count the vertices of nodes[lo, hi) whose computed distance to center_ is below
  // reach_ (the search's test) and takes those that are not from possible; false once the answer
  // is settled (count > kMaxVisits or possible <= kMaxVisits) or the reads are spent.
  bool count_within(const Block& blk, std::size_t lo, std::size_t hi, std::size_t& count, std::size_t& possible) {
    while (hi > lo) {
      if (count > kMaxVisits || possible <= kMaxVisits || crowd_reads_ >= kMaxCrowdReads) return false;
      const std::size_t mid = lo + (hi - lo) / 2;
      const Box& b = blk.boxes[mid];
      ++crowd_reads_;
      const double x0 = double{b.x0} - center_.x, x1 = double{b.x1} - center_.x;
      const double y0 = double{b.y0} - center_.y, y1 = double{b.y1} - center_.y;
      const double nx = std::max({x0, 0.0, -x1}), ny = std::max({y0, 0.0, -y1});
      if (!(nx * nx + ny * ny < reach2_)) {  // no vertex of the box within reach
        possible -= hi - lo;
        return true;
      }
      const double fx = std::max(-x0, x1), fy = std::max(-y0, y1);
      if (fx * fx + fy * fy < reach2_) {  // every vertex of the box within reach
        count += hi - lo;
        return true;
      }
      const Point& p = blk.nodes[mid].p;
      const double dx = p.x - center_.x, dy = p.y - center_.y;
      if (dx * dx + dy * dy < reach2_) {
        ++count;
      } else {
        --possible;
      }
      if (!count_within(blk, lo, mid, count, possible)) return false;
      lo = mid + 1;
    }
    return true;
  }

  static void build(const std::vector<Point>& points, std::vector<VertexId>& ids, std::size_t lo, std::size_t hi,
                    unsigned depth) {
    if (hi - lo <= 1) return;
    const std::size_t mid = lo + (hi - lo) / 2;
    const bool by_x = depth % 2 == 0;
    std::nth_element(ids.begin() + static_cast<std::ptrdiff_t>(lo), ids.begin() + static_cast<std::ptrdiff_t>(mid),
                     ids.begin() + static_cast<std::ptrdiff_t>(hi), [&](VertexId p, VertexId q) {
                       return by_x ? points[p].x < points[q].x : points[p].y < points[q].y;
                     });
    build(points, ids, lo, mid, depth + 1);
    build(points, ids, mid + 1, hi, depth + 1);
  }

  // Fills newest[mid] for the subtree of ids[lo, hi) and its descendants; returns it.
  static VertexId newest_in(std::vector<Node>& nodes, std::size_t lo, std::size_t hi) {
    if (hi <= lo) return 0;
    const std::size_t mid = lo + (hi - lo) / 2;
    nodes[mid].newest = std::max({nodes[mid].id, newest_in(nodes, lo, mid), newest_in(nodes, mid + 1, hi)});
    return nodes[mid].newest;
  }

  // The region of a kd-tree node: its points lie in [x0, x1] × [y0, y1].
  struct Cell {
    double x0, x1, y0, y1;
  };

  // Every vertex of ids[lo, hi) within reach_ of the centre goes to check; true at the first one
  // it confirms. The two halves of a range lie on either side of its median's coordinate, and a
  // half whose cell lies farther than reach_ from the centre is skipped: its vertices would all
  // fail check (the order of the checks is that of the whole search, so the vertex found is the
  // same). Without it a large empty disk visited every vertex of its bounding box: on a fan, whose
  // wide thin triangles have huge circumdisks, most of the vertices in every query. A subtree
  // holding no id from `from` on is skipped as well.
  template <class Check>
  bool search(const Block& blk, std::size_t lo, std::size_t hi, unsigned depth, Cell cell, VertexId from,
              Check& check) {
    while (hi > lo && visits_ <= kMaxVisits) {
      const std::size_t mid = lo + (hi - lo) / 2;
      const Node& node = blk.nodes[mid];
      if (node.newest < from) return false;  // only older vertices below
      const double dx = std::max({cell.x0 - center_.x, 0.0, center_.x - cell.x1});
      const double dy = std::max({cell.y0 - center_.y, 0.0, center_.y - cell.y1});
      if (!(dx * dx + dy * dy < reach2_)) return false;
      ++visits_;
      if (check(node.id, node.p)) return true;
      const bool by_x = depth % 2 == 0;
      const double split = by_x ? node.p.x : node.p.y;
      ++depth;
      Cell low = cell;
      (by_x ? low.x1 : low.y1) = split;
      if (search(blk, lo, mid, depth, low, from, check)) return true;
      (by_x ? cell.x0 : cell.y0) = split;
      lo = mid + 1;
    }
    return false;
  }

  std::size_t indexed_ = 0;
  std::vector<VertexId> pending_;
  std::vector<Block> blocks_;
  Point center_{};
  double reach_ = 0.0, reach2_ = 0.0, band2_ = 0.0;
  std::size_t visits_ = 0;
  std::size_t crowd_reads_ = 0;
  VertexId found_ = kNone;
};

}  // namespace mwst::brh
