// src/algorithms/refine/segments.cpp — subsegments (refiner.hpp): splitting the encroached ones
// (concentric shells), at double precision next to the convex hull, and the Lawson flips and hull
// repairs a rounded split point needs.
#include "algorithms/refine/refiner.hpp"

#include <algorithm>
#include <limits>

#include "mwst/error.hpp"

namespace mwst::refinement {

namespace {


// How many shifted split parameters are tried on each side when a rounded split point is
// rejected (thin outside triangles along a convex-hull boundary need a point inside them).
constexpr int kSplitShifts = 24;

// A subsegment is not split where a domain triangle beside it is thinner than kThinSide times the
// coordinates' magnitude (its apex that close to the subsegment's line): a rounded split point lies
// up to half an ulp (1.1e-16 of the magnitude) off the line, which changes that triangle's area by
// the same fraction of its height — over 1e-9 of it only when thinner than this — and an
// independent check cannot tell which long side of such a sliver the point is on. (Found by
// fuzzing: the hull of three points, two of them 50 ulps apart, refined with --convex-hull.)
constexpr double kThinSide = 1e-7;
// ... unless the domain is so much larger than the subsegment that no rounding of its split point
// can matter to its area: a point off the line by an ulp (2.2e-16 of the magnitude) moves the
// boundary by at most that times the subsegment's length, and while that is below kThinAreaShare
// of the domain's area the split goes ahead (the exact orientation tests of split_point_valid keep
// the mesh valid). The rule is for slivers that are the domain, not slivers along a large hull:
// 160k points on a spiral have hull triangles with angles of 1e-8 radians along convex arcs, whose
// encroached hull edges were left unsplit (239 triangles outside a 20° bound).
constexpr double kThinAreaShare = 1e-14;

}  // namespace

// ---- pending subsegments begin here ---------------------------------------------------------------

// The pending subsegment p where it is now (its hint, or a walk to u and a turn around it); kNone
// if it is no longer a subsegment.
Handle Refiner::find_subsegment(const Pending& p) {
  const Handle h = p.hint;
  if ((h >> 2) < m_.triangles.size() && !m_.is_dead(h >> 2)) {
    const VertexId a = m_.org(h), b = m_.dest(h);
    if (((a == p.u && b == p.w) || (a == p.w && b == p.u)) && m_.is_segment(h)) return h;
  }
  // The hint went stale (a neighbouring flip moved the edge to another slot): find u again by a
  // short walk from the old place, then turn around u.
  Handle start = (h >> 2) < m_.triangles.size() && !m_.is_dead(h >> 2) ? h : kNone;
  const Location loc = m_.locate(m_.points[p.u], start);
  if (loc.kind != Location::Kind::kOnVertex) return kNone;
  const Handle g0 = loc.handle;
  Handle g = g0;
  std::size_t guard = 0;
  do {
    if (m_.dest(g) == p.w) return m_.is_segment(g) ? g : kNone;
    g = m_.onext(g);
    if (++guard > m_.triangles.size()) break;
  } while (g != g0);
  return kNone;
}

// Splits the pending subsegments (those that may be split), until none is left or a budget stops
// the refinement; true if any was split.
bool Refiner::split_all_pending() {
  bool any = false;
  while (!pending_.empty() && !stop_) {
    const Pending p = pending_.back();
    pending_.pop_back();
    if (!unsplittable_.empty() && unsplittable_.count(undirected_key(p.u, p.w))) continue;
    const Handle h = find_subsegment(p);
    if (h == kNone || !may_split(h)) continue;
    if (budget_reached()) {
      stop_ = true;
      stop_reason_ = StopReason{StopKind::kSteinerBudget, 0, {}};
      break;
    }
    // Segment splits can cascade for long (points on a circle: every hull edge encroached).
    if ((++segment_splits_timed_ & 15) == 0 && out_of_time()) break;
    if (split_subsegment(h)) any = true;
  }
  return any;
}

// ---- splitting one subsegment begins here ---------------------------------------------------------

// True if org(h) is an endpoint of another subsegment making an angle below 90° with h.
bool Refiner::shares_acute_segment(Handle h) const {
  const VertexId u = m_.org(h), w = m_.dest(h);
  const Point& pu = m_.points[u];
  const double dx = m_.points[w].x - pu.x, dy = m_.points[w].y - pu.y;
  Handle g = h;
  std::size_t guard = 0;
  do {
    g = m_.onext(g);
    const VertexId x = m_.dest(g);
    if (x != w && x != kInfinite && m_.is_segment(g)) {
      const double ex = m_.points[x].x - pu.x, ey = m_.points[x].y - pu.y;
      if (dx * ex + dy * ey > 0.0) return true;
    }
    if (++guard > m_.triangles.size()) break;
  } while (g != h);
  return false;
}

// Two input segments from a vertex c at an angle below 60° (below which a vertex on one can
// encroach a subsegment of the other): subsegment h of one is encroached by v, the apex of a domain
// triangle beside h and a split vertex of the other, and the usual split point (shells or midpoint)
// would leave v encroaching one half of h and would itself encroach a subsegment of v's segment
// at v. That is the loop concentric shells exist to prevent (Ruppert 1995; Shewchuk 2002; Triangle:
// "each vertex added to split one segment will encroach upon the other segment, which must then be
// split with a vertex that will encroach upon the first segment"), and shells do not prevent it once
// a segment with both ends at acute angles was split at its midpoint (the rule that comment goes on
// to give), off the shells of its neighbour. So h is split at v's distance r from c instead. On a ray from c, the
// diametral disk of a subsegment with both ends within distance r of c lies in the disk of radius r
// about c, touching its circle only at the subsegment's outer end; that of a subsegment with both
// ends at least r from c lies outside the open disk. A vertex at distance r from c thus encroaches
// no subsegment of a segment from c that has a vertex at distance r too (the lens lies inside the
// disk): after this split v encroaches neither half of h, and the new vertex encroaches nothing on
// v's segment. Only split vertices are followed: an input vertex is a feature, and the splits that
// close in on it stop at its local feature size (Ruppert's bound); a split vertex is not, and the
// mutual splits run down to the width of the angle all along both segments. The last spike of
// `mwst generate fan 3000` (two sides of lengths 1 and 0.999 at 1.7e-7 radians, midpoints 5e-4
// apart) took 760,453 segment splits that way, subsegments of 1e-6. Returns the split as from +
// t (to − from), false if the usual point stays.
bool Refiner::shell_through_encroacher(Handle h, double length, const Point& usual, Point& from, Point& to,
                                       double& t) const {
  if (!(length > 0.0)) return false;
  const VertexId a = m_.org(h), b = m_.dest(h);
  std::pair<VertexId, VertexId> own = original_segment(a);
  if (own.first == kNone) own = original_segment(b);
  if (own.first == kNone) own = {std::min(a, b), std::max(a, b)};
  const Point& pa = m_.points[a];
  const Point& pb = m_.points[b];
  for (const Handle side : {h, m_.sym(h)}) {
    if (!m_.in_domain(side >> 2)) continue;
    const VertexId v = m_.apex(side);
    const Point& pv = m_.points[v];
    // The usual split point ends v's encroachment: it stays (Ruppert's and Shewchuk's rules).
    if (!encroaches(pv, pa, pb) || (!encroaches(pv, pa, usual) && !encroaches(pv, usual, pb))) continue;
    for (const VertexId c : {own.first, own.second}) {
      const VertexId d = c == own.first ? own.second : own.first;
      if (v == c || v == d) continue;
      const VertexId e = split_segment_end(v, c);
      if (e == kNone || e == d) continue;
      const Point& pc = m_.points[c];
      const double ux = m_.points[d].x - pc.x, uy = m_.points[d].y - pc.y;
      const double wx = m_.points[e].x - pc.x, wy = m_.points[e].y - pc.y;
      const double dot = ux * wx + uy * wy;
      if (!(dot > 0.0 && dot * dot > 0.25 * (ux * ux + uy * uy) * (wx * wx + wy * wy))) continue;
      const double r = distance(pc, pv), ra = distance(pc, pa), rb = distance(pc, pb);
      const bool a_inner = ra <= rb;
      const double s = (r - (a_inner ? ra : rb)) / length;
      // Strictly inside h, and not within rounding of an end (where the ordinary rule does).
      if (!(s > 1e-9 && s < 1.0 - 1e-9)) continue;
      // Mutual encroachment starts only if the usual split point encroaches v's segment in turn.
      if (!encroaches_subsegment_at(Mesh::lprev(side), usual)) continue;
      from = a_inner ? pa : pb;
      to = a_inner ? pb : pa;
      t = s;
      return true;
    }
  }
  return false;
}

// Does q encroach a subsegment with an endpoint at org(around) (the diametral lens or circle)?
bool Refiner::encroaches_subsegment_at(Handle around, const Point& q) const {
  const Point& pv = m_.points[m_.org(around)];
  Handle g = around;
  std::size_t guard = 0;
  do {
    const VertexId x = m_.dest(g);
    if (x != kInfinite && m_.is_segment(g) && encroaches(q, pv, m_.points[x])) return true;
    g = m_.onext(g);
    if (++guard > m_.triangles.size()) break;
  } while (g != around);
  return false;
}

// Can subsegment h = a→b (triangle of h in the domain) be split at the rounded point p? It must lie
// strictly between a and b in each coordinate in which they differ, and level with them in one in
// which they agree: then every chain of splits runs monotonically in both coordinates, so it stays
// in order along its segment however coarse the doubles are (near 2.5e15, where they are 0.5
// apart, the rounded midpoint of a subsegment 1.1 long fell level with one end and the chain
// doubled back). And the new triangles on finite sides must be counter-clockwise. (On a ghost side
// anything goes: restore_hull() makes the hull convex again.)
bool Refiner::split_point_valid(Handle h, const Point& p) const {
  const VertexId a = m_.org(h), b = m_.dest(h), c = m_.apex(h);
  const Point& pa = m_.points[a];
  const Point& pb = m_.points[b];
  if (p == pa || p == pb) return false;
  const auto between = [](double q, double from, double to) {
    return from == to ? q == from : (from < to ? from < q && q < to : to < q && q < from);
  };
  // (This also puts p strictly between a and b along the segment.)
  if (!between(p.x, pa.x, pb.x) || !between(p.y, pa.y, pb.y)) return false;
  if (orient2d(pa, p, m_.points[c]) <= 0 || orient2d(p, pb, m_.points[c]) <= 0) return false;
  const VertexId d = m_.apex(m_.sym(h));
  if (d == kInfinite) return true;
  return orient2d(pb, p, m_.points[d]) > 0 && orient2d(p, pa, m_.points[d]) > 0;
}

// Splits subsegment h (seen from a domain side) on a concentric shell or at its midpoint; false if
// it cannot be split (too thin, no valid rounded point, or the conforming splits' guard).
bool Refiner::split_subsegment(Handle h) {
  ++mesh_edits_;  // (the fan run, fan_run.cpp)
  if (!m_.in_domain(h >> 2)) h = m_.sym(h);
  if (!m_.in_domain(h >> 2)) return false;
  const VertexId a = m_.org(h), b = m_.dest(h);
  const Point pa = m_.points[a], pb = m_.points[b];
  if (conforming_ && squared_distance(pa, pb) < conforming_guard2_) {
    // The conforming splits went far below the input's smallest feature: stop (termination guard).
    stop_ = true;
    stop_reason_ = StopReason{StopKind::kBeyondFeatureSize, 0, {}};
    return false;
  }
  const double length = distance(pa, pb);
  Point p;
  if (too_thin_to_split(h, length) || !find_split_point(h, length, p)) {
    unsplittable_.insert(undirected_key(a, b));
    ++stats_.precision_skips;
    return false;
  }
  insert_split_vertex(h, p);
  return true;
}

// Is a domain triangle beside subsegment h thinner than kThinSide (see there)?
bool Refiner::too_thin_to_split(Handle h, double length) const {
  const Point& pa = m_.points[m_.org(h)];
  const Point& pb = m_.points[m_.dest(h)];
  for (const Handle side : {h, m_.sym(h)}) {
    if (!m_.in_domain(side >> 2)) continue;
    const Point& c = m_.points[m_.apex(side)];
    const double magnitude = std::max({std::fabs(pa.x), std::fabs(pa.y), std::fabs(pb.x), std::fabs(pb.y),
                                       std::fabs(c.x), std::fabs(c.y)});
    const double cross = 2.0 * std::fabs(signed_area(pa, pb, c));  // the apex's distance to the line,
    if (cross >= kThinSide * magnitude * length) continue;           // times length
    if (domain_area_ < 0.0) domain_area_ = m_.domain_area();
    if (0x1p-52 * magnitude * length > kThinAreaShare * domain_area_) return true;
  }
  return false;
}

// The split point of subsegment h: the shell through an encroaching vertex on a segment at a small
// angle (shell_through_encroacher), else concentric shells (Ruppert; Shewchuk) — with exactly one
// endpoint shared with another segment at an acute angle, at a power of two P from it with
// 1.5P ≤ L < 3P — else the midpoint; the intended rounded point, then its ulp neighbours, then
// slightly shifted parameters: at double precision the point is almost never exactly on the
// segment, and near-degenerate neighbours or the hull may reject a particular rounding. If none
// fits, the thin outside triangles beyond a hull subsegment are unfolded and the search repeated.
bool Refiner::find_split_point(Handle h, double length, Point& p) {
  const Point pa = m_.points[m_.org(h)], pb = m_.points[m_.dest(h)];
  const bool shared_a = shares_acute_segment(h);
  const bool shared_b = shares_acute_segment(m_.sym(h));
  Point from = pa, to = pb;
  double t = 0.5;
  if (shared_a != shared_b && length > 0.0) {
    if (shared_b) std::swap(from, to);
    const int k = std::ilogb(length / 1.5);
    t = std::ldexp(1.0, k) / length;
  }
  const Point usual{from.x + t * (to.x - from.x), from.y + t * (to.y - from.y)};
  shell_through_encroacher(h, length, usual, from, to, t);
  auto at = [&](double s) {
    if (s == 0.5) return midpoint(from, to);
    return Point{snap_to_range(from.x + s * (to.x - from.x)), snap_to_range(from.y + s * (to.y - from.y))};
  };
  auto search = [&](Point& out) {
    const Point p0 = at(t);
    if (split_point_valid(h, p0)) {
      out = p0;
      return true;
    }
    for (int shift = 0; shift <= 2 * kSplitShifts; ++shift) {
      // shift 0: the ulp neighbours of p0; then parameters t·(1 ± k·2^-12), k = 1..kSplitShifts.
      const double factor = 1.0 + (shift % 2 ? 1.0 : -1.0) * ((shift + 1) / 2) * 0x1p-12;
      const Point base = shift == 0 ? p0 : at(t * factor);
      for (int i = 0; i < 9; ++i) {
        const int dx = i % 3 - 1, dy = i / 3 - 1;
        Point q = base;
        if (dx) q.x = std::nextafter(q.x, dx > 0 ? std::numeric_limits<double>::infinity()
                                                 : -std::numeric_limits<double>::infinity());
        if (dy) q.y = std::nextafter(q.y, dy > 0 ? std::numeric_limits<double>::infinity()
                                                 : -std::numeric_limits<double>::infinity());
        if (in_supported_range(q) && split_point_valid(h, q)) {
          out = q;
          return true;
        }
      }
    }
    return false;
  };
  bool ok = search(p);
  unfolded_.clear();
  if (!ok && unfold_hull_slivers(h)) {
    ok = search(p);
    if (!ok) {
      // No point fits the unfolded side either (the split point must lie strictly between the
      // ends in each coordinate, which coarse doubles may not allow): fold the hull again, or it
      // is left reflex where the slivers were (BRH on a needle 3.7e19 long, found by fuzzing).
      hull_work_.clear();
      queue_unfolded_corners();
      unfolded_.clear();
      restore_hull(hull_work_);
    }
  }
  return ok;
}

// Inserts the split point p of subsegment h = a→b (a domain triangle on h's side), restores the
// Delaunay property and the convex hull around it, and queues what the new vertex makes bad.
void Refiner::insert_split_vertex(Handle h, const Point& p) {
  const VertexId a = m_.org(h), b = m_.dest(h);
  ensure_capacity();
  const std::int32_t marker = m_.marker(h);
  const VertexId v = m_.add_vertex(p, VertexKind::kSteinerOnSegment, marker);
  // The input segment this vertex lies on (for the Miller–Pav–Walkington rule).
  std::pair<VertexId, VertexId> seg = original_segment(a);
  if (seg.first == kNone) seg = original_segment(b);
  if (seg.first == kNone) seg = {std::min(a, b), std::max(a, b)};
  segment_of_.emplace(v, seg);
  const bool ghost_side = m_.is_ghost(m_.sym(h) >> 2);
  const auto opposite = m_.split_edge(h, v);
  stack_.clear();
  for (const Handle g : opposite) {
    // Ghost edges are not Lawson-flipped (that could make finite triangles that are not marked
    // outside); restore_hull() handles the hull.
    if (!(ghost_side && m_.is_ghost(g >> 2))) stack_.push_back(g);
  }
  Handle last = opposite[0];  // apex v, in the domain
  m_.legalize(v, stack_, &last);
  if (ghost_side) fold_hull_after_split(opposite);
  // Recheck every edge of the new vertex's star (see relax()).
  stack_.clear();
  {
    Handle h0 = last;
    if (m_.apex(h0) == v) h0 = Mesh::lprev(h0);
    else if (m_.dest(h0) == v) h0 = Mesh::lnext(h0);
    Handle g = h0;
    do {
      if (!m_.is_ghost(g >> 2)) {
        for (unsigned e = 0; e < 3; ++e) stack_.push_back(make_handle(g >> 2, e));
      }
      g = m_.onext(g);
    } while (g != h0);
  }
  const TriangleId near = last >> 2;
  relax();
  {
    const Location loc = m_.locate(p, make_handle(near, 0));
    if (loc.kind != Location::Kind::kOnVertex) throw InternalError("refine: lost a split vertex");
    last = loc.handle;
  }
  ++stats_.segment_splits;
  after_insertion(v, last);
}

// After a split of a hull subsegment: split_edge left the ghosts (b, v, ∞) in the old ghost's slot
// and (v, a, ∞) in a new one; the hull is made convex again at b, a, v and at the corners of every
// stretch of hull unfold_hull_slivers opened.
void Refiner::fold_hull_after_split(const std::array<Handle, 4>& opposite) {
  const TriangleId u = opposite[2] >> 2, u1 = opposite[3] >> 2;
  hull_work_.clear();
  const Triangle& U = m_.triangles[u];
  unsigned j = 0;
  while (U.v[j] != kInfinite) ++j;
  hull_work_.push_back(m_.sym(make_handle(u, prev3(j))) >> 2);  // the ghost ending at b
  hull_work_.push_back(u1);                                      // check at a
  hull_work_.push_back(u);                                       // check at v
  queue_unfolded_corners();
  restore_hull(hull_work_);
}

// Every corner of a stretch of hull unfold_hull_slivers opened may be reflex: queues the ghosts
// it made for restore_hull, to check at both finite corners of each.
void Refiner::queue_unfolded_corners() {
  for (const TriangleId g : unfolded_) {
    if (!m_.is_ghost(g)) continue;
    hull_work_.push_back(g);
    const Triangle& G = m_.triangles[g];
    unsigned k = 0;
    while (G.v[k] != kInfinite) ++k;
    hull_work_.push_back(m_.sym(make_handle(g, prev3(k))) >> 2);
  }
}

// ---- flips and the hull begin here ----------------------------------------------------------------

// General Lawson flipping from the edges on stack_: after a flip the four outer edges of the
// quadrilateral are rechecked. Segments and ghost edges are never flipped, nor an edge between the
// domain and the outside (they are always segments anyway). Needed after a boundary split: the
// rounded split point is not exactly on the subsegment, and next to the thin outside triangles of
// a convex-hull boundary an edge at the new vertex itself can fail the Delaunay test.
void Refiner::relax() {
  ++mesh_edits_;  // (the fan run, fan_run.cpp)
  while (!stack_.empty()) {
    const Handle h = stack_.back();
    stack_.pop_back();
    const TriangleId t = h >> 2, u = m_.sym(h) >> 2;
    if (m_.is_segment(h) || m_.is_ghost(t) || m_.is_ghost(u) ||
        m_.is_outside(t) != m_.is_outside(u) || !m_.is_locally_non_delaunay(h)) {
      continue;
    }
    const Handle diag = m_.flip(h);
    const TriangleId a = diag >> 2, b = m_.sym(diag) >> 2;
    for (unsigned e = 0; e < 3; ++e) {
      if (make_handle(a, e) != diag) stack_.push_back(make_handle(a, e));
      if (make_handle(b, e) != m_.sym(diag)) stack_.push_back(make_handle(b, e));
    }
    if (m_.in_domain(a)) {
      enqueue_if_bad(a);
      enqueue_if_bad(b);
    }
  }
}

// A split point on a hull subsegment is rounded, so the hull may turn reflex at it (p inside) or
// at a neighbour (p outside, next to collinear hull vertices). Reflex hull vertices are removed as
// incremental convex hull construction does: the ghost edge at the vertex is flipped, which turns
// the two ghosts into a thin finite triangle — marked kOutside, as it is not domain — and one
// ghost. `work` holds ghosts whose second finite corner is to be checked.
void Refiner::restore_hull(std::vector<TriangleId>& work) {
  ++mesh_edits_;  // (the fan run, fan_run.cpp)
  while (!work.empty()) {
    const TriangleId g = work.back();
    work.pop_back();
    if (m_.is_dead(g) || !m_.is_ghost(g)) continue;
    const Triangle& G = m_.triangles[g];
    unsigned k = 0;
    while (G.v[k] != kInfinite) ++k;
    // G reads (a, b, ∞); the next ghost (b, c, ∞) lies across G's edge b–∞ (opposite a).
    const VertexId a = G.v[next3(k)], b = G.v[prev3(k)];
    const Handle edge = make_handle(g, next3(k));
    const Handle across = m_.sym(edge);
    const VertexId c = m_.apex(across);
    if (c == kInfinite || orient2d(m_.points[a], m_.points[b], m_.points[c]) <= 0) continue;
    // Reflex at b: flip b–∞. Slot g becomes the finite triangle (a, b, c); the other slot the
    // ghost (a, c, ∞).
    m_.flip(edge);
    m_.flags[g] = static_cast<std::uint8_t>(m_.flags[g] | kOutside);
    // The new outside triangle may not be Delaunay with the outside triangles beyond its two old
    // hull edges; the outside region is kept Delaunay like the rest (validate checks it).
    for (unsigned e = 0; e < 3; ++e) stack_.push_back(make_handle(g, e));
    relax();
    const TriangleId u = across >> 2;
    work.push_back(u);  // check at c
    const Triangle& U = m_.triangles[u];
    unsigned j = 0;
    while (U.v[j] != kInfinite) ++j;
    work.push_back(m_.sym(make_handle(u, prev3(j))) >> 2);  // the ghost ending at a: check at a
  }
}

// If the far side of subsegment h is one of the thin outside triangles made by restore_hull (a fan
// of them can cover a hull subsegment split many times), no rounded split point may fit inside it.
// Unfolding them — flipping each, from the one on the hull inwards, with the ghost beside it —
// gives the subsegment a ghost on its far side; the split's restore_hull folds the hull again.
// Only near-degenerate triangles (area below 1e-10 of the squared longest edge) are unfolded,
// never a real part of the outside region. Returns true if h now has a ghost on its far side.
bool Refiner::unfold_hull_slivers(Handle h) {
  ++mesh_edits_;  // (the fan run, fan_run.cpp)
  auto thin = [&](TriangleId t) {
    if (m_.is_ghost(t) || !m_.is_outside(t)) return false;
    const Triangle& T = m_.triangles[t];
    const Point &a = m_.points[T.v[0]], &b = m_.points[T.v[1]], &c = m_.points[T.v[2]];
    const double cross = std::fabs((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
    const double l = std::max({squared_distance(a, b), squared_distance(b, c), squared_distance(c, a)});
    return cross < 1e-10 * l;
  };
  const TriangleId start = m_.sym(h) >> 2;
  if (!thin(start)) return false;
  // Breadth-first search through thin outside triangles (across non-segment edges) for one that
  // borders a ghost; parent links give the path back. A triangle is seen once per search (slot
  // stamps: the search may reach its 512 nodes on every split of a long hull subsegment).
  if (sliver_seen_.size() < m_.triangle_slots()) sliver_seen_.resize(m_.triangle_slots(), 0);
  if (++sliver_search_ == 0) {
    std::fill(sliver_seen_.begin(), sliver_seen_.end(), 0);
    sliver_search_ = 1;
  }
  std::vector<SliverNode>& nodes = sliver_nodes_;
  nodes.assign(1, SliverNode{start, kNone});
  sliver_seen_[start] = sliver_search_;
  std::size_t found = kNone;
  for (std::size_t i = 0; i < nodes.size() && found == kNone && nodes.size() < 512; ++i) {
    for (unsigned e = 0; e < 3; ++e) {
      const Handle g = make_handle(nodes[i].t, e);
      if (m_.is_segment(g)) continue;
      const TriangleId n = m_.sym(g) >> 2;
      if (m_.is_ghost(n)) {
        found = i;
        break;
      }
      if (sliver_seen_[n] != sliver_search_ && thin(n)) {
        sliver_seen_[n] = sliver_search_;
        nodes.push_back({n, i});
      }
    }
  }
  if (found == kNone) return false;
  for (std::size_t i = found; i != kNone; i = nodes[i].parent) {
    const TriangleId t = nodes[i].t;
    Handle edge = kNone;
    for (unsigned e = 0; e < 3 && edge == kNone; ++e) {
      const Handle g = make_handle(t, e);
      if (!m_.is_segment(g) && m_.is_ghost(m_.sym(g) >> 2)) edge = g;
    }
    if (edge == kNone) return false;
    const TriangleId u = m_.sym(edge) >> 2;
    m_.flip(edge);
    m_.flags[t] = static_cast<std::uint8_t>(m_.flags[t] & ~kOutside);
    m_.flags[u] = static_cast<std::uint8_t>(m_.flags[u] & ~kOutside);
    unfolded_.push_back(t);
    unfolded_.push_back(u);
  }
  return m_.is_ghost(m_.sym(h) >> 2);
}

}  // namespace mwst::refinement
