// check_triangulation() (mwst/mesh/check.hpp): validates plain triangles read back from files against
// the input graph they claim to triangulate — the independent check behind `mwst check`, in the
// spirit of Triangle's checkmesh/checkdelaunay, but trusting nothing of the mesh's own structure.
//
// Topology: every directed edge occurs once (two triangles with the same orientation on an edge
// overlap), an edge with both orientations is interior, one with one orientation is on the mesh
// boundary, and the angles of the triangles around a vertex add up to 360° inside the mesh (at most
// 360° on its boundary), so no fan wraps twice. Geometry: orientation and incircle are exact
// (geometry.hpp); the domain comes from our constrained Delaunay triangulation of the input, whose
// boundary edges and segments must reappear in the mesh as chains of edges, possibly subdivided
// by (rounded) Steiner points; the mesh boundary must be exactly those chains, and the areas agree.
#include "mwst/mesh/check.hpp"
#include "mesh/check_tables.hpp"
#include "mesh/keys.hpp"
#include "geometry/expansion.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>

#include "mwst/mesh/delaunay.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst {

namespace detail {
// The orient2d determinant computed exactly and rounded to double (predicates.cpp; exact sign).
double orient2d_value(const Point& a, const Point& b, const Point& c);
}  // namespace detail

namespace {

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}
std::string point_text(const Point& p) {
  // Appended piece by piece: "(" + std::string + ... trips GCC 12's -Wrestrict false positive.
  std::string s = "(";
  s += number(p.x);
  s += ", ";
  s += number(p.y);
  s += ')';
  return s;
}

// Angle (degrees) at p between the rays to q and r; atan2 of cross and dot is accurate for tiny
// and near-straight angles alike.
double angle_deg(const Point& p, const Point& q, const Point& r) {
  const double ux = q.x - p.x, uy = q.y - p.y, vx = r.x - p.x, vy = r.y - p.y;
  return std::atan2(std::fabs(ux * vy - uy * vx), ux * vx + uy * vy) * (180.0 / std::numbers::pi);
}

// Kinds of mesh edges that lie on a chain of the reference domain.
constexpr std::uint8_t kOnDomainBoundary = 1;  // on a boundary edge of the domain
constexpr std::uint8_t kOnSegment = 2;         // on an input segment (or a piece of one)
constexpr std::uint8_t kOnChain = kOnDomainBoundary | kOnSegment;
constexpr std::uint8_t kListed = 4;            // (not a chain) listed as a subsegment by the mesh's .poly

// Tolerances for rounding, documented in check.hpp.
constexpr double kOnLineTolerance = 1e-12;  // times the coordinate magnitude of the segment
constexpr double kAreaTolerance = 1e-8;     // relative difference of mesh and domain area
constexpr double kTurnTolerance = 1e-6;     // degrees around a vertex
constexpr double kAngleTolerance = 1e-9;    // degrees, for --min-angle
// A mesh vertex on an input segment lies within this many ulps of the segment's largest coordinate
// magnitude M of the segment's line (check_input_segments). Rounded crossings and Steiner points
// are within an ulp (0.81 at most on the data sets under dt, dr, brh and qtr); the CDT resolves a
// crossing at a segment's end when that end is within 256·2^-52 of the larger of the crossing's
// magnitude and the segments' lengths (at most 2√2·M) of the crossing or of the other line, up to
// about 1450 ulps of M.
constexpr double kSegmentUlps = 2048.0;

// Position along the piece a → b: the coordinate in which the piece runs furthest, signed to grow
// from a to b. It orders the vertices along the piece exactly, where the parameter
// t = (q − a)·(b − a) / |b − a|² does not: t rounds to one value for vertices a few ulps apart on a
// long piece (refinement can put a cluster of Steiner points within 1e-20 of each other 16 units
// along a hull edge), so a chain through them would seem to stall.
struct AlongPiece {
  bool by_x = true;
  double sign = 1.0;
  AlongPiece(const Point& a, const Point& b) {
    const double dx = b.x - a.x, dy = b.y - a.y;
    by_x = std::fabs(dx) >= std::fabs(dy);
    sign = (by_x ? dx : dy) >= 0.0 ? 1.0 : -1.0;
  }
  double operator()(const Point& q) const { return sign * (by_x ? q.x : q.y); }
};

// Does the closed segment ab meet the open triangle (t0, t1, t2), counter-clockwise? Exact: they are
// apart iff a line separates them weakly (the separating-axis theorem), and for a segment and a
// triangle the only candidates are the triangle's three edge lines and the segment's own line.
bool segment_meets_open_triangle(const Point& a, const Point& b, const Point& t0, const Point& t1, const Point& t2) {
  const std::array<const Point*, 3> t{&t0, &t1, &t2};
  for (unsigned k = 0; k < 3; ++k) {
    const Point& u = *t[k];
    const Point& v = *t[(k + 1) % 3];
    if (orient2d(u, v, a) <= 0 && orient2d(u, v, b) <= 0) return false;  // both outside edge uv
  }
  const int s0 = orient2d(a, b, t0), s1 = orient2d(a, b, t1), s2 = orient2d(a, b, t2);
  return !((s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0));
}

// Which domain the mesh is checked against: chosen by area (the carved domain, or the convex hull
// minus the holes when only that one's area agrees), or one of the two.
enum class Domain { kByArea, kCarved, kHull };

class Checker {
 public:
  Checker(const Pslg& input, const std::vector<Point>& points,
          const std::vector<std::array<std::uint32_t, 3>>& triangles,
          const std::vector<Segment>& subsegments, const CheckOptions& options, Domain domain)
      : input_(input), p_(points), tri_(triangles), subsegments_(subsegments), options_(options), domain_(domain) {}

  CheckResult run() {
    check_vertex_range();
    check_triangles();
    build_edges();
    index_vertices();
    choose_domain();
    check_domain_vertices();
    build_guides();
    walk_domain_chains();
    check_mesh_boundary();
    check_subsegments();
    check_input_segments();
    check_turning();
    if (options_.delaunay || options_.conforming_delaunay) check_delaunay();
    if (options_.min_angle_deg > 0.0) check_min_angle();
    return std::move(result_);
  }

 private:
  void violation(std::string message) {
    ++result_.violations;
    if (result_.messages.size() < options_.max_messages) result_.messages.push_back(std::move(message));
  }
  static std::string tri_name(std::size_t t) { return "triangle " + std::to_string(t + 1); }
  std::string vertex_name(std::uint32_t v) const {
    return "vertex " + std::to_string(v + 1) + " " + point_text(p_[v]);
  }
  std::string edge_name(std::uint32_t u, std::uint32_t v) const {
    return "edge " + std::to_string(u + 1) + "-" + std::to_string(v + 1) + " " + point_text(p_[u]) +
           "-" + point_text(p_[v]);
  }

  // Every vertex is inside the supported coordinate range (0 or a magnitude in [1e-50, 1e50]),
  // where the predicates are exact and mwst reads files back.
  void check_vertex_range() {
    for (std::uint32_t v = 0; v < p_.size(); ++v) {
      if (!in_supported_range(p_[v])) {
        violation(vertex_name(v) + " is outside the supported coordinate range (0 or a magnitude between "
                  "1e-50 and 1e50)");
      }
    }
  }

  // Orientation of every triangle (exact); triangles naming missing or repeated vertices are
  // reported and left out of everything else.
  void check_triangles() {
    const std::size_t n = p_.size();
    valid_.assign(tri_.size(), 0);
    for (std::size_t t = 0; t < tri_.size(); ++t) {
      const auto& T = tri_[t];
      if (T[0] >= n || T[1] >= n || T[2] >= n) {
        violation(tri_name(t) + " names a vertex that does not exist");
        continue;
      }
      if (T[0] == T[1] || T[1] == T[2] || T[2] == T[0]) {
        violation(tri_name(t) + " repeats a vertex");
        continue;
      }
      valid_[t] = 1;
      const int o = orient2d(p_[T[0]], p_[T[1]], p_[T[2]]);
      if (o < 0) violation(tri_name(t) + " is clockwise");
      if (o == 0) violation(tri_name(t) + " is degenerate (its corners are collinear)");
      result_.area += signed_area(p_[T[0]], p_[T[1]], p_[T[2]]);
    }
  }

  // Directed edges → the triangle holding them and its apex (the first triangle listing an edge;
  // a later one with the same orientation overlaps it); undirected adjacency lists.
  void build_edges() {
    const std::size_t n = p_.size();
    used_.assign(n, 0);
    for (std::size_t t = 0; t < tri_.size(); ++t) {
      if (!valid_[t]) continue;
      for (const std::uint32_t u : tri_[t]) used_[u] = 1;
    }
    for (const detail::DirectedEdges::Duplicate& d : edges_.build(n, tri_, valid_)) {
      const auto& T = tri_[d.slot / 3];
      violation(edge_name(T[d.slot % 3], T[(d.slot % 3 + 1) % 3]) + " is in " + tri_name(d.first_slot / 3) + " and " +
                tri_name(d.slot / 3) + " with the same orientation (they overlap)");
    }
    edge_kind_.assign(edges_.size(), 0);
    // Compressed adjacency (with repeats: an interior edge appears from both sides).
    adj_start_.assign(n + 1, 0);
    for (std::uint32_t u = 0; u < n; ++u) {
      for (std::uint32_t e = edges_.begin(u); e < edges_.end(u); ++e) {
        ++adj_start_[u + 1];
        ++adj_start_[edges_.destination(e) + 1];
      }
    }
    for (std::size_t v = 0; v < n; ++v) adj_start_[v + 1] += adj_start_[v];
    adj_.resize(adj_start_[n]);
    std::vector<std::uint32_t> fill(adj_start_.begin(), adj_start_.end() - 1);
    for (std::uint32_t u = 0; u < n; ++u) {
      for (std::uint32_t e = edges_.begin(u); e < edges_.end(u); ++e) {
        const std::uint32_t v = edges_.destination(e);
        adj_[fill[u]++] = v;
        adj_[fill[v]++] = u;
      }
    }
  }

  // Used mesh vertices by their exact coordinates; two at the same point is a violation.
  void index_vertices() {
    by_point_ = detail::PointTable(p_.size());
    for (std::uint32_t v = 0; v < p_.size(); ++v) {
      if (!used_[v]) continue;
      const std::uint32_t first = by_point_.insert(p_[v], v);
      if (first != kNone) {
        violation("vertices " + std::to_string(first + 1) + " and " + std::to_string(v + 1) +
                  " are at the same point " + point_text(p_[v]));
      }
    }
  }

  static bool areas_agree(double a, double b) {
    return std::fabs(a - b) <= kAreaTolerance * std::max(std::fabs(a), std::fabs(b));
  }

  // The reference domain: carved by the segments, or the convex hull minus the holes when the
  // mesh covers that instead (the two differ only where the segments leave concavities).
  void choose_domain() {
    if (domain_ == Domain::kHull) {
      ConstrainOptions hull;
      hull.convex_hull = true;
      reference_ = constrained_delaunay(input_, hull);
      result_.domain_area = reference_.domain_area();
      result_.convex_hull = true;
    } else {
      reference_ = constrained_delaunay(input_, ConstrainOptions{});
      result_.domain_area = reference_.domain_area();
    }
    if (domain_ == Domain::kByArea && !areas_agree(result_.area, result_.domain_area) && !input_.segments.empty()) {
      ConstrainOptions hull;
      hull.convex_hull = true;
      Mesh whole = constrained_delaunay(input_, hull);
      const double whole_area = whole.domain_area();
      if (areas_agree(result_.area, whole_area)) {
        reference_ = std::move(whole);
        result_.domain_area = whole_area;
        result_.convex_hull = true;
      }
    }
    if (input_.segments.empty()) result_.convex_hull = true;
    if (!areas_agree(result_.area, result_.domain_area)) {
      violation("the triangles cover an area of " + number(result_.area) + ", the domain " +
                number(result_.domain_area));
    }
  }

  std::string reference_name(VertexId r) const {
    const Point& q = reference_.points[r];
    if (r < reference_.input_vertex_count) {
      return "input vertex " + std::to_string(static_cast<long long>(r) + input_.first_index) + " " + point_text(q);
    }
    return "crossing point " + point_text(q);
  }

  // The mesh vertex at a reference vertex's exact position, or kNone.
  std::uint32_t mesh_vertex_at(VertexId r) const {
    return by_point_.find(reference_.points[r]);
  }

  // Every vertex of the domain (input points, crossing points) is a mesh vertex.
  void check_domain_vertices() {
    std::vector<char> in_domain(reference_.points.size(), 0);
    for (TriangleId t = 0; t < reference_.triangles.size(); ++t) {
      if (!reference_.in_domain(t)) continue;
      for (const VertexId v : reference_.triangles[t].v) in_domain[v] = 1;
    }
    for (VertexId r = 0; r < in_domain.size(); ++r) {
      if (in_domain[r] && mesh_vertex_at(r) == kNone) {
        violation(reference_name(r) + " is not a vertex of the mesh");
      }
    }
  }

  // True if mesh vertex w lies on the line through a and b, exactly or within the rounding of
  // constructed points.
  bool near_line(const Point& a, const Point& b, const Point& w) const {
    if (orient2d(a, b, w) == 0) return true;
    const double scale = std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(b.x), std::fabs(b.y)});
    const double dx = b.x - a.x, dy = b.y - a.y;
    const double cross = std::fabs(dx * (w.y - a.y) - dy * (w.x - a.x));
    return cross <= kOnLineTolerance * scale * std::hypot(dx, dy);
  }

  // u and v are adjacent: the chains walk along mesh edges.
  void mark_chain_edge(std::uint32_t u, std::uint32_t v, std::uint8_t kind) {
    edge_kind_[edges_.undirected(u, v)] |= kind;
    if (kind & kOnDomainBoundary) boundary_chain_.push_back({u, v});
  }

  // Guide edges: the mesh's own boundary edges and the subsegments its .poly lists (those that are
  // mesh edges). On a correct mesh they run along the domain's boundary and segments, and every
  // guide vertex that is not a vertex of the domain (an input point or crossing: a junction) is a
  // rounded Steiner point on one piece with exactly two guide edges. Following them tells apart
  // pieces that rounding cannot: two sides of a wedge far thinner than the coordinates' rounding
  // (a triangle 27 wide and 5.6e14 long) lie within each other's tolerance near the apex.
  void build_guides() {
    const std::size_t n = p_.size();
    junction_.assign(n, 0);
    for (VertexId r = 0; r < reference_.points.size(); ++r) {
      const std::uint32_t v = mesh_vertex_at(r);
      if (v != kNone) junction_[v] = 1;
    }
    std::vector<std::uint64_t> edges;  // undirected, sorted, each once
    for (std::uint32_t u = 0; u < n; ++u) {
      for (std::uint32_t e = edges_.begin(u); e < edges_.end(u); ++e) {
        const std::uint32_t v = edges_.destination(e);
        if (!edges_.contains(v, u)) edges.push_back(undirected_key(u, v));
      }
    }
    for (const Segment& s : subsegments_) {
      if (s.a >= n || s.b >= n || s.a == s.b) continue;
      if (edges_.undirected(s.a, s.b) != kNone) edges.push_back(undirected_key(s.a, s.b));
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    guide_start_.assign(n + 1, 0);
    for (const std::uint64_t key : edges) {
      ++guide_start_[(key >> 32) + 1];
      ++guide_start_[static_cast<std::uint32_t>(key) + 1];
    }
    for (std::size_t v = 0; v < n; ++v) guide_start_[v + 1] += guide_start_[v];
    guide_.resize(guide_start_[n]);
    std::vector<std::uint32_t> fill(guide_start_.begin(), guide_start_.end() - 1);
    for (const std::uint64_t key : edges) {
      const auto u = static_cast<std::uint32_t>(key >> 32), v = static_cast<std::uint32_t>(key);
      guide_[fill[u]++] = v;
      guide_[fill[v]++] = u;
    }
  }

  // The piece from reference vertex ru to rv as a path of guide edges: from u, a guide edge, then
  // through non-junction vertices with two guide edges each, every one within rounding of the line
  // and further along it than the last, to v. Marks the path's edges with `kind` and returns true
  // if there is one; false (nothing reported) if not, and walk_chain() decides.
  bool guided_chain(VertexId ru, VertexId rv, std::uint8_t kind) {
    const std::uint32_t u = mesh_vertex_at(ru), v = mesh_vertex_at(rv);
    if (u == kNone || v == kNone) return false;
    const Point& a = p_[u];
    const Point& b = p_[v];
    const AlongPiece along(a, b);
    const double s_end = along(b);
    for (std::uint32_t i = guide_start_[u]; i < guide_start_[u + 1]; ++i) {
      path_.assign(1, u);
      std::uint32_t previous = u, cur = guide_[i];
      double s_cur = along(a);
      while (cur != v) {
        if (junction_[cur] || guide_start_[cur + 1] - guide_start_[cur] != 2) break;
        const Point& q = p_[cur];
        const double s = along(q);
        if (!(s > s_cur && s < s_end) || !near_line(a, b, q)) break;  // s rises: the path cannot loop
        path_.push_back(cur);
        s_cur = s;
        const std::uint32_t first = guide_[guide_start_[cur]];
        const std::uint32_t next = first == previous ? guide_[guide_start_[cur] + 1] : first;
        previous = cur;
        cur = next;
      }
      if (cur != v) continue;
      path_.push_back(v);
      for (std::size_t k = 0; k + 1 < path_.size(); ++k) mark_chain_edge(path_[k], path_[k + 1], kind);
      return true;
    }
    return false;
  }

  // Follows mesh edges from u to v along the straight piece between them, marking each edge with
  // `kind`. Returns false (after reporting) if the mesh has no such chain.
  bool walk_chain(VertexId ru, VertexId rv, std::uint8_t kind) {
    const std::uint32_t u = mesh_vertex_at(ru), v = mesh_vertex_at(rv);
    if (u == kNone || v == kNone) return false;  // already reported as a missing vertex
    const Point& a = p_[u];
    const Point& b = p_[v];
    const AlongPiece along(a, b);
    const double s_end = along(b);
    std::uint32_t cur = u;
    double s_cur = along(a);
    while (cur != v) {
      std::uint32_t next = kNone;
      double s_next = s_end;
      for (std::uint32_t i = adj_start_[cur]; i < adj_start_[cur + 1]; ++i) {
        const std::uint32_t w = adj_[i];
        if (w == v) {
          next = v;
          break;
        }
        const Point& q = p_[w];
        const double s = along(q);
        if (s > s_cur && s < s_next && near_line(a, b, q)) {
          next = w;
          s_next = s;
        }
      }
      if (next == kNone) {
        const std::string what = (kind & kOnSegment) ? "segment" : "domain boundary edge";
        violation("the " + what + " from " + reference_name(ru) + " to " + reference_name(rv) +
                  " is not a chain of mesh edges (it stops at " + vertex_name(cur) + ")");
        return false;
      }
      mark_chain_edge(cur, next, kind);
      s_cur = next == v ? s_end : s_next;
      cur = next;
    }
    return true;
  }

  // Each boundary edge and each segment edge of the reference domain, as a chain of mesh edges.
  void walk_domain_chains() {
    const Mesh& r = reference_;
    for (TriangleId t = 0; t < r.triangles.size(); ++t) {
      if (!r.in_domain(t)) continue;
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        const TriangleId other = triangle_of(r.sym(h));
        const bool boundary = !r.in_domain(other);
        const bool segment = r.is_segment(h);
        if (!boundary && !segment) continue;
        if (!boundary && other < t) continue;  // an interior segment edge, seen from both sides
        std::uint8_t kind = 0;
        if (boundary) kind |= kOnDomainBoundary;
        if (segment) kind |= kOnSegment;
        // The domain lies left of org → dest of a domain triangle's edge.
        if (!guided_chain(r.org(h), r.dest(h), kind)) walk_chain(r.org(h), r.dest(h), kind);
      }
    }
  }

  // The mesh boundary is exactly the domain boundary, with the mesh on the domain side.
  void check_mesh_boundary() {
    for (const auto& [u, v] : boundary_chain_) {
      const bool forward = edges_.contains(u, v);
      const bool backward = edges_.contains(v, u);
      if (forward && backward) {
        violation(edge_name(u, v) + " lies on the domain boundary but has triangles on both sides");
      } else if (!forward) {
        violation(edge_name(u, v) + " lies on the domain boundary but its triangle is outside the domain");
      }
    }
    // An edge with one orientation is on the mesh boundary (it stands for itself as undirected).
    on_boundary_.assign(p_.size(), 0);
    for (std::uint32_t u = 0; u < p_.size(); ++u) {
      for (std::uint32_t e = edges_.begin(u); e < edges_.end(u); ++e) {
        const std::uint32_t v = edges_.destination(e);
        if (edges_.contains(v, u)) continue;
        on_boundary_[u] = on_boundary_[v] = 1;
        if ((edge_kind_[e] & kOnDomainBoundary) == 0) {
          violation(edge_name(u, v) + " of " + tri_name(edges_.triangle(e)) +
                    " is on the mesh boundary but not on the domain boundary (a gap in the mesh)");
        }
      }
    }
  }

  // PREFIX.poly: its subsegments are mesh edges on input segments (or, for a convex hull domain,
  // on the hull), and every mesh edge on an input segment is listed.
  void check_subsegments() {
    if (subsegments_.empty()) return;
    for (std::size_t i = 0; i < subsegments_.size(); ++i) {
      const Segment& s = subsegments_[i];
      const std::string name = "subsegment " + std::to_string(i + 1) + " of the mesh's .poly";
      if (s.a >= p_.size() || s.b >= p_.size()) {
        violation(name + " names a vertex that does not exist");
        continue;
      }
      const std::uint32_t e = edges_.undirected(s.a, s.b);
      if (e == kNone) {
        violation(name + " (" + edge_name(s.a, s.b) + ") is not a mesh edge");
        continue;
      }
      edge_kind_[e] |= kListed;
      if ((edge_kind_[e] & kOnChain) == 0) {
        violation(name + " (" + edge_name(s.a, s.b) + ") lies on no input segment");
      }
    }
    for (std::uint32_t u = 0; u < p_.size(); ++u) {
      for (std::uint32_t e = edges_.begin(u); e < edges_.end(u); ++e) {
        if ((edge_kind_[e] & kOnSegment) == 0 || (edge_kind_[e] & kListed) != 0) continue;
        const std::uint32_t v = edges_.destination(e);  // e stands for {u, v}: only it has kinds
        violation(edge_name(std::min(u, v), std::max(u, v)) +
                  " lies on an input segment but the mesh's .poly does not list it");
      }
    }
  }

  // Every input segment, checked against the input itself (not against the reference domain,
  // whose crossing points come from the same code as the mesh's): from the mesh vertex at one end
  // to the one at the other, a chain of mesh edges whose vertices never step back along the
  // segment by more than kSegmentUlps ulps of its largest coordinate magnitude M (the CDT's
  // snapping of crossings, SegmentLine::behind_beyond_tolerance) and lie within kSegmentUlps ulps
  // of M of its line (the distance from the exactly computed orient2d). A crossing vertex or a
  // Steiner point moved further than rounding is refused. Where the segment leaves the mesh (a
  // segment in a hole, or bounding a hole) the part beyond is walked from the other end; a segment
  // is reported only where it runs into a triangle's interior, or when its chain ends short of it.
  void check_input_segments() {
    dead_end_.assign(p_.size(), 0);
    std::vector<std::uint32_t> at_input(input_.points.size(), kNone);
    for (std::size_t i = 0; i < input_.points.size(); ++i) {
      at_input[i] = by_point_.find(input_.points[i]);
    }
    for (std::size_t i = 0; i < input_.segments.size(); ++i) {
      const Segment& s = input_.segments[i];
      if (s.a >= input_.points.size() || s.b >= input_.points.size()) continue;
      const Point& a = input_.points[s.a];
      const Point& b = input_.points[s.b];
      if (a == b) continue;
      const std::uint32_t u = at_input[s.a], v = at_input[s.b];
      if (u == kNone && v == kNone) continue;  // wholly outside the mesh, or reported as missing
      const SegmentLine line(a, b);
      std::uint32_t stop = kNone;
      bool enters = false;
      if (u != kNone) {
        stop = follow_segment(line, u, v, &enters);
        if (stop == kNone) continue;
        if (!enters && v != kNone) {
          // The segment leaves the mesh at `stop`: walk the rest from the far end.
          const SegmentLine back(b, a);
          const std::uint32_t back_stop = follow_segment(back, v, u, &enters);
          if (back_stop == kNone) continue;
          if (enters || line.ahead(p_[stop], p_[back_stop])) stop = back_stop;
        }
      } else {
        const SegmentLine back(b, a);
        stop = follow_segment(back, v, u, &enters);
        if (stop == kNone) continue;
      }
      if (!enters) continue;
      std::string name = "input segment " + std::to_string(static_cast<long long>(i) + input_.first_index);
      if (i < input_.segment_lines.size()) name += " (line " + std::to_string(input_.segment_lines[i]) + ")";
      violation(name + " from " + point_text(a) + " to " + point_text(b) +
                " is not a chain of mesh edges within rounding of it: at " + vertex_name(stop) +
                " it runs into a triangle");
    }
  }

  // The line of an input segment: exact-enough distance and a strictly increasing position.
  struct SegmentLine {
    Point a, b;
    double length;
    double tolerance;  // on the cross and dot products: kSegmentUlps ulps of M, times length
    // Is q strictly further along the segment than r: (q − r)·(b − a) > 0, exactly (expansion
    // arithmetic)? Along the segment, not along its larger coordinate: the CDT resolves crossings
    // at vertices within its rounding tolerance of a segment, on either side of it, so near a long
    // diagonal segment at coarse coordinates (doubles 0.0625 apart near 2.8e14) its chain ran from
    // a vertex 2 units below the line to one 5 units above it and 7 further along, but 1.75 back
    // in y. Exactly, so that vertices an ulp apart (refinement puts clusters of Steiner points
    // within 1e-20 of each other 16 units along a hull edge) are ordered as they lie.
    bool ahead(const Point& q, const Point& r) const { return exact::sign(along(q, r)) > 0; }
    // Is q behind r along the segment by more than the tolerance: (q − r)·(b − a) < −tolerance,
    // i.e. further back than kSegmentUlps ulps of M? The CDT snaps a crossing to an end of the
    // crossed subsegment (or of the piece) up to 256·2^-52 of the larger of the crossing's
    // magnitude and the segments' lengths away, within kSegmentUlps ulps of M. Each crossing lies
    // on a piece of the segment's chain, from a vertex v to a vertex w further along (the piece
    // still to insert, or a subsegment another segment crosses): a convex combination of v and w,
    // not behind v along the segment. The vertex it snaps to is behind v by at most the snap
    // distance. Where doubles are as coarse as the input's features, two crossings a few units
    // apart snap to vertices in the reverse order (dt of 7 fuzzed points near -7.7e15, doubles 1
    // apart: crossings 5.5 apart along a segment resolved at two vertices 8.5 to 16.6 units from
    // them, the second of which is 0.31 behind the first).
    bool behind_beyond_tolerance(const Point& q, const Point& r) const {
      exact::Expansion<1> slack;
      slack.push(tolerance);
      return exact::sign(along(q, r) + slack) < 0;
    }
    // (q − r)·(b − a), exactly (expansion arithmetic).
    exact::Expansion<16> along(const Point& q, const Point& r) const {
      const exact::Expansion<8> along_x = exact::difference(q.x, r.x) * exact::difference(b.x, a.x);
      const exact::Expansion<8> along_y = exact::difference(q.y, r.y) * exact::difference(b.y, a.y);
      return along_x + along_y;
    }
    SegmentLine(const Point& from, const Point& to) : a(from), b(to), length(distance(from, to)) {
      const double magnitude = std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(b.x), std::fabs(b.y)});
      const double ulp = std::nextafter(magnitude, std::numeric_limits<double>::infinity()) - magnitude;
      tolerance = kSegmentUlps * ulp * length;
    }
    bool near(const Point& q) const {
      // orient2d(a, b, q) / |ab| is the distance of q from the line (exact sign, rounded value).
      return std::fabs(detail::orient2d_value(a, b, q)) <= tolerance;
    }
  };

  // Depth-first search from mesh vertex `from` to `to` (kNone: none) along mesh edges whose far
  // vertices are near the line and not behind the near vertex along it by more than the tolerance
  // (each vertex is expanded once: a vertex that led nowhere once leads nowhere again, dead_end_).
  // A step across the line, to a vertex level with the last along it or a little behind it, is
  // part of a chain: where doubles are as coarse as the input's features, the CDT resolves a
  // crossing at an end of the crossed subsegment within its rounding, and the chain then runs
  // sideways (dt of 8 fuzzed points near -8.6e15, doubles 1 apart: a vertical segment's chain
  // stepped from its end at x = -67 to a vertex at x = -66 at the same height, then down) or
  // back (behind_beyond_tolerance). Returns kNone when the chain reaches `to`,
  // otherwise where it stopped: the vertex furthest along of those reached from which the segment
  // runs out of the mesh, or, if it runs into the interior of a mesh triangle from every one of
  // them, the furthest one reached, with *enters set.
  std::uint32_t follow_segment(const SegmentLine& line, std::uint32_t from, std::uint32_t to, bool* enters) {
    std::vector<std::uint32_t>& stack = path_;
    stack.assign(1, from);
    std::vector<std::uint32_t> touched;
    std::uint32_t furthest = from;
    bool found = false;
    while (!stack.empty() && !found) {
      const std::uint32_t cur = stack.back();
      stack.pop_back();
      if (line.ahead(p_[cur], p_[furthest])) furthest = cur;
      for (std::uint32_t k = adj_start_[cur]; k < adj_start_[cur + 1]; ++k) {
        const std::uint32_t w = adj_[k];
        if (w == to) {
          found = true;
          break;
        }
        if (dead_end_[w]) continue;
        if (line.behind_beyond_tolerance(p_[w], p_[cur]) || !line.ahead(line.b, p_[w]) || !line.near(p_[w])) {
          continue;
        }
        dead_end_[w] = 1;  // visited: reached once, never expanded again
        touched.push_back(w);
        stack.push_back(w);
      }
    }
    for (const std::uint32_t w : touched) dead_end_[w] = 0;
    if (found) return kNone;
    // The chain stops. Where the segment leaves the mesh from a vertex the walk reached (a hole,
    // the outside), the walk from the other end checks the rest: the furthest such vertex is the
    // stop. Only if the segment enters a triangle from every vertex reached is it reported, from
    // the furthest one. (Near the line means within the tolerance, which at coordinates where
    // doubles are coarse spans several vertices: the CDT, which resolves crossings at ends within
    // its own rounding tolerance, chained a segment of a fuzzed input near -2.8e14 through a vertex
    // 1.4 units off it, to the mesh's boundary and out, while the walk also reached a vertex 3.15
    // units off on the other side, further along, from which the segment enters a triangle.)
    std::uint32_t leaving = kNone;
    touched.push_back(from);
    for (const std::uint32_t c : touched) {
      if (!segment_enters_from(line, c) && (leaving == kNone || line.ahead(p_[c], p_[leaving]))) {
        leaving = c;
      }
    }
    *enters = leaving == kNone;
    return *enters ? furthest : leaving;
  }

  // Does the segment, leaving mesh vertex c towards b, enter one of c's triangles? The direction
  // from c (within the tolerance of the line, not on it) must enter the triangle, and the segment
  // itself must meet the triangle's interior: a vertex near the line but off it (a vertex of
  // another segment that the CDT resolved a crossing at, within rounding) can have a sliver on the
  // far side of the line that the direction towards b enters and the segment misses (dt of a
  // fuzzed input near -7e14, where the spacing of doubles is 0.125: an input vertex 2.1 units off
  // the segment, a sliver 0.35 wide).
  bool segment_enters_from(const SegmentLine& line, std::uint32_t c) const {
    const Point& pc = p_[c];
    for (std::uint32_t k = adj_start_[c]; k < adj_start_[c + 1]; ++k) {
      const std::uint32_t w = adj_[k];
      const std::uint32_t e = edges_.find(c, w);
      if (e == kNone) continue;
      const Point& q = p_[edges_.apex(e)];
      if (orient2d(pc, p_[w], line.b) >= 0 && orient2d(pc, q, line.b) <= 0 &&
          segment_meets_open_triangle(line.a, line.b, pc, p_[w], q)) {
        return true;
      }
    }
    return false;
  }

  // The triangles around each vertex turn 360° inside the mesh and at most 360° on its boundary.
  void check_turning() {
    std::vector<double> turn(p_.size(), 0.0);
    for (std::size_t t = 0; t < tri_.size(); ++t) {
      if (!valid_[t]) continue;
      const auto& T = tri_[t];
      for (unsigned k = 0; k < 3; ++k) {
        turn[T[k]] += angle_deg(p_[T[k]], p_[T[(k + 1) % 3]], p_[T[(k + 2) % 3]]);
      }
    }
    for (std::uint32_t v = 0; v < p_.size(); ++v) {
      if (!used_[v]) continue;
      if (on_boundary_[v] ? turn[v] > 360.0 + kTurnTolerance : std::fabs(turn[v] - 360.0) > kTurnTolerance) {
        violation("the triangles around " + vertex_name(v) + " turn " + number(turn[v]) +
                  " degrees" + (on_boundary_[v] ? " (more than 360)" : " (not 360)"));
      }
    }
  }

  // Constrained Delaunay: across every interior edge not on an input segment (nor listed as a
  // subsegment) — conforming Delaunay: across every interior edge —, the far apex is not strictly
  // inside the circumcircle (exact incircle).
  void check_delaunay() {
    for (std::uint32_t u = 0; u < p_.size(); ++u) {
      for (std::uint32_t e = edges_.begin(u); e < edges_.end(u); ++e) {
        const std::uint32_t v = edges_.destination(e);
        if (u > v) continue;
        const std::uint32_t other = edges_.find(v, u);
        if (other == kNone) continue;
        if (!options_.conforming_delaunay && edge_kind_[e] != 0) continue;  // on a chain, or listed
        if (incircle(p_[u], p_[v], p_[edges_.apex(e)], p_[edges_.apex(other)]) > 0) {
          violation(edge_name(u, v) + " is not Delaunay: " + vertex_name(edges_.apex(other)) +
                    " lies inside the circumcircle of " + tri_name(edges_.triangle(e)));
        }
      }
    }
  }

  void check_min_angle() {
    for (std::size_t t = 0; t < tri_.size(); ++t) {
      if (!valid_[t]) continue;
      const auto& T = tri_[t];
      double smallest = 180.0;
      for (unsigned k = 0; k < 3; ++k) {
        smallest = std::min(smallest, angle_deg(p_[T[k]], p_[T[(k + 1) % 3]], p_[T[(k + 2) % 3]]));
      }
      if (smallest < options_.min_angle_deg - kAngleTolerance) {
        violation(tri_name(t) + " has an angle of " + number(smallest) + " degrees, below " +
                  number(options_.min_angle_deg));
      }
    }
  }

  const Pslg& input_;
  const std::vector<Point>& p_;
  const std::vector<std::array<std::uint32_t, 3>>& tri_;
  const std::vector<Segment>& subsegments_;
  const CheckOptions& options_;
  Domain domain_;
  CheckResult result_;

  std::vector<char> valid_;
  std::vector<char> used_;
  std::vector<char> on_boundary_;
  detail::DirectedEdges edges_;  // directed edge → the triangle holding it and its apex
  std::vector<std::uint32_t> adj_start_, adj_;
  detail::PointTable by_point_;  // used mesh vertices by their exact coordinates
  Mesh reference_;
  std::vector<char> junction_;  // mesh vertex at a vertex of the domain (input point, crossing)
  std::vector<std::uint32_t> guide_start_, guide_;  // guide edges (build_guides), both directions
  std::vector<std::uint32_t> path_;                 // scratch for guided_chain, follow_segment
  std::vector<char> dead_end_;                      // scratch for follow_segment
  // Per entry of edges_ that stands for an undirected edge (DirectedEdges::undirected): the kinds
  // of the domain's chains it lies on, and kListed if the mesh's .poly lists it; 0 on the others.
  std::vector<std::uint8_t> edge_kind_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> boundary_chain_;  // directed, domain on the left
};

}  // namespace

CheckResult check_triangulation(const Pslg& input, const std::vector<Point>& points,
                                const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                const std::vector<Segment>& subsegments, const CheckOptions& options) {
  CheckResult by_area = Checker(input, points, triangles, subsegments, options, Domain::kByArea).run();
  if (by_area.ok() || input.segments.empty()) return by_area;
  // The carved domain and the convex hull minus the holes can differ by a sliver below the area
  // tolerance (a notch of a segment chain within rounding of the hull, or a long thin hull far
  // from the origin): their areas then both agree with the mesh's, and the area cannot tell which
  // one it covers. A mesh that triangulates the other one exactly passes.
  const Domain other = by_area.convex_hull ? Domain::kCarved : Domain::kHull;
  CheckResult second = Checker(input, points, triangles, subsegments, options, other).run();
  return second.ok() ? second : by_area;
}

}  // namespace mwst
