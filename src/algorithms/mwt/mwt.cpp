// The exact minimum weight triangulation of a mesh's vertex set with its segments as constraints
// (mwst/algorithms/mwt.hpp), after Beirouti and Snoeyink, "Implementations of the LMT heuristic for
// minimum weight triangulation" (SoCG 1998); docs/algorithms/mwt.md tells the whole method.
//  1. Candidate edges: the diamond test of Drysdale, McElfresh and Snoeyink (route "diamond",
//     enumerated in growing disks with "dead sectors"), or all visible pairs (route "visibility").
//     Witness and angle tests run in doubles with a margin that only ever keeps an edge; vertex-on-
//     edge and crossing tests are exact (orient2d).
//  2. The LMT-skeleton (Dickerson and Montague 1996): edges with no locally minimal empty pair of
//     candidate triangles die, edges no living candidate crosses are fixed; repeat.
//  3. The faces of the fixed edges: the polygon dynamic program (polygon_mwt.hpp) when simple,
//     else "not solved".
//  4. Route "diamond" answers for the domain only if its triangulation contains every subsegment
//     and boundary edge; otherwise the visibility route is tried.
// Lengths are summed in doubles: "exact" means exact up to the rounding of those sums.
#include "mwst/algorithms/mwt.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mwst/error.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "algorithms/mwt/polygon_mwt.hpp"
#include "mesh/keys.hpp"

namespace mwst {

namespace {

using Index = std::uint32_t;
using Tri = std::array<Index, 3>;

// ---- the domain ---------------------------------------------------------------------------------

struct Domain {
  std::vector<VertexId> ids;   // local index → mesh vertex
  std::vector<Point> pts;      // local coordinates
  std::vector<Tri> triangles;  // the mesh's in-domain triangles (local, counter-clockwise)
  std::vector<std::array<Index, 2>> constraints;     // subsegments and boundary edges (a < b)
  std::vector<std::array<Index, 2>> boundary;        // directed boundary edges, domain on the left
  std::unordered_map<std::uint64_t, Handle> outer;   // (org, dest) mesh ids of a boundary edge → handle outside
  std::vector<std::array<std::int64_t, 3>> segments; // subsegments: mesh ids a, b and marker
  std::vector<std::vector<Index>> segment_neighbours;  // per local vertex, along subsegments
  std::vector<char> on_segment;  // a Steiner point splitting a segment (VertexKind::kSteinerOnSegment)
};

// A triangle whose corner at a segment's Steiner point has two subsegments as sides spans a
// straight angle in truth (the rounded point only looks convex): a sliver along the segment, which
// EFH may not make either (flip.hpp, is_straight_corner). Such triangles are excluded.
bool straight_corner(const Domain& d, Index apex, Index a, Index b) {
  if (!d.on_segment[apex]) return false;
  const auto& s = d.segment_neighbours[apex];
  return std::find(s.begin(), s.end(), a) != s.end() && std::find(s.begin(), s.end(), b) != s.end();
}

Domain collect_domain(const Mesh& m) {
  Domain d;
  std::unordered_map<VertexId, Index> local;
  auto local_of = [&](VertexId v) {
    auto [it, inserted] = local.emplace(v, static_cast<Index>(d.ids.size()));
    if (inserted) {
      d.ids.push_back(v);
      d.pts.push_back(m.points[v]);
    }
    return it->second;
  };
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (!m.in_domain(t)) continue;
    const auto& v = m.triangles[t].v;
    d.triangles.push_back({local_of(v[0]), local_of(v[1]), local_of(v[2])});
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      const TriangleId other = m.sym(h) >> 2;
      const bool boundary = !m.in_domain(other);
      const bool segment = m.is_segment(h);
      const Index a = local_of(m.org(h)), b = local_of(m.dest(h));
      if (boundary) {
        d.boundary.push_back({a, b});
        d.outer.emplace(edge_key(m.org(h), m.dest(h)), m.sym(h));
      }
      if (boundary || (segment && t < other)) d.constraints.push_back({std::min(a, b), std::max(a, b)});
      if (segment && (boundary || t < other)) d.segments.push_back({m.org(h), m.dest(h), m.marker(h)});
    }
  }
  d.segment_neighbours.assign(d.ids.size(), {});
  d.on_segment.assign(d.ids.size(), 0);
  for (const auto& s : d.segments) {
    const Index a = local.at(static_cast<VertexId>(s[0])), b = local.at(static_cast<VertexId>(s[1]));
    d.segment_neighbours[a].push_back(b);
    d.segment_neighbours[b].push_back(a);
  }
  for (Index i = 0; i < d.ids.size(); ++i) {
    d.on_segment[i] = d.ids[i] < m.vertex_kind.size() && m.vertex_kind[d.ids[i]] == VertexKind::kSteinerOnSegment;
  }
  return d;
}

// ---- box queries: a bounding-volume tree (median splits), robust to clustered inputs ----------

struct Box {
  double xmin, ymin, xmax, ymax;
};

class BoxTree {
 public:
  explicit BoxTree(std::vector<Box> boxes) : boxes_(std::move(boxes)) {
    order_.resize(boxes_.size());
    std::iota(order_.begin(), order_.end(), Index{0});
    if (!boxes_.empty()) build(0, static_cast<Index>(order_.size()));
  }

  // Calls f(i) for every item whose box meets q, until f returns false.
  template <class F>
  void query(const Box& q, F&& f) const {
    if (nodes_.empty()) return;
    Index stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (!meets(node.box, q)) continue;
      if (node.left == kNone) {
        for (Index k = node.begin; k < node.end; ++k) {
          if (meets(boxes_[order_[k]], q) && !f(order_[k])) return;
        }
        continue;
      }
      stack[top++] = node.left;
      stack[top++] = node.right;
    }
  }

 private:
  struct Node {
    Box box;
    Index begin, end, left, right;
  };
  static bool meets(const Box& a, const Box& b) {
    return a.xmin <= b.xmax && b.xmin <= a.xmax && a.ymin <= b.ymax && b.ymin <= a.ymax;
  }
  Index build(Index begin, Index end) {
    Box box = boxes_[order_[begin]];
    for (Index k = begin + 1; k < end; ++k) {
      const Box& b = boxes_[order_[k]];
      box = {std::min(box.xmin, b.xmin), std::min(box.ymin, b.ymin), std::max(box.xmax, b.xmax), std::max(box.ymax, b.ymax)};
    }
    const auto id = static_cast<Index>(nodes_.size());
    nodes_.push_back({box, begin, end, kNone, kNone});
    if (end - begin <= 8) return id;
    const bool by_x = box.xmax - box.xmin >= box.ymax - box.ymin;
    const Index mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end, [&](Index a, Index b) {
      const Box& A = boxes_[a];
      const Box& B = boxes_[b];
      return by_x ? A.xmin + A.xmax < B.xmin + B.xmax : A.ymin + A.ymax < B.ymin + B.ymax;
    });
    const Index left = build(begin, mid);
    const Index right = build(mid, end);
    nodes_[id].left = left;
    nodes_[id].right = right;
    return id;
  }

  std::vector<Box> boxes_;
  std::vector<Index> order_;
  std::vector<Node> nodes_;  // depth ≤ log2(n / 8) + 1 (median splits), well inside the stack
};

class PointGrid {
 public:
  explicit PointGrid(const std::vector<Point>& p) : tree_(boxes(p)) {
    double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
    for (const Point& q : p) {
      x0 = std::min(x0, q.x), y0 = std::min(y0, q.y);
      x1 = std::max(x1, q.x), y1 = std::max(y1, q.y);
    }
    diagonal_ = std::hypot(x1 - x0, y1 - y0);
    magnitude_ = std::max({std::fabs(x0), std::fabs(x1), std::fabs(y0), std::fabs(y1)});
  }
  double diagonal() const { return diagonal_; }
  double magnitude() const { return magnitude_; }

  // Calls f(i) for every point in the box, until f returns false.
  template <class F>
  void for_each_in_box(double xmin, double ymin, double xmax, double ymax, F&& f) const {
    tree_.query(Box{xmin, ymin, xmax, ymax}, std::forward<F>(f));
  }

 private:
  static std::vector<Box> boxes(const std::vector<Point>& p) {
    std::vector<Box> b;
    b.reserve(p.size());
    for (const Point& q : p) b.push_back({q.x, q.y, q.x, q.y});
    return b;
  }
  BoxTree tree_;
  double diagonal_ = 0, magnitude_ = 0;
};

// Exact: does p lie on the open segment uv (p ≠ u, v)?
bool on_open_segment(const Point& u, const Point& v, const Point& p) {
  if (orient2d(u, v, p) != 0) return false;
  if (u.x != v.x) return std::min(u.x, v.x) < p.x && p.x < std::max(u.x, v.x);
  return std::min(u.y, v.y) < p.y && p.y < std::max(u.y, v.y);
}

// Exact: do the segments ab and cd cross at a point interior to both (no shared endpoint)?
bool properly_cross(const Point& a, const Point& b, const Point& c, const Point& d) {
  const int o1 = orient2d(a, b, c), o2 = orient2d(a, b, d);
  if (o1 == 0 || o2 == 0 || o1 == o2) return false;
  const int o3 = orient2d(c, d, a), o4 = orient2d(c, d, b);
  return o3 != 0 && o4 != 0 && o3 != o4;
}

// ---- candidates: the diamond test ---------------------------------------------------------------

enum class Diamond { kKeep, kExcluded, kThroughVertex };

Diamond diamond_test(const std::vector<Point>& P, const PointGrid& grid, Index u, Index v,
                     double tan_angle) {
  const Point& a = P[u];
  const Point& b = P[v];
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double L = std::hypot(dx, dy);
  const double ex = dx / L, ey = dy / L;
  const double margin = 1e-12 * L + 1e-13 * grid.magnitude();
  const double h = 0.5 * L * tan_angle + margin;
  const double mx = 0.5 * (a.x + b.x), my = 0.5 * (a.y + b.y);
  const double xmin = std::min({a.x, b.x, mx - std::fabs(ey) * h}) - margin;
  const double xmax = std::max({a.x, b.x, mx + std::fabs(ey) * h}) + margin;
  const double ymin = std::min({a.y, b.y, my - std::fabs(ex) * h}) - margin;
  const double ymax = std::max({a.y, b.y, my + std::fabs(ex) * h}) + margin;
  bool left = false, right = false, through = false;
  grid.for_each_in_box(xmin, ymin, xmax, ymax, [&](Index k) {
    if (k == u || k == v) return true;
    const Point& p = P[k];
    const double qx = p.x - a.x, qy = p.y - a.y;
    const double t = qx * ex + qy * ey;
    const double s = ex * qy - ey * qx;  // signed distance, left of a→b positive
    if (std::fabs(s) <= margin + 1e-9 * L && on_open_segment(a, b, p)) {
      through = true;
      return false;
    }
    if (t <= margin || t >= L - margin || std::fabs(s) <= margin) return true;
    if (std::fabs(s) < tan_angle * std::min(t, L - t) - margin) {
      (s > 0 ? left : right) = true;
    }
    return true;  // keep scanning: a vertex on the edge must still be found
  });
  if (through) return Diamond::kThroughVertex;
  return (left && right) ? Diamond::kExcluded : Diamond::kKeep;
}

std::vector<std::array<Index, 2>> diamond_candidates(const std::vector<Point>& P, double angle,
                                                     std::size_t max_edges, bool& too_many) {
  const PointGrid grid(P);
  const double shrunk = angle * (1.0 - 1e-6);
  const double tan_angle = std::tan(shrunk);
  const double gap_limit = shrunk - 3e-9;
  constexpr double kAngleSlack = 1e-9;
  std::vector<std::array<Index, 2>> edges;
  std::vector<double> angles;
  for (Index u = 0; u < P.size(); ++u) {
    const Point& a = P[u];
    auto visit_disk = [&](double radius, auto&& f) {
      grid.for_each_in_box(a.x - radius, a.y - radius, a.x + radius, a.y + radius, [&](Index k) {
        if (k != u) f(k, std::hypot(P[k].x - a.x, P[k].y - a.y));
        return true;
      });
    };
    auto test = [&](Index v) {
      if (v <= u) return;
      if (diamond_test(P, grid, u, v, tan_angle) == Diamond::kKeep) edges.push_back({u, v});
    };
    if (edges.size() > max_edges) {
      too_many = true;
      return {};
    }
    // Start at about the nearest-neighbour distance (doubling from a tiny radius until the square
    // of half-width r holds another point), so clustered inputs start at their local scale.
    double r = grid.diagonal() * 0x1p-40;
    for (bool found = false; !found && r < grid.diagonal();) {
      grid.for_each_in_box(a.x - r, a.y - r, a.x + r, a.y + r, [&](Index k) {
        found = k != u;
        return !found;
      });
      if (!found) r *= 2.0;
    }
    visit_disk(2.0 * r, [&](Index v, double dist) {
      if (dist <= 2.0 * r) test(v);
    });
    while (2.0 * r <= grid.diagonal() * (1.0 + 1e-9)) {
      // Dead sectors from the points within r (with a margin on r) for the edges longer than 2r.
      angles.clear();
      visit_disk(r, [&](Index k, double dist) {
        if (dist <= r * (1.0 - 1e-9)) angles.push_back(std::atan2(P[k].y - a.y, P[k].x - a.x));
      });
      std::sort(angles.begin(), angles.end());
      bool all_dead = angles.size() >= 2;
      for (std::size_t i = 0; all_dead && i < angles.size(); ++i) {
        const double next = i + 1 < angles.size() ? angles[i + 1] : angles[0] + 2.0 * std::numbers::pi;
        if (next - angles[i] >= gap_limit) all_dead = false;
      }
      if (all_dead) break;
      auto dead = [&](double psi) {
        if (angles.size() < 2) return false;
        // first angle above psi + slack (cyclically) and last below psi − slack
        auto it = std::upper_bound(angles.begin(), angles.end(), psi + kAngleSlack);
        const double above = it != angles.end() ? *it : angles.front() + 2.0 * std::numbers::pi;
        auto jt = std::lower_bound(angles.begin(), angles.end(), psi - kAngleSlack);
        const double below = jt != angles.begin() ? *(jt - 1) : angles.back() - 2.0 * std::numbers::pi;
        return above - psi < shrunk - kAngleSlack && psi - below < shrunk - kAngleSlack &&
               above - psi > kAngleSlack && psi - below > kAngleSlack;
      };
      const double inner = 2.0 * r, outer = 4.0 * r;
      visit_disk(outer, [&](Index v, double dist) {
        if (v <= u || dist <= inner || dist > outer) return;
        if (dead(std::atan2(P[v].y - a.y, P[v].x - a.x))) return;
        test(v);
      });
      r *= 2.0;
    }
  }
  return edges;
}

// ---- candidates: visibility in the domain -------------------------------------------------------

std::vector<std::array<Index, 2>> visibility_candidates(const Domain& d) {
  const std::vector<Point>& P = d.pts;
  const std::size_t n = P.size();
  // Corners of the domain triangles at each vertex: (next, previous) counter-clockwise.
  std::vector<std::vector<std::array<Index, 2>>> corners(n);
  for (const Tri& t : d.triangles) {
    for (unsigned k = 0; k < 3; ++k) corners[t[k]].push_back({t[(k + 1) % 3], t[(k + 2) % 3]});
  }
  auto enters_domain = [&](Index u, Index v) {
    for (const auto& c : corners[u]) {
      if (c[0] == v || c[1] == v) return true;
      if (orient2d(P[u], P[c[0]], P[v]) > 0 && orient2d(P[u], P[c[1]], P[v]) < 0) return true;
    }
    return false;
  };
  std::vector<std::array<Index, 2>> edges;
  for (Index u = 0; u < n; ++u) {
    for (Index v = u + 1; v < n; ++v) {
      bool ok = enters_domain(u, v);
      for (Index r : d.segment_neighbours[u]) ok = ok && !straight_corner(d, r, u, v);
      for (Index k = 0; ok && k < n; ++k) {
        if (k != u && k != v && on_open_segment(P[u], P[v], P[k])) ok = false;
      }
      for (std::size_t s = 0; ok && s < d.constraints.size(); ++s) {
        const auto& c = d.constraints[s];
        if (c[0] == u || c[0] == v || c[1] == u || c[1] == v) continue;
        if (properly_cross(P[u], P[v], P[c[0]], P[c[1]])) ok = false;
      }
      if (ok) edges.push_back({u, v});
    }
  }
  return edges;
}

// ---- the LMT-skeleton and the face DP -----------------------------------------------------------

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

  const std::string& overflow() const { return overflow_; }
  std::size_t size() const { return E_.size(); }
  std::size_t initial_size() const { return initial_edges_; }
  bool has_edge(Index a, Index b) const { return index_.count(undirected_key(a, b)) != 0; }

  // Fixes the forced edges, then runs the skeleton loop. False if two fixed edges cross.
  bool run(const std::vector<std::array<Index, 2>>& forced) {
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

  // Triangulates the faces of the fixed edges inside the region. `outside_face(walk)` tells
  // whether a face (its vertex cycle, counter-clockwise around the face) is outside the region.
  // With `hull_outer`, the face outside the convex hull is skipped too: the face at the
  // lexicographically lowest vertex v0 that contains the direction (−1, 0) (all points lie in the
  // closed half-plane x ≥ x0, so that wedge is outside; exact).
  template <class OutsideFace>
  CoreResult triangulate_faces(OutsideFace outside_face, std::size_t max_region, bool hull_outer) const {
    CoreResult r;
    const std::size_t n = P_.size();
    std::vector<std::vector<Index>> around(n);
    for (Index e = 0; e < E_.size(); ++e) {
      if (state_[e] != kFixed) continue;
      ++r.skeleton_edges;
      around[E_[e][0]].push_back(E_[e][1]);
      around[E_[e][1]].push_back(E_[e][0]);
    }
    // Connectivity: with one component containing every vertex, each face is a disk.
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
      if (find(v) != find(0)) {
        r.reason = "the LMT-skeleton is disconnected (a face is not a simple polygon)";
        return r;
      }
    }
    // Counter-clockwise order of the fixed neighbours of each vertex (exact).
    for (Index v = 0; v < n; ++v) {
      const Point& c = P_[v];
      auto half = [&](Index w) { return P_[w].y > c.y || (P_[w].y == c.y && P_[w].x > c.x) ? 0 : 1; };
      std::sort(around[v].begin(), around[v].end(), [&](Index a, Index b) {
        const int ha = half(a), hb = half(b);
        if (ha != hb) return ha < hb;
        return orient2d(c, P_[a], P_[b]) > 0;
      });
    }
    std::uint64_t hull_edge = std::numeric_limits<std::uint64_t>::max();
    if (hull_outer) {
      Index v0 = 0;
      for (Index v = 1; v < n; ++v) {
        if (P_[v].x < P_[v0].x || (P_[v].x == P_[v0].x && P_[v].y < P_[v0].y)) v0 = v;
      }
      const auto& ring = around[v0];
      // The neighbour just before (counter-clockwise) the first one in the lower half-plane.
      std::size_t k = 0;
      const Point& c = P_[v0];
      while (k < ring.size() && (P_[ring[k]].y > c.y || (P_[ring[k]].y == c.y && P_[ring[k]].x > c.x))) ++k;
      const Index w = (k == 0 || k == ring.size()) ? ring.back() : ring[k - 1];
      hull_edge = edge_key(v0, w);
    }
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

 private:
  static constexpr std::uint8_t kAlive = 0, kFixed = 1, kDead = 2;

  struct Apex {
    Index w;       // the third corner
    Index e1, e2;  // the edges (a, w) and (b, w) of the triangle on edge (a, b)
  };

  void index_edges() {
    index_.clear();
    for (Index e = 0; e < E_.size(); ++e) index_.emplace(edge_key(E_[e][0], E_[e][1]), e);
    adjacency_.assign(P_.size(), {});
    for (Index e = 0; e < E_.size(); ++e) {
      adjacency_[E_[e][0]].push_back({E_[e][1], e});
      adjacency_[E_[e][1]].push_back({E_[e][0], e});
    }
    for (auto& a : adjacency_) std::sort(a.begin(), a.end());
  }

  bool has_triangles_on_both_sides(Index e) const {
    bool left = false, right = false;
    for (Index i = tri_start_[e]; i < tri_start_[e + 1]; ++i) {
      if (usable(apex_[i])) (apex_side_[i] > 0 ? left : right) = true;
    }
    return left && right;
  }

  // Removes the dead edges and the triangles using them, renumbering the rest.
  void drop_dead_edges() {
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

  bool build_crossings(std::size_t max_crossings) {
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

  // Candidate triangles: three candidate edges bounding a triangle with no vertex inside.
  bool build_triangles(std::size_t max_triangles) {
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

  bool empty(const PointGrid& grid, Index a, Index b, Index w, int side) const {
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

  bool locally_minimal_pair(Index e) const {
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

  bool usable(const Apex& t) const { return state_[t.e1] != kDead && state_[t.e2] != kDead; }

  void push(Index e) {
    if (queued_.size() != E_.size()) queued_.assign(E_.size(), 0);
    if (state_[e] != kAlive || queued_[e]) return;
    queued_[e] = 1;
    work_.push_back(e);
  }

  bool fix(Index e) {
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

  void kill(Index e) {
    state_[e] = kDead;
    for (Index i = tri_start_[e]; i < tri_start_[e + 1]; ++i) {
      push(apex_[i].e1);
      push(apex_[i].e2);
    }
    for (Index k = cross_start_[e]; k < cross_start_[e + 1]; ++k) push(cross_[k]);
  }

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

// ---- the result mesh ----------------------------------------------------------------------------

Mesh rebuild(const Mesh& input, const Domain& d, const std::vector<Tri>& tris) {
  Mesh m = input;
  std::vector<TriangleId> slots;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (m.in_domain(t)) slots.push_back(t);
  }
  if (slots.size() != tris.size()) {
    throw InternalError("mwt: the optimal triangulation has " + std::to_string(tris.size()) +
                        " triangles, the domain " + std::to_string(slots.size()));
  }
  std::unordered_map<std::uint64_t, Handle> directed;
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const TriangleId t = slots[i];
    m.flags[t] = static_cast<std::uint8_t>(m.flags[t] & ~std::uint8_t{7});
    for (unsigned k = 0; k < 3; ++k) m.triangles[t].v[k] = d.ids[tris[i][k]];
    for (unsigned e = 0; e < 3; ++e) directed.emplace(edge_key(m.org(make_handle(t, e)), m.dest(make_handle(t, e))), make_handle(t, e));
  }
  for (const auto& [k, h] : directed) {
    const VertexId a = static_cast<VertexId>(k >> 32), b = static_cast<VertexId>(k & 0xFFFFFFFFu);
    auto it = directed.find(edge_key(b, a));
    if (it != directed.end()) {
      m.triangles[h >> 2].n[h & 3] = it->second;
      continue;
    }
    auto out = d.outer.find(k);
    if (out == d.outer.end()) throw InternalError("mwt: an edge of the optimal triangulation has no neighbour");
    m.triangles[h >> 2].n[h & 3] = out->second;
    m.triangles[out->second >> 2].n[out->second & 3] = h;
  }
  for (const auto& s : d.segments) {
    const auto it = directed.find(edge_key(static_cast<VertexId>(s[0]), static_cast<VertexId>(s[1])));
    if (it == directed.end()) throw InternalError("mwt: a subsegment is missing from the optimal triangulation");
    m.set_segment(it->second, static_cast<std::int32_t>(s[2]));
  }
  return m;
}

// The triangles of a triangulation of the convex hull lying in the domain: flood fill from the
// domain side of each boundary edge, never crossing a boundary edge. Empty if a boundary edge is
// missing.
std::vector<Tri> restrict_to_domain(const Domain& d, const std::vector<Tri>& tris) {
  std::unordered_map<std::uint64_t, Index> owner;
  for (Index i = 0; i < tris.size(); ++i) {
    for (unsigned k = 0; k < 3; ++k) owner.emplace(edge_key(tris[i][k], tris[i][(k + 1) % 3]), i);
  }
  std::unordered_map<std::uint64_t, char> barrier;
  for (const auto& b : d.boundary) barrier.emplace(edge_key(b[0], b[1]), 1), barrier.emplace(edge_key(b[1], b[0]), 1);
  std::vector<char> inside(tris.size(), 0);
  std::vector<Index> stack;
  for (const auto& b : d.boundary) {
    auto it = owner.find(edge_key(b[0], b[1]));
    if (it == owner.end()) return {};
    if (!inside[it->second]) inside[it->second] = 1, stack.push_back(it->second);
  }
  while (!stack.empty()) {
    const Index t = stack.back();
    stack.pop_back();
    for (unsigned k = 0; k < 3; ++k) {
      const Index a = tris[t][k], b = tris[t][(k + 1) % 3];
      if (barrier.count(edge_key(a, b))) continue;
      auto it = owner.find(edge_key(b, a));
      if (it != owner.end() && !inside[it->second]) inside[it->second] = 1, stack.push_back(it->second);
    }
  }
  std::vector<Tri> out;
  for (Index i = 0; i < tris.size(); ++i) {
    if (inside[i]) out.push_back(tris[i]);
  }
  return out;
}

}  // namespace

MwtResult exact_mwt(const Mesh& mesh, const MwtOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  MwtResult result;
  const Domain d = collect_domain(mesh);
  result.vertices = d.pts.size();
  auto finish = [&](const std::vector<Tri>& tris, const CoreResult& core, std::size_t candidates) {
    result.mesh = rebuild(mesh, d, tris);
    const std::vector<std::string> problems = validate(result.mesh);
    if (!problems.empty()) throw InternalError("mwt: the optimal triangulation is invalid: " + problems.front());
    result.solved = true;
    result.reason.clear();
    result.weight = measure(result.mesh).weight_total;
    result.candidate_edges = candidates;
    result.skeleton_edges = core.skeleton_edges;
    result.result_edges = core.result_edges;
    result.regions = core.regions;
    result.largest_region = core.largest_region;
  };
  if (d.pts.size() < 3) {
    result.reason = "the domain has no triangle";
    return result;
  }
  if (options.diamond_route) {
    result.route = "diamond";
    bool too_many = false;
    std::vector<std::array<Index, 2>> candidates =
        diamond_candidates(d.pts, options.diamond_angle, options.max_candidate_edges, too_many);
    result.candidate_edges = candidates.size();
    Skeleton skeleton(d.pts, too_many ? std::vector<std::array<Index, 2>>{} : std::move(candidates), {},
                      options.max_candidate_triangles, options.max_crossing_pairs);
    if (too_many) {
      result.reason = "too many candidate edges (diamond route)";
    } else if (!skeleton.overflow().empty()) {
      result.reason = skeleton.overflow() + " (diamond route)";
    } else if (!skeleton.run({})) {
      result.reason = "two fixed edges cross (diamond route)";
    } else {
      // Every face inside the convex hull is triangulated (the MWT of the point set).
      CoreResult core = skeleton.triangulate_faces([](const std::vector<Index>&) { return false; },
                                                   options.max_region, /*hull_outer=*/true);
      result.skeleton_edges = core.skeleton_edges;
      result.regions = core.regions;
      result.largest_region = core.largest_region;
      if (!core.solved) {
        result.reason = core.reason + " (diamond route)";
      } else {
        std::unordered_map<std::uint64_t, char> edges;
        for (const Tri& t : core.triangles) {
          for (unsigned k = 0; k < 3; ++k) edges.emplace(undirected_key(t[k], t[(k + 1) % 3]), 1);
        }
        bool contains_constraints = true;
        for (const auto& c : d.constraints) contains_constraints = contains_constraints && edges.count(edge_key(c[0], c[1]));
        if (!contains_constraints) {
          result.reason = "the point set's MWT misses a segment or boundary edge (diamond route)";
        } else {
          const std::vector<Tri> inside = restrict_to_domain(d, core.triangles);
          bool sliver = false;
          for (const Tri& t : inside) {
            for (unsigned k = 0; k < 3 && !sliver; ++k) sliver = straight_corner(d, t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
          }
          if (sliver) {
            result.reason = "the point set's MWT has a straight-angle sliver along a segment (diamond route)";
          } else {
            finish(inside, core, skeleton.initial_size());
          }
        }
      }
    }
  }
  if (!result.solved && d.pts.size() > options.max_visibility_vertices) {
    result.reason += (result.reason.empty() ? "" : "; ") + std::string("too many vertices for the visibility route");
  } else if (!result.solved) {
    const std::string earlier = result.reason.empty() ? "" : result.reason + "; ";
    result.route = "visibility";
    Skeleton skeleton(d.pts, visibility_candidates(d), d.constraints, options.max_candidate_triangles,
                      options.max_crossing_pairs);
    result.candidate_edges = skeleton.initial_size();
    if (!skeleton.overflow().empty()) {
      result.reason = earlier + skeleton.overflow() + " (visibility route)";
    } else if (!skeleton.run(d.constraints)) {
      result.reason = earlier + "two fixed edges cross (visibility route)";
    } else {
      std::unordered_map<std::uint64_t, char> reversed_boundary;
      for (const auto& b : d.boundary) reversed_boundary.emplace(edge_key(b[1], b[0]), 1);
      CoreResult core = skeleton.triangulate_faces(
          [&](const std::vector<Index>& walk) {
            for (std::size_t i = 0; i < walk.size(); ++i) {
              if (reversed_boundary.count(edge_key(walk[i], walk[(i + 1) % walk.size()]))) return true;
            }
            return false;
          },
          options.max_region, /*hull_outer=*/false);
      result.skeleton_edges = core.skeleton_edges;
      result.regions = core.regions;
      result.largest_region = core.largest_region;
      if (!core.solved) {
        result.reason = earlier + core.reason + " (visibility route)";
      } else {
        finish(core.triangles, core, skeleton.initial_size());
      }
    }
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace mwst
