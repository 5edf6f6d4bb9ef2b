// src/algorithms/refine/insertion.cpp — locating and inserting free Steiner points
// (refiner.hpp): a visibility walk that stops at subsegments, Bowyer–Watson insertion with the
// encroachment test on the cavity's boundary, and Lawson flips as the fallback.
//
// The cavity (triangles whose circumcircle contains the point, grown across non-segment edges) is
// found first, its boundary subsegments are tested for encroachment, and only then is the cavity
// replaced by the star of the point. This is the same mesh Lawson flips would give, with one
// incircle test per cavity neighbour and no undo.
#include "algorithms/refine/refiner.hpp"

#include "mwst/error.hpp"

namespace mwst::refinement {

namespace {

// Stars of more than this many triangles are queued in a scattered order instead of ring order.
// The queue pops the newest entry of a bucket first, so in ring order the next Steiner point goes
// next to the last one. Where a point empties a fan of nearly cocircular skinny triangles (the
// Delaunay triangulation of points on a circle, and again each ring of off-centers inside it), the
// next point's cavity is then all of the fan but one triangle: refining 40k points on a circle at
// 20° grew cavities of 9.0M triangles in all, Θ(n²). Popped in bit-reversed order, starting from
// the ring's middle (its start and end are next to the point itself), each point takes only the
// triangles nearer to it than to the points before it, about half of what is left there, as in a
// randomized insertion order: 1.1M triangles, O(n log n). Below this size ring order is kept:
// ordinary stars have 3 to 10 triangles, and the largest star in the refinements of the 13 data
// sets has 391 (the first circumcenter in Ellipse's fan), so their meshes are unchanged.
// Scattering from 512 rather than from 64 costs little: on a 100k circle 3.1M cavity triangles
// in all against 2.1M.
constexpr std::size_t kScatteredStar = 512;

}  // namespace

// ---- the walk begins here -------------------------------------------------------------------------

// A visibility walk from triangle `start` (in the domain) towards p that never crosses a
// subsegment: if every edge with p strictly beyond it is a subsegment, returns kBlocked with one.
//
// Where the walk turns about one vertex through a point fan (a run of triangles whose far edges
// lie on one line), the triangles of the run where its step is forced are crossed in one step
// (skip_fan_run, fan_run.cpp), with the random generator advanced as if each had been stepped
// through: the walk ends where it would have, in the same state.
Refiner::WalkResult Refiner::walk(const Point& p, TriangleId start) {
  TriangleId t = start;
  Handle came_from = kNone;
  const std::size_t limit = 64 + 4 * m_.triangles.size();
  // The vertex the last crossed edges share, and how many edges in a row were crossed at it.
  VertexId pivot = kNone, last_org = kNone, last_dest = kNone;
  std::size_t turns = 0;
  std::size_t walked = 0, skipped = 0;
  for (std::size_t steps = 0; steps < limit; ++steps) {
    if (came_from != kNone && opt_.fan_shortcut) {
      if (turns >= kFanTurns && !in_fan_run(t) && fan_credit_ >= std::max(kFanTurns, fan_build_cost_ / 4)) {
        build_fan_run(pivot, t);
      }
      if (in_fan_run(t)) {
        const std::size_t crossed = skip_fan_run(p, t, came_from);
        skipped += crossed;
        steps += crossed;
        if (steps >= limit) break;
      }
    }
    ++walked;
    if (turns >= kFanTurns) ++fan_credit_;
    const Triangle& T = m_.triangles[t];
    int o[3];
    for (unsigned e = 0; e < 3; ++e) {
      o[e] = make_handle(t, e) == came_from
                 ? 1
                 : orient2d(m_.points[T.v[next3(e)]], m_.points[T.v[prev3(e)]], p);
    }
    walk_rng_ = xorshift_step(walk_rng_);
    const unsigned first = walk_rng_ % 3;
    Handle blocked = kNone;
    bool moved = false;
    for (unsigned i = 0; i < 3; ++i) {
      const unsigned e = (first + i) % 3;
      if (o[e] >= 0) continue;
      const Handle h = make_handle(t, e);
      const Handle s = T.n[e];
      if (m_.is_segment(h) || !m_.in_domain(s >> 2)) {
        blocked = h;
        continue;
      }
      const VertexId a = T.v[next3(e)], b = T.v[prev3(e)];
      if (a == pivot || b == pivot) {
        ++turns;
      } else {
        pivot = (a == last_org || a == last_dest) ? a : ((b == last_org || b == last_dest) ? b : kNone);
        turns = pivot == kNone ? 0 : 2;
      }
      last_org = a;
      last_dest = b;
      came_from = s;
      t = s >> 2;
      moved = true;
      break;
    }
    if (moved) continue;
    stats_.walk_steps += walked;
    stats_.walk_steps_skipped += skipped;
    if (blocked != kNone) return {WalkKind::kBlocked, blocked};
    const int zeros = (o[0] == 0) + (o[1] == 0) + (o[2] == 0);
    if (zeros == 0) return {WalkKind::kInTriangle, make_handle(t, 0)};
    if (zeros == 1) {
      const unsigned e = o[0] == 0 ? 0 : (o[1] == 0 ? 1 : 2);
      return {WalkKind::kOnEdge, make_handle(t, e)};
    }
    for (unsigned k = 0; k < 3; ++k) {
      if (m_.points[T.v[k]] == p) return {WalkKind::kOnVertex, make_handle(t, prev3(k))};
    }
    throw InternalError("refine: inconsistent orientation tests in the walk");
  }
  throw InternalError("refine: walk did not terminate (corrupt mesh)");
}

// ---- Bowyer–Watson insertion begins here ----------------------------------------------------------

// Bowyer–Watson insertion of a free Steiner point p lying in (or on a non-segment edge of) t0;
// kTooLarge, with nothing changed, if its cavity would exceed cavity_limit triangles.
Refiner::InsertKind Refiner::insert_free(const Point& p, TriangleId t0, std::size_t cavity_limit) {
  const InsertKind grown = grow_cavity(p, t0, cavity_limit);
  if (grown != InsertKind::kInserted) return grown;
  const InsertKind boundary = check_cavity_boundary(p);
  if (boundary != InsertKind::kInserted) return boundary;
  fill_star(p);
  return InsertKind::kInserted;
}

// The cavity of p (cavity_) and its boundary as a counter-clockwise ring of handles (boundary_):
// kInserted when grown, kFailed if the growth meets a cavity triangle again, kTooLarge once it
// passes cavity_limit triangles.
Refiner::InsertKind Refiner::grow_cavity(const Point& p, TriangleId t0, std::size_t cavity_limit) {
  cavity_.clear();
  boundary_.clear();
  stack_.clear();
  if (cavity_stamp_.size() < m_.triangles.size()) {
    cavity_stamp_.resize(m_.triangles.size() + m_.triangles.size() / 4 + 64, 0);
  }
  if (++cavity_round_ == 0) {  // the stamp wrapped: clear the old ones
    std::fill(cavity_stamp_.begin(), cavity_stamp_.end(), 0);
    cavity_round_ = 1;
  }
  cavity_.push_back(t0);
  cavity_stamp_[t0] = cavity_round_;
  stack_.push_back(make_handle(t0, 2));
  stack_.push_back(make_handle(t0, 1));
  stack_.push_back(make_handle(t0, 0));
  // Depth-first growth in counter-clockwise order, so the boundary comes out as a ccw ring.
  while (!stack_.empty()) {
    const Handle h = stack_.back();
    stack_.pop_back();
    const Handle s = m_.sym(h);
    const TriangleId u = s >> 2;
    if (!m_.is_segment(h) && m_.in_domain(u)) {
      const Triangle& U = m_.triangles[u];
      if (incircle(m_.points[U.v[0]], m_.points[U.v[1]], m_.points[U.v[2]], p) > 0) {
        // The cavity of a point in a constrained Delaunay triangulation is a triangulated disk
        // with no interior vertex, so its dual is a tree: meeting a cavity triangle again means
        // the exact invariants failed somewhere; fall back to Lawson flips.
        if (cavity_stamp_[u] == cavity_round_) return InsertKind::kFailed;
        cavity_stamp_[u] = cavity_round_;
        cavity_.push_back(u);
        if (cavity_.size() > cavity_limit) {
          count_cavity(cavity_.size());
          return InsertKind::kTooLarge;
        }
        stack_.push_back(Mesh::lprev(s));
        stack_.push_back(Mesh::lnext(s));
        continue;
      }
    }
    boundary_.push_back(h);
  }
  count_cavity(cavity_.size());
  return InsertKind::kInserted;
}

// The cavity must be star-shaped from p (p strictly inside every boundary edge), and p must not
// encroach a subsegment on its boundary (those are the subsegments p would see). kInserted: p may
// be inserted; kEncroaches: the subsegments it encroaches are pending; kProtected: p lies on or
// beyond a subsegment that may not be split; kFailed: the cavity is not star-shaped (or p is
// beyond a subsegment too thin to split).
Refiner::InsertKind Refiner::check_cavity_boundary(const Point& p) {
  bool encroached = false;
  for (const Handle h : boundary_) {
    const Point& a = m_.points[m_.org(h)];
    const Point& b = m_.points[m_.dest(h)];
    const int o = orient2d(a, b, p);
    if (m_.is_segment(h)) {
      if (!may_split(h)) {
        // A protected subsegment: p may encroach it, but not lie on or beyond it.
        if (o <= 0) return InsertKind::kProtected;
        continue;
      }
      if (o <= 0 || encroaches(p, a, b)) {
        if (unsplittable_.empty() || !unsplittable_.count(undirected_key(m_.org(h), m_.dest(h)))) {
          push_pending(h);
          encroached = true;
        } else if (o <= 0) {
          return InsertKind::kFailed;
        }
      }
    } else if (o <= 0) {
      return InsertKind::kFailed;
    }
  }
  if (encroached) return InsertKind::kEncroaches;
  if (boundary_.size() != cavity_.size() + 2) return InsertKind::kFailed;
  return InsertKind::kInserted;
}

// Replaces the cavity by the star of p: triangle i = (p, a_i, a_{i+1}) over boundary edge i.
void Refiner::fill_star(const Point& p) {
  ensure_capacity();
  // The fan run stays valid unless the cavity takes one of its triangles: the others keep their
  // corners, flags and the neighbours across their spokes.
  if (fan_run_edits_ == mesh_edits_) {
    for (const TriangleId c : cavity_) {
      if (c < fan_position_.size() && fan_position_[c] != 0) {
        ++mesh_edits_;
        break;
      }
    }
  }
  const std::size_t n = boundary_.size();
  ring_.clear();
  for (const Handle h : boundary_) {
    const bool seg = m_.is_segment(h);
    // Each triangle of the star inherits the area bound of the cavity triangle it replaces on its
    // boundary edge (so bounds stay where they were; the cavity never crosses a subsegment, so
    // regional bounds are one value here).
    ring_.push_back({m_.org(h), m_.sym(h), seg, seg ? m_.marker(h) : 0, own_bounds_ ? m_.area_bound[h >> 2] : -1.0});
  }
  slots_.assign(cavity_.begin(), cavity_.end());
  slots_.push_back(m_.new_triangle());
  slots_.push_back(m_.new_triangle());
  const VertexId v = m_.add_vertex(p, VertexKind::kSteiner, 0);
  const bool has_markers = !m_.segment_marker.empty();
  for (std::size_t i = 0; i < n; ++i) {
    const TriangleId t = slots_[i];
    const std::size_t next = i + 1 == n ? 0 : i + 1;
    const std::size_t prev = i == 0 ? n - 1 : i - 1;
    Triangle& T = m_.triangles[t];
    T.v = {v, ring_[i].org, ring_[next].org};
    T.n[0] = ring_[i].outer;
    T.n[1] = make_handle(slots_[next], 2);
    T.n[2] = make_handle(slots_[prev], 1);
    const Handle outer = ring_[i].outer;
    m_.triangles[outer >> 2].n[outer & 3] = make_handle(t, 0);
    m_.flags[t] = ring_[i].segment ? kSegmentEdge0 : std::uint8_t{0};
    if (has_markers && ring_[i].segment) m_.segment_marker[3 * t] = ring_[i].marker;
    if (own_bounds_) m_.area_bound[t] = ring_[i].bound;
  }
  ++stats_.steiner_inserted;
  if (conforming_) {
    // p faces each subsegment of the ring across it now: is each still locally Delaunay?
    for (std::size_t i = 0; i < n; ++i) {
      if (ring_[i].segment) check_subsegment(make_handle(slots_[i], 0));
    }
  }
  queue_star(n);
}

// Queues the bad triangles of the star just made (slots_, n triangles), in ring order for an
// ordinary star, scattered for a large one (kScatteredStar).
//
// A large star is tested with the clock read every 256 triangles: a point inside 160k points on a
// circle has a star of all of them, and BRH's criterion floods each one's circumdisk (1 s for the
// one star). Out of time the rest is not queued: the refinement stops after this split.
void Refiner::queue_star(std::size_t n) {
  if (n <= kScatteredStar) {
    for (std::size_t i = 0; i < n; ++i) enqueue_if_bad(slots_[i]);
  } else {
    // Pushed so that the bucket pops them as ring position n/2 + r(0), n/2 + r(1), ... (mod n),
    // r the bit reversal: the point's far side first, then its sides, then the quarters between.
    const int bits = static_cast<int>(std::bit_width(n - 1));
    for (std::size_t j = std::size_t{1} << bits; j-- > 0;) {
      if ((j & 255) == 0 && out_of_time()) return;
      std::size_t r = 0;
      for (int b = 0; b < bits; ++b) r |= ((j >> b) & 1) << (bits - 1 - b);
      if (r < n) enqueue_if_bad(slots_[(r + n / 2) % n]);
    }
  }
}

// ---- Lawson insertion and its aftermath begin here ------------------------------------------------

// Fallback insertion by Lawson flips (never across subsegments); used only if the cavity test
// above ever finds the cavity not star-shaped.
void Refiner::insert_lawson(const Point& p, TriangleId t0) {
  ensure_capacity();
  ++mesh_edits_;
  const VertexId v = m_.add_vertex(p, VertexKind::kSteiner, 0);
  Handle hint = kNone;
  const VertexId got = m_.insert_vertex(v, make_handle(t0, 0), &hint);
  if (got != v) {
    m_.points.pop_back();
    m_.vertex_kind.pop_back();
    m_.vertex_marker.pop_back();
    ++stats_.precision_skips;
    return;
  }
  ++stats_.steiner_inserted;
  after_insertion(v, hint);
}

// Inserts the Steiner point p (lying in t0) of bad triangle t. If p encroaches subsegments they are
// split instead and t is queued again; kProtected (p lies on or beyond a protected subsegment) and
// kTooLarge (its cavity passes cavity_limit) are left to the caller, with nothing changed.
Refiner::InsertKind Refiner::insert_for(TriangleId t, const Eval& ev, const Point& p, TriangleId t0,
                                        std::size_t cavity_limit) {
  const InsertKind r = insert_free(p, t0, cavity_limit);
  if (r == InsertKind::kEncroaches) {
    split_pending_for(t, ev);
  } else if (r == InsertKind::kFailed) {
    insert_lawson(p, t0);
  }
  return r;
}

// After a vertex v was inserted (by a split and flips): queue the bad triangles of its star and
// the subsegments it or its neighbours encroach. `around` is an edge with v as an endpoint or apex.
void Refiner::after_insertion(VertexId v, Handle around) {
  Handle h0 = around;
  if (m_.apex(h0) == v) {
    h0 = Mesh::lprev(h0);
  } else if (m_.dest(h0) == v) {
    h0 = Mesh::lnext(h0);
  }
  if (m_.org(h0) != v) throw InternalError("refine: lost the new vertex");
  Handle h = h0;
  std::size_t guard = 0;
  do {
    const TriangleId t = h >> 2;
    if (m_.in_domain(t)) {
      enqueue_if_bad(t);
      for (unsigned e = 0; e < 3; ++e) {
        const Handle g = make_handle(t, e);
        if (m_.is_segment(g)) check_subsegment(g);
      }
    } else if (conforming_ && !m_.is_ghost(t) && !m_.is_dead(t)) {
      // An outside triangle of the star faces subsegments of the domain's boundary too.
      for (unsigned e = 0; e < 3; ++e) {
        const Handle g = make_handle(t, e);
        if (m_.is_segment(g)) check_subsegment(g);
      }
    }
    h = m_.onext(h);
    if (++guard > m_.triangles.size()) throw InternalError("refine: vertex star does not close");
  } while (h != h0);
}

}  // namespace mwst::refinement
