// src/algorithms/mwt/skeleton.cpp — the LMT-skeleton and the face dynamic program (skeleton.hpp).
#include "algorithms/mwt/skeleton.hpp"

#include <algorithm>
#include <limits>
#include <numeric>

#include "mwst/error.hpp"
#include "algorithms/mwt/polygon_mwt.hpp"

namespace mwst::mwt {

Skeleton::Skeleton(const std::vector<Point>& P, std::vector<std::array<Index, 2>> edges,
         const std::vector<std::array<Index, 2>>& forced, std::size_t max_triangles, std::size_t max_crossings)
    : P_(P), E_(std::move(edges)) {
  initial_edges_ = E_.size();
  index_edges();
  if (!build_triangles(max_triangles)) {
    overflow_ = "too many candidate triangles";
    return;
  }
  state_.assign(E_.size(), kAlive);
  for (const auto& f : forced) {
    auto it = index_.find(undirected_key(f[0], f[1]));
    if (it == index_.end()) throw InternalError("mwt: a forced edge is not a candidate");
    state_[it->second] = kFixed;
  }
  for (bool changed = true; changed;) {
    changed = false;
    for (Index e = 0; e < E_.size(); ++e) {
      if (state_[e] == kAlive && has_triangles_on_both_sides(e) && !locally_minimal_pair(e)) {
        state_[e] = kDead;
        changed = true;
      }
    }
  }
  drop_dead_edges();
  if (!build_crossings(max_crossings)) {
    overflow_ = "too many crossing pairs of candidate edges";
    return;
  }
  state_.assign(E_.size(), kAlive);
}

bool Skeleton::run(const std::vector<std::array<Index, 2>>& forced) {
  for (const auto& f : forced) {
    auto it = index_.find(undirected_key(f[0], f[1]));
    if (it == index_.end()) throw InternalError("mwt: a forced edge is not a candidate");
    if (!fix(it->second)) return false;
  }
  for (Index e = 0; e < E_.size(); ++e) push(e);
  while (!work_.empty()) {
    const Index e = work_.back();
    work_.pop_back();
    queued_[e] = 0;
    if (state_[e] != kAlive) continue;
    bool crossed = false;
    for (Index k = cross_start_[e]; k < cross_start_[e + 1]; ++k) {
      if (state_[cross_[k]] != kDead) {
        crossed = true;
        break;
      }
    }
    if (!crossed) {
      if (!fix(e)) return false;
    } else if (!locally_minimal_pair(e)) {
      kill(e);
    }
  }
  return true;
}

// The fixed neighbours of every vertex; `count` gets the number of fixed edges.
std::vector<std::vector<Index>> Skeleton::fixed_neighbours(std::size_t& count) const {
  std::vector<std::vector<Index>> around(P_.size());
  for (Index e = 0; e < E_.size(); ++e) {
    if (state_[e] != kFixed) continue;
    ++count;
    around[E_[e][0]].push_back(E_[e][1]);
    around[E_[e][1]].push_back(E_[e][0]);
  }
  return around;
}

// Connectivity: with one component containing every vertex, each face is a disk.
bool Skeleton::connected(const std::vector<std::vector<Index>>& around) const {
  const std::size_t n = P_.size();
  std::vector<Index> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](Index x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (Index v = 0; v < n; ++v) {
    for (Index w : around[v]) parent[find(v)] = find(w);
  }
  for (Index v = 1; v < n; ++v) {
    if (find(v) != find(0)) return false;
  }
  return true;
}

// Counter-clockwise order of the fixed neighbours of each vertex (exact).
void Skeleton::sort_counter_clockwise(std::vector<std::vector<Index>>& around) const {
  for (Index v = 0; v < P_.size(); ++v) {
    const Point& c = P_[v];
    auto half = [&](Index w) { return P_[w].y > c.y || (P_[w].y == c.y && P_[w].x > c.x) ? 0 : 1; };
    std::sort(around[v].begin(), around[v].end(), [&](Index a, Index b) {
      const int ha = half(a), hb = half(b);
      if (ha != hb) return ha < hb;
      return orient2d(c, P_[a], P_[b]) > 0;
    });
  }
}

// A directed fixed edge of the face outside the convex hull: at the lexicographically lowest
// vertex v0, the neighbour just before (counter-clockwise) the first one in the lower half-plane.
std::uint64_t Skeleton::outer_face_edge(const std::vector<std::vector<Index>>& around) const {
  Index v0 = 0;
  for (Index v = 1; v < P_.size(); ++v) {
    if (P_[v].x < P_[v0].x || (P_[v].x == P_[v0].x && P_[v].y < P_[v0].y)) v0 = v;
  }
  const auto& ring = around[v0];
  std::size_t k = 0;
  const Point& c = P_[v0];
  while (k < ring.size() && (P_[ring[k]].y > c.y || (P_[ring[k]].y == c.y && P_[ring[k]].x > c.x))) ++k;
  const Index w = (k == 0 || k == ring.size()) ? ring.back() : ring[k - 1];
  return edge_key(v0, w);
}

CoreResult Skeleton::triangulate_faces(const std::function<bool(const std::vector<Index>&)>& outside_face,
                                       std::size_t max_region, bool hull_outer) const {
  CoreResult r;
  const std::size_t n = P_.size();
  std::vector<std::vector<Index>> around = fixed_neighbours(r.skeleton_edges);
  if (!connected(around)) {
    r.reason = "the LMT-skeleton is disconnected (a face is not a simple polygon)";
    return r;
  }
  sort_counter_clockwise(around);
  const std::uint64_t hull_edge = hull_outer ? outer_face_edge(around) : std::numeric_limits<std::uint64_t>::max();
  std::unordered_map<std::uint64_t, Index> position;  // directed (v, w) → index of w around v
  for (Index v = 0; v < n; ++v) {
    for (Index i = 0; i < around[v].size(); ++i) position.emplace(edge_key(v, around[v][i]), i);
  }
  std::unordered_map<std::uint64_t, char> visited;
  std::vector<Index> walk;
  std::vector<Point> polygon;
  std::vector<std::array<std::uint32_t, 3>> local;
  std::size_t diagonals = 0;
  for (Index v0 = 0; v0 < n; ++v0) {
    for (Index w0 : around[v0]) {
      if (visited.count(edge_key(v0, w0))) continue;
      walk.clear();
      Index a = v0, b = w0;
      // The face on the left of a→b: at b, continue with the neighbour just clockwise of a.
      while (!visited.count(edge_key(a, b))) {
        visited.emplace(edge_key(a, b), 1);
        walk.push_back(a);
        const auto& ring = around[b];
        const Index i = position.at(edge_key(b, a));
        const Index c = ring[(i + ring.size() - 1) % ring.size()];
        a = b;
        b = c;
      }
      bool outer = false;
      for (std::size_t i = 0; hull_outer && i < walk.size() && !outer; ++i) {
        outer = edge_key(walk[i], walk[(i + 1) % walk.size()]) == hull_edge;
      }
      if (outer || outside_face(walk)) continue;
      std::vector<Index> sorted = walk;
      std::sort(sorted.begin(), sorted.end());
      if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) {
        r.reason = "a face of the LMT-skeleton is not a simple polygon (dangling edges)";
        return r;
      }
      if (walk.size() == 3) {
        r.triangles.push_back({walk[0], walk[1], walk[2]});
        continue;
      }
      ++r.regions;
      r.largest_region = std::max(r.largest_region, walk.size());
      if (walk.size() > max_region) {
        r.reason = "a face of the LMT-skeleton has more corners than max_region";
        return r;
      }
      polygon.clear();
      for (Index v : walk) polygon.push_back(P_[v]);
      local.clear();
      const double w = polygon_mwt(polygon, &local);
      if (!(w < std::numeric_limits<double>::infinity())) {
        r.reason = "the polygon DP found no triangulation of a skeleton face";
        return r;
      }
      diagonals += walk.size() - 3;
      for (const auto& t : local) r.triangles.push_back({walk[t[0]], walk[t[1]], walk[t[2]]});
    }
  }
  r.result_edges = r.skeleton_edges + diagonals;
  r.solved = true;
  return r;
}

void Skeleton::index_edges() {
  index_.clear();
  for (Index e = 0; e < E_.size(); ++e) index_.emplace(edge_key(E_[e][0], E_[e][1]), e);
  adjacency_.assign(P_.size(), {});
  for (Index e = 0; e < E_.size(); ++e) {
    adjacency_[E_[e][0]].push_back({E_[e][1], e});
    adjacency_[E_[e][1]].push_back({E_[e][0], e});
  }
  for (auto& a : adjacency_) std::sort(a.begin(), a.end());
}

bool Skeleton::has_triangles_on_both_sides(Index e) const {
  bool left = false, right = false;
  for (Index i = tri_start_[e]; i < tri_start_[e + 1]; ++i) {
    if (usable(apex_[i])) (apex_side_[i] > 0 ? left : right) = true;
  }
  return left && right;
}

void Skeleton::drop_dead_edges() {
  std::vector<Index> renumber(E_.size(), kNone);
  std::vector<std::array<Index, 2>> kept;
  std::vector<std::uint8_t> kept_state;
  for (Index e = 0; e < E_.size(); ++e) {
    if (state_[e] == kDead) continue;
    renumber[e] = static_cast<Index>(kept.size());
    kept.push_back(E_[e]);
    kept_state.push_back(state_[e]);
  }
  std::vector<Index> start{0};
  std::vector<Apex> apex;
  std::vector<std::int8_t> side;
  for (Index e = 0; e < E_.size(); ++e) {
    if (state_[e] == kDead) continue;
    for (Index i = tri_start_[e]; i < tri_start_[e + 1]; ++i) {
      const Apex& t = apex_[i];
      if (renumber[t.e1] == kNone || renumber[t.e2] == kNone) continue;
      apex.push_back({t.w, renumber[t.e1], renumber[t.e2]});
      side.push_back(apex_side_[i]);
    }
    start.push_back(static_cast<Index>(apex.size()));
  }
  E_ = std::move(kept);
  state_ = std::move(kept_state);
  apex_ = std::move(apex);
  apex_side_ = std::move(side);
  tri_start_ = std::move(start);
  index_edges();
}

bool Skeleton::build_crossings(std::size_t max_crossings) {
  std::vector<Box> boxes;
  boxes.reserve(E_.size());
  for (const auto& e : E_) {
    const Point& a = P_[e[0]];
    const Point& b = P_[e[1]];
    boxes.push_back({std::min(a.x, b.x), std::min(a.y, b.y), std::max(a.x, b.x), std::max(a.y, b.y)});
  }
  const BoxTree tree(boxes);
  cross_.clear();
  cross_start_.assign(E_.size() + 1, 0);
  for (Index e = 0; e < E_.size(); ++e) {
    const Index a = E_[e][0], b = E_[e][1];
    tree.query(boxes[e], [&](Index f) {
      const Index c = E_[f][0], d = E_[f][1];
      if (c == a || c == b || d == a || d == b) return true;
      if (properly_cross(P_[a], P_[b], P_[c], P_[d])) cross_.push_back(f);
      return true;
    });
    if (cross_.size() > max_crossings) return false;
    cross_start_[e + 1] = static_cast<Index>(cross_.size());
  }
  return true;
}

bool Skeleton::build_triangles(std::size_t max_triangles) {
  const PointGrid grid(P_);
  tri_start_.assign(E_.size() + 1, 0);
  for (Index e = 0; e < E_.size(); ++e) {
    const Index a = E_[e][0], b = E_[e][1];
    const auto& A = adjacency_[a];
    const auto& B = adjacency_[b];
    std::size_t i = 0, j = 0;
    while (i < A.size() && j < B.size()) {
      if (A[i].first < B[j].first) {
        ++i;
      } else if (B[j].first < A[i].first) {
        ++j;
      } else {
        const Index w = A[i].first;
        const int side = orient2d(P_[a], P_[b], P_[w]);
        if (side != 0 && empty(grid, a, b, w, side)) {
          apex_.push_back({w, A[i].second, B[j].second});
          apex_side_.push_back(static_cast<std::int8_t>(side));
        }
        ++i, ++j;
      }
    }
    if (apex_.size() > max_triangles) return false;
    tri_start_[e + 1] = static_cast<Index>(apex_.size());
  }
  return true;
}

bool Skeleton::empty(const PointGrid& grid, Index a, Index b, Index w, int side) const {
  const Index p = a, q = side > 0 ? b : w, r = side > 0 ? w : b;  // counter-clockwise
  const Point& A = P_[p];
  const Point& B = P_[q];
  const Point& C = P_[r];
  bool is_empty = true;
  grid.for_each_in_box(std::min({A.x, B.x, C.x}), std::min({A.y, B.y, C.y}), std::max({A.x, B.x, C.x}),
                       std::max({A.y, B.y, C.y}), [&](Index k) {
                         if (k == p || k == q || k == r) return true;
                         const Point& X = P_[k];
                         if (orient2d(A, B, X) >= 0 && orient2d(B, C, X) >= 0 && orient2d(C, A, X) >= 0) {
                           is_empty = false;
                           return false;
                         }
                         return true;
                       });
  return is_empty;
}

bool Skeleton::locally_minimal_pair(Index e) const {
  const Index a = E_[e][0], b = E_[e][1];
  const Point& A = P_[a];
  const Point& B = P_[b];
  for (Index i = tri_start_[e]; i < tri_start_[e + 1]; ++i) {
    if (apex_side_[i] < 0 || !usable(apex_[i])) continue;
    for (Index j = tri_start_[e]; j < tri_start_[e + 1]; ++j) {
      if (apex_side_[j] > 0 || !usable(apex_[j])) continue;
      const Point& W = P_[apex_[i].w];
      const Point& X = P_[apex_[j].w];
      // Strictly convex quadrilateral a x b w: the diagonal wx crosses ab properly.
      const int o1 = orient2d(W, X, A), o2 = orient2d(W, X, B);
      const bool convex = o1 != 0 && o2 != 0 && o1 != o2;
      if (!convex || compare_squared_lengths(A, B, W, X) <= 0) return true;
    }
  }
  return false;
}

void Skeleton::push(Index e) {
  if (queued_.size() != E_.size()) queued_.assign(E_.size(), 0);
  if (state_[e] != kAlive || queued_[e]) return;
  queued_[e] = 1;
  work_.push_back(e);
}

bool Skeleton::fix(Index e) {
  if (state_[e] == kFixed) return true;
  if (state_[e] == kDead) return false;
  state_[e] = kFixed;
  for (Index k = cross_start_[e]; k < cross_start_[e + 1]; ++k) {
    const Index f = cross_[k];
    if (state_[f] == kFixed) return false;
    if (state_[f] == kAlive) kill(f);
  }
  return true;
}

void Skeleton::kill(Index e) {
  state_[e] = kDead;
  for (Index i = tri_start_[e]; i < tri_start_[e + 1]; ++i) {
    push(apex_[i].e1);
    push(apex_[i].e2);
  }
  for (Index k = cross_start_[e]; k < cross_start_[e + 1]; ++k) push(cross_[k]);
}

}  // namespace mwst::mwt
