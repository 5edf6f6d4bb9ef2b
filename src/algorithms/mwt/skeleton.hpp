// src/algorithms/mwt/skeleton.hpp — the LMT-skeleton (Dickerson and Montague 1996) over candidate
// edges, and the polygon dynamic program over the faces of its fixed edges (docs/algorithms/mwt.md,
// steps 2 and 3). Internal (not installed).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "algorithms/mwt/box_tree.hpp"
#include "algorithms/mwt/domain.hpp"
#include "mesh/keys.hpp"

namespace mwst::mwt {

struct CoreResult {
  bool solved = false;
  std::string reason;
  std::vector<Tri> triangles;  // counter-clockwise, in the region
  std::size_t skeleton_edges = 0, result_edges = 0, regions = 0, largest_region = 0;
};

class Skeleton {
 public:
  // Builds the candidate triangles, removes the edges that have triangles on both sides but no
  // locally minimal pair of them (a first skeleton pass that needs no crossing lists, so that
  // these lists are built for the survivors only), then the crossing lists. `overflow()` is set,
  // and nothing else may be called, when a size limit is exceeded.
  Skeleton(const std::vector<Point>& P, std::vector<std::array<Index, 2>> edges,
           const std::vector<std::array<Index, 2>>& forced, std::size_t max_triangles, std::size_t max_crossings);

  const std::string& overflow() const { return overflow_; }
  std::size_t size() const { return E_.size(); }
  std::size_t initial_size() const { return initial_edges_; }
  bool has_edge(Index a, Index b) const { return index_.count(undirected_key(a, b)) != 0; }

  // Fixes the forced edges, then runs the skeleton loop. False if two fixed edges cross.
  bool run(const std::vector<std::array<Index, 2>>& forced);

  // Triangulates the faces of the fixed edges inside the region. `outside_face(walk)` tells
  // whether a face (its vertex cycle, counter-clockwise around the face) is outside the region.
  // With `hull_outer`, the face outside the convex hull is skipped too: the face at the
  // lexicographically lowest vertex v0 that contains the direction (−1, 0) (all points lie in the
  // closed half-plane x ≥ x0, so that wedge is outside; exact).
  CoreResult triangulate_faces(const std::function<bool(const std::vector<Index>&)>& outside_face, std::size_t max_region,
                               bool hull_outer) const;

 private:
  // triangulate_faces' steps: the fixed edges around each vertex, their connectivity, their
  // counter-clockwise order, and an edge of the face outside the convex hull.
  std::vector<std::vector<Index>> fixed_neighbours(std::size_t& count) const;
  bool connected(const std::vector<std::vector<Index>>& around) const;
  void sort_counter_clockwise(std::vector<std::vector<Index>>& around) const;
  std::uint64_t outer_face_edge(const std::vector<std::vector<Index>>& around) const;

  static constexpr std::uint8_t kAlive = 0, kFixed = 1, kDead = 2;

  struct Apex {
    Index w;       // the third corner
    Index e1, e2;  // the edges (a, w) and (b, w) of the triangle on edge (a, b)
  };

  void index_edges();

  bool has_triangles_on_both_sides(Index e) const;

  // Removes the dead edges and the triangles using them, renumbering the rest.
  void drop_dead_edges();

  bool build_crossings(std::size_t max_crossings);

  // Candidate triangles: three candidate edges bounding a triangle with no vertex inside.
  bool build_triangles(std::size_t max_triangles);

  bool empty(const PointGrid& grid, Index a, Index b, Index w, int side) const;

  bool locally_minimal_pair(Index e) const;

  bool usable(const Apex& t) const { return state_[t.e1] != kDead && state_[t.e2] != kDead; }

  void push(Index e);

  bool fix(Index e);

  void kill(Index e);

  const std::vector<Point>& P_;
  std::vector<std::array<Index, 2>> E_;
  std::unordered_map<std::uint64_t, Index> index_;
  std::vector<std::vector<std::pair<Index, Index>>> adjacency_;  // (neighbour, edge), by neighbour
  std::vector<Index> cross_start_, cross_;
  std::vector<Index> tri_start_;
  std::vector<Apex> apex_;
  std::vector<std::int8_t> apex_side_;
  std::vector<std::uint8_t> state_, queued_;
  std::vector<Index> work_;
  std::size_t initial_edges_ = 0;
  std::string overflow_;
};

}  // namespace mwst::mwt
