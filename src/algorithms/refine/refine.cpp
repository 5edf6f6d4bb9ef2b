// Delaunay refinement (the paper's DR column, and the engine of bundle removal).
//
// Ruppert, "A Delaunay refinement algorithm for quality 2-dimensional mesh generation" (1995), with
// the practical rules of Shewchuk, "Delaunay refinement algorithms for triangular mesh generation"
// (2002) as Triangle 1.6 applies them, and Üngör's off-centers ("Off-centers: a new type of Steiner
// points for computing size-optimal quality-guaranteed Delaunay triangulations", LATIN 2004):
//
//  1. Encroached subsegments are split first, always before any triangle. A vertex encroaches a
//     subsegment if it lies in its diametral lens (Chew; default) or circle (Ruppert). In a
//     constrained Delaunay mesh only the apices of the two triangles beside it need checking.
//  2. A subsegment with exactly one endpoint shared (at less than 90°) with another segment is
//     split on a concentric shell: at the power-of-two distance P from that endpoint with
//     1.5P ≤ L < 3P, so both segments of a small input angle get split points at equal distances.
//  3. Bad triangles are taken from a bucketed priority queue, shortest edge first (measured better
//     than worst quality first; numbers in bench/README.md). Each gets its off-center (or
//     circumcenter), located by a walk from the triangle that stops at subsegments. A point beyond a
//     subsegment, on one, or encroaching one of the subsegments that would bound its cavity is not
//     inserted: those subsegments are split and the triangle is queued again.
//  4. Miller–Pav–Walkington: a skinny triangle whose shortest edge joins split points on two
//     segments sharing an endpoint, at equal distances from it, is not split (it cannot be fixed;
//     splitting it would cascade towards the apex forever). Such triangles are counted at the end.
//
// Free Steiner points are inserted Bowyer–Watson style: the cavity (triangles whose circumcircle
// contains the point, grown across non-segment edges) is found first, its boundary subsegments are
// tested for encroachment, and only then is the cavity replaced by the star of the point. This is
// the same mesh Lawson flips would give, with one incircle test per cavity neighbour and no undo.
//
// Choices and measurements (bench/README.md has the tables): diametral lenses give lower weight and
// fewer Steiner points than circles at 10°, 20° and 30° on our data; the off-center factor is 0.90
// (kOffCenterFactor: lighter than Triangle's 0.95, see refine.hpp); shortest-edge-first beats
// worst-quality-first on weight and Steiner count at every bound measured.
//
// Boundary handling at double precision: a rounded split point is accepted only if the four new
// triangles are counter-clockwise and, on the convex hull, the hull stays convex; otherwise ulp
// neighbours are tried. A .node point set's domain is its convex hull: its hull edges are marked as
// subsegments (marker 1) before refining, so they are protected like input segments.
#include "mwst/algorithms/refine.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "mwst/error.hpp"

namespace mwst {

namespace {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

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

// The termination guard (Refiner::set_feature_guard): an angle-bad triangle whose shortest edge is
// below this fraction of the input's smallest feature stops the refinement. Measured on the 13
// data sets, 10k points on a circle and on an ellipse, at 5° to 33° with both rules: no triangle
// split had a shortest edge below 0.41 of the smallest feature (0.0025 at 34° with circumcenters,
// a run of 17 s); the runaways tried (a 1° spike at 38° to 55°, a unit square at 50°, data sets
// and 10k points on a circle at 37° to 55°) stop within a second.
constexpr double kFeatureGuardFraction = 1.0 / 1024.0;

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

inline std::uint64_t pair_key(VertexId u, VertexId w) {
  if (u > w) std::swap(u, w);
  return (static_cast<std::uint64_t>(u) << 32) | w;
}

// A priority queue of triangle slots in buckets of a positive key (smallest first). The bucket is
// the key's exponent and top mantissa bits, so each octave of the key has 2^kSubBits buckets.
// An entry is a triangle slot and the vertex at its corner 0 when queued: a popped entry whose slot
// now holds a triangle with another corner 0 is stale and dropped without touching coordinates
// (most stale entries are cavity triangles destroyed by an earlier insertion). An entry that
// passes is re-tested, so staleness never causes a wrong split. Within a bucket the last pushed
// comes first (the newest triangles are the ones in cache).
class BucketQueue {
 public:
  static constexpr unsigned kSubBits = 2;
  static constexpr std::size_t kBuckets = std::size_t{2048} << kSubBits;

  BucketQueue() : buckets_(kBuckets), nonempty_(kBuckets / 64, 0) {}

  struct Entry {
    TriangleId t;
    VertexId v0;
  };

  void push(double key, TriangleId t, VertexId v0) {
    std::size_t b = 0;
    if (key > 0.0) {
      b = static_cast<std::size_t>(std::bit_cast<std::uint64_t>(key) >> (52 - kSubBits));
      if (b >= kBuckets) b = kBuckets - 1;
    }
    buckets_[b].push_back({t, v0});
    nonempty_[b >> 6] |= std::uint64_t{1} << (b & 63);
    if (b < lowest_) lowest_ = b;
    ++size_;
  }

  bool pop(Entry& out) {
    if (size_ == 0) return false;
    std::size_t word = lowest_ >> 6;
    std::uint64_t bits = nonempty_[word] & (~std::uint64_t{0} << (lowest_ & 63));
    while (bits == 0) bits = nonempty_[++word];
    const std::size_t b = (word << 6) | static_cast<std::size_t>(std::countr_zero(bits));
    lowest_ = b;
    std::vector<Entry>& v = buckets_[b];
    out = v.back();
    v.pop_back();
    if (v.empty()) nonempty_[b >> 6] &= ~(std::uint64_t{1} << (b & 63));
    --size_;
    return true;
  }

  std::size_t size() const { return size_; }

 private:
  std::vector<std::vector<Entry>> buckets_;
  std::vector<std::uint64_t> nonempty_;
  std::size_t lowest_ = kBuckets;
  std::size_t size_ = 0;
};

// What the default test learns about a triangle.
struct Eval {
  bool bad = false;
  bool angle_bad = false;  // smallest angle below the bound
  bool size_bad = false;   // area above the bound
  unsigned apex = 0;       // corner opposite the shortest edge (the smallest angle)
  double shortest2 = 0.0;  // squared length of the shortest edge
  double key = 0.0;        // priority (smaller first)
};

class Refiner {
 public:
  Refiner(Mesh& mesh, const RefineOptions& options, RefineStats& stats)
      : m_(mesh), opt_(options), stats_(stats) {
    const double alpha = std::max(0.0, options.min_angle_deg) * std::numbers::pi / 180.0;
    alpha_ = alpha;
    if (alpha > 0.0) {
      const double c = std::cos(alpha);
      good_cos2_ = c * c;
      offcenter_scale_ = options.offcenter_factor * 0.5 / std::tan(0.5 * alpha);
    }
    // Lens: apex angle ≥ 180° − 2α, i.e. cos(apex) ≤ −cos 2α. For α ≥ 45° the lens would exceed
    // the diametral circle, and for α = 0 it is empty; both fall back to the circle.
    // Conforming Delaunay asks for empty diametral circles (Triangle's -D does the same).
    conforming_ = options.conforming_delaunay;
    lens_ = options.encroachment == Encroachment::kDiametralLens && options.min_angle_deg > 0.0 &&
            options.min_angle_deg < 45.0 && !conforming_;
    if (lens_) {
      const double c2 = std::cos(2.0 * alpha);
      lens_cos2_ = c2 * c2;
    }
    max_area_ = options.max_area;
    own_bounds_ = !mesh.area_bound.empty();
    custom_test_ = static_cast<bool>(options.is_bad);
    if (options.feature_guard_length > 0.0) guard_length2_ = options.feature_guard_length * options.feature_guard_length;
    seeded_ = custom_test_ && !options.seed_triangles.empty();
    worst_first_ = options.order == RefineOrder::kWorstQualityFirst;
  }

  void run();

 private:
  // ---- tests -----------------------------------------------------------------------------------
  bool evaluate(TriangleId t, Eval& ev);
  void enqueue_if_bad(TriangleId t) {
    Eval ev;
    if (seeded_) tested_.push_back(t);
    if (evaluate(t, ev)) queue_.push(ev.key, t, m_.triangles[t].v[0]);
  }
  bool encroaches(const Point& x, const Point& a, const Point& b) const;
  void check_subsegment(Handle h);
  bool may_split(Handle h) const;
  bool mpw_leaves(TriangleId t, const Eval& ev) const;

  // ---- Steiner points --------------------------------------------------------------------------
  Point steiner_point(TriangleId t, const Eval& ev) const;
  void split_triangle(TriangleId t, const Eval& ev);
  void split_at_centroid(TriangleId t, const Eval& ev);
  void insert_for(TriangleId t, const Eval& ev, const Point& p, TriangleId t0, bool centroid_next);

  // ---- walking and inserting -------------------------------------------------------------------
  enum class WalkKind { kInTriangle, kOnEdge, kOnVertex, kBlocked };
  struct WalkResult {
    WalkKind kind;
    Handle handle;
  };
  WalkResult walk(const Point& p, TriangleId start);
  enum class InsertKind { kInserted, kEncroaches, kProtected, kFailed };
  InsertKind insert_free(const Point& p, TriangleId t0);
  void insert_lawson(const Point& p, TriangleId t0);
  void after_insertion(VertexId v, Handle around);

  // ---- subsegments -----------------------------------------------------------------------------
  struct Pending {
    VertexId u, w;
    Handle hint;
  };
  void push_pending(Handle h) { pending_.push_back({m_.org(h), m_.dest(h), h}); }
  Handle find_subsegment(const Pending& p);
  bool split_all_pending();
  bool split_subsegment(Handle h);
  bool shares_acute_segment(Handle h) const;
  bool split_point_valid(Handle h, const Point& p) const;
  void restore_hull(std::vector<TriangleId>& work);
  void relax();
  bool unfold_hull_slivers(Handle h);
  std::pair<VertexId, VertexId> original_segment(VertexId v) const {
    const auto it = segment_of_.find(v);
    return it == segment_of_.end() ? std::pair<VertexId, VertexId>{kNone, kNone} : it->second;
  }

  // ---- bookkeeping -----------------------------------------------------------------------------
  void mark_hull_segments();
  void set_feature_guard();
  void prepare_conforming();
  void reserve_for_area_bound();
  bool budget_reached() const {
    return stats_.steiner_inserted + stats_.segment_splits >= opt_.max_steiner;
  }
  void ensure_capacity() {
    // Grow by a quarter instead of doubling: for large refinements this bounds peak memory.
    if (m_.triangles.size() + 2 > m_.triangles.capacity()) {
      const std::size_t n = m_.triangles.capacity() + m_.triangles.capacity() / 4 + 64;
      m_.triangles.reserve(n);
      m_.flags.reserve(n);
      if (!m_.segment_marker.empty()) m_.segment_marker.reserve(3 * n);
    }
    if (m_.points.size() + 1 > m_.points.capacity()) {
      const std::size_t n = m_.points.capacity() + m_.points.capacity() / 4 + 64;
      m_.points.reserve(n);
      m_.vertex_kind.reserve(n);
      m_.vertex_marker.reserve(n);
    }
  }

  Mesh& m_;
  const RefineOptions& opt_;
  RefineStats& stats_;
  double alpha_ = 0.0;
  double good_cos2_ = 1.0;  // cos² of the angle bound
  double offcenter_scale_ = 0.0;
  bool lens_ = false;
  double lens_cos2_ = 0.0;
  double max_area_ = -1.0;
  bool own_bounds_ = false;  // Mesh::area_bound in use
  bool conforming_ = false;  // RefineOptions::conforming_delaunay
  std::size_t protected_skips_ = 0;  // triangles left: their point lies on or beyond a protected subsegment
  // Squared length below which a subsegment is no longer split for conforming Delaunay (the
  // termination guard of those splits; 0 = none).
  double conforming_guard2_ = 0.0;
  bool custom_test_ = false;
  bool seeded_ = false;  // RefineOptions::seed_triangles in use
  bool worst_first_ = false;
  bool stop_ = false;
  std::string stop_reason_;
  const Clock::time_point started_ = Clock::now();  // the time budget counts from here
  std::size_t segment_splits_timed_ = 0;            // split_all_pending's clock reads, 1 in 16
  // Squared length below which an angle-bad triangle's shortest edge stops the refinement (the
  // termination guard; 0 = none): see set_feature_guard().
  double guard_length2_ = 0.0;

  BucketQueue queue_;
  std::vector<Pending> pending_;
  std::unordered_set<std::uint64_t> unsplittable_;
  // Refinement-made vertices on segments → the endpoints of the input segment they lie on.
  std::unordered_map<VertexId, std::pair<VertexId, VertexId>> segment_of_;
  std::uint32_t walk_rng_ = 0x2545F491u;

  // Scratch (no allocation per insertion).
  std::vector<TriangleId> cavity_;
  // cavity_stamp_[t] == cavity_round_ iff slot t is in the cavity being grown: an O(1) membership
  // test (a linear search of cavity_ made an insertion quadratic in its cavity size, and the first
  // insertions into the fan of skinny triangles a point set on a circle gives have cavities of
  // the whole mesh).
  std::vector<std::uint32_t> cavity_stamp_;
  std::uint32_t cavity_round_ = 0;
  std::vector<Handle> boundary_;
  std::vector<Handle> stack_;
  struct BoundaryEdge {
    VertexId org;
    Handle outer;
    bool segment;
    std::int32_t marker;
    double bound;  // Mesh::area_bound of the cavity triangle on this edge
  };
  std::vector<BoundaryEdge> ring_;
  std::vector<TriangleId> slots_;
  std::vector<TriangleId> hull_work_;
  std::vector<TriangleId> unfolded_;  // ghosts made by unfold_hull_slivers, to be refolded
  std::vector<TriangleId> tested_;    // seeded: every slot tested (the final recount's range)
};

// ---- tests -------------------------------------------------------------------------------------

bool Refiner::evaluate(TriangleId t, Eval& ev) {
  const Triangle& T = m_.triangles[t];
  const Point& a = m_.points[T.v[0]];
  const Point& b = m_.points[T.v[1]];
  const Point& c = m_.points[T.v[2]];
  const double abx = b.x - a.x, aby = b.y - a.y;
  const double bcx = c.x - b.x, bcy = c.y - b.y;
  const double cax = a.x - c.x, cay = a.y - c.y;
  const double l2 = abx * abx + aby * aby;  // opposite corner 2
  const double l0 = bcx * bcx + bcy * bcy;  // opposite corner 0
  const double l1 = cax * cax + cay * cay;  // opposite corner 1
  // Shortest edge and the cosine² of the angle opposite it (the smallest angle), from the dot
  // product of the two longer edges at that corner, as Triangle does.
  unsigned k;
  double shortest, dot, la, lb;
  if (l0 <= l1 && l0 <= l2) {
    k = 0;
    shortest = l0;
    dot = -(abx * cax + aby * cay);  // (b−a)·(c−a)
    la = l2;
    lb = l1;
  } else if (l1 <= l2) {
    k = 1;
    shortest = l1;
    dot = -(abx * bcx + aby * bcy);  // (a−b)·(c−b)
    la = l2;
    lb = l0;
  } else {
    k = 2;
    shortest = l2;
    dot = -(bcx * cax + bcy * cay);  // (b−c)·(a−c)
    la = l0;
    lb = l1;
  }
  const double cos2 = dot > 0.0 ? dot * dot / (la * lb) : 0.0;
  ev.apex = k;
  ev.shortest2 = shortest;
  ev.angle_bad = alpha_ > 0.0 && cos2 > good_cos2_;
  ev.size_bad = false;
  if (max_area_ > 0.0 || own_bounds_) {
    const double area = triangle_area(a, b, c);
    ev.size_bad = max_area_ > 0.0 && area > max_area_;
    if (own_bounds_) {
      const double bound = m_.area_bound[t];
      ev.size_bad = ev.size_bad || (bound > 0.0 && area > bound);
    }
  }
  if (custom_test_) {
    // The area bound holds with a custom test too (bundle removal's --max-area); the test is
    // called first, whatever the area, as its caller may record what it is asked.
    ev.bad = opt_.is_bad(m_, t) || ev.size_bad;
  } else {
    ev.bad = ev.angle_bad || ev.size_bad;
  }
  ev.key = worst_first_ ? std::max(0.0, 1.0 - cos2) : shortest;
  return ev.bad;
}

bool Refiner::encroaches(const Point& x, const Point& a, const Point& b) const {
  if (!lens_) return in_diametral_circle(a, b, x) > 0;
  // Lens (a quality heuristic, decided in floating point as Triangle does; the circle test above
  // is exact): the angle axb is at least 180° − 2α.
  const double ax = a.x - x.x, ay = a.y - x.y, bx = b.x - x.x, by = b.y - x.y;
  const double dot = ax * bx + ay * by;
  if (dot >= 0.0) return false;
  return dot * dot >= lens_cos2_ * (ax * ax + ay * ay) * (bx * bx + by * by);
}

// Queues subsegment h if the apex of an in-domain triangle beside it encroaches it.
void Refiner::check_subsegment(Handle h) {
  if (!may_split(h)) return;
  if (conforming_ && !m_.is_ghost(h >> 2) && !m_.is_ghost(m_.sym(h) >> 2) && m_.is_locally_non_delaunay(h)) {
    push_pending(h);
    return;
  }
  const VertexId a = m_.org(h), b = m_.dest(h);
  const Point& pa = m_.points[a];
  const Point& pb = m_.points[b];
  const Handle s = m_.sym(h);
  if (m_.in_domain(h >> 2) && encroaches(m_.points[m_.apex(h)], pa, pb)) {
    push_pending(h);
    return;
  }
  if (m_.in_domain(s >> 2) && encroaches(m_.points[m_.apex(s)], pa, pb)) push_pending(h);
}

// May refinement split subsegment h (RefineOptions::segment_splitting)? Triangle's -Y protects the
// subsegments on the boundary of the triangulation (a side not in the domain: a hole, the outside,
// the hull), -YY every subsegment.
bool Refiner::may_split(Handle h) const {
  switch (opt_.segment_splitting) {
    case SegmentSplitting::kAllowed: return true;
    case SegmentSplitting::kNever: return false;
    case SegmentSplitting::kNotBoundary: return m_.in_domain(h >> 2) && m_.in_domain(m_.sym(h) >> 2);
  }
  return true;
}

// The Miller–Pav–Walkington rule (in Triangle's form): a skinny triangle is left alone if the two
// ends of its shortest edge are split points on two different input segments that share an
// endpoint, at equal distances (within 0.1%) from it — the triangle subtends a small input angle
// and no Steiner point can improve it. Unlike Triangle we require the input angle to be below 60°.
bool Refiner::mpw_leaves(TriangleId t, const Eval& ev) const {
  if (segment_of_.empty()) return false;
  const Triangle& T = m_.triangles[t];
  const VertexId p = T.v[next3(ev.apex)], q = T.v[prev3(ev.apex)];
  const auto sp = original_segment(p);
  if (sp.first == kNone) return false;
  const auto sq = original_segment(q);
  if (sq.first == kNone || sp == sq) return false;
  VertexId join = kNone;
  if (sp.first == sq.first || sp.first == sq.second) join = sp.first;
  if (sp.second == sq.first || sp.second == sq.second) join = sp.second;
  if (join == kNone) return false;
  const Point& pj = m_.points[join];
  const double d1 = squared_distance(m_.points[p], pj);
  const double d2 = squared_distance(m_.points[q], pj);
  if (!(d1 < 1.001 * d2 && d1 > 0.999 * d2)) return false;
  // Only small input angles (below 60°) are exempt; at a wide angle the triangle can be fixed.
  const double dot = (m_.points[p].x - pj.x) * (m_.points[q].x - pj.x) +
                     (m_.points[p].y - pj.y) * (m_.points[q].y - pj.y);
  return dot > 0.0 && dot * dot > 0.25 * d1 * d2;
}

// ---- Steiner points ----------------------------------------------------------------------------

Point Refiner::steiner_point(TriangleId t, const Eval& ev) const {
  if (opt_.steiner_point) return opt_.steiner_point(m_, t);
  const Triangle& T = m_.triangles[t];
  // p → q is the shortest edge, r the apex of the smallest angle; (p, q, r) counter-clockwise.
  const Point& p = m_.points[T.v[next3(ev.apex)]];
  const Point& q = m_.points[T.v[prev3(ev.apex)]];
  const Point& r = m_.points[T.v[ev.apex]];
  // Circumcenter relative to p. The denominator 2·orient2d is taken in floating point when the
  // filter certifies its sign and magnitude, else from the exact construction.
  const double qx = q.x - p.x, qy = q.y - p.y, rx = r.x - p.x, ry = r.y - p.y;
  const double left = qx * ry, right = qy * rx;
  const double det = left - right;
  Point center;
  if (std::fabs(det) > 1e-12 * (std::fabs(left) + std::fabs(right))) {
    const double q2 = qx * qx + qy * qy, r2 = rx * rx + ry * ry;
    const double inv = 0.5 / det;
    center = {p.x + (ry * q2 - qy * r2) * inv, p.y + (qx * r2 - rx * q2) * inv};
  } else {
    center = circumcenter(p, q, r);
  }
  if (opt_.rule == SteinerRule::kCircumcenter || offcenter_scale_ <= 0.0 || !ev.angle_bad) {
    return {snap_to_range(center.x), snap_to_range(center.y)};
  }
  // Off-center (Üngör): on the bisector of pq, on r's side, at distance
  // factor·(|pq|/2)·cot(α/2) from the midpoint m — unless the circumcenter is closer.
  const double mx = p.x + 0.5 * qx, my = p.y + 0.5 * qy;
  const double len = std::sqrt(qx * qx + qy * qy);
  const double d = offcenter_scale_ * len;
  const double cmx = center.x - mx, cmy = center.y - my;
  if (cmx * cmx + cmy * cmy <= d * d || len == 0.0) {
    return {snap_to_range(center.x), snap_to_range(center.y)};
  }
  // Left normal of p→q points to r's side.
  const double s = d / len;
  return {snap_to_range(mx - qy * s), snap_to_range(my + qx * s)};
}

void Refiner::split_triangle(TriangleId t, const Eval& ev) {
  const Point p = steiner_point(t, ev);
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !in_supported_range(p)) {
    ++stats_.precision_skips;
    return;
  }
  const WalkResult w = walk(p, t);
  switch (w.kind) {
    case WalkKind::kOnVertex:
      // The rounded point coincides with a vertex: nothing can be inserted at double precision.
      ++stats_.precision_skips;
      return;
    case WalkKind::kBlocked:
    case WalkKind::kOnEdge:
      if (w.kind == WalkKind::kBlocked || m_.is_segment(w.handle)) {
        if (!may_split(w.handle)) {
          // Beyond or on a subsegment that may not be split.
          split_at_centroid(t, ev);
          return;
        }
        // Beyond a subsegment or on one: that subsegment is encroached (Ruppert's lemma: a
        // circumcenter hidden behind a subsegment implies the triangle's vertices encroach it).
        ++stats_.rejected;
        push_pending(w.handle);
        if (split_all_pending()) {
          queue_.push(ev.key, t, m_.triangles[t].v[0]);
        } else {
          ++stats_.precision_skips;
        }
        return;
      }
      [[fallthrough]];
    case WalkKind::kInTriangle: {
      insert_for(t, ev, p, w.handle >> 2, true);
      return;
    }
  }
}

// The Steiner point of t lies on or beyond a subsegment that may not be split (segment_splitting).
// A triangle too large for its area bound gets its centroid instead, which lies inside it, so the
// area bounds are always met; a triangle bad by its angle alone is left as it is (Triangle's -Y
// warns of the same: the quality may suffer) and counted.
void Refiner::split_at_centroid(TriangleId t, const Eval& ev) {
  if (!ev.size_bad) {
    ++protected_skips_;
    return;
  }
  const Triangle& T = m_.triangles[t];
  const Point& a = m_.points[T.v[0]];
  const Point& b = m_.points[T.v[1]];
  const Point& c = m_.points[T.v[2]];
  const Point p{(a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0};
  const WalkResult w = walk(p, t);
  if (w.kind == WalkKind::kOnVertex || w.kind == WalkKind::kBlocked ||
      (w.kind == WalkKind::kOnEdge && m_.is_segment(w.handle))) {
    ++protected_skips_;  // (a sliver whose rounded centroid is not inside it)
    return;
  }
  insert_for(t, ev, p, w.handle >> 2, false);
}

// Inserts the Steiner point p (lying in t0) of bad triangle t. If p encroaches subsegments they are
// split instead and t is queued again; if it lies on or beyond a protected one, t gets its
// centroid when `centroid_next` (split_at_centroid), else it is left and counted.
void Refiner::insert_for(TriangleId t, const Eval& ev, const Point& p, TriangleId t0, bool centroid_next) {
  const InsertKind r = insert_free(p, t0);
  if (r == InsertKind::kProtected) {
    if (centroid_next) {
      split_at_centroid(t, ev);
    } else {
      ++protected_skips_;
    }
  } else if (r == InsertKind::kEncroaches) {
    ++stats_.rejected;
    if (split_all_pending()) {
      queue_.push(ev.key, t, m_.triangles[t].v[0]);
    } else {
      ++stats_.precision_skips;
    }
  } else if (r == InsertKind::kFailed) {
    insert_lawson(p, t0);
  }
}

// ---- walking and inserting ---------------------------------------------------------------------

// A visibility walk from triangle `start` (in the domain) towards p that never crosses a
// subsegment: if every edge with p strictly beyond it is a subsegment, returns kBlocked with one.
Refiner::WalkResult Refiner::walk(const Point& p, TriangleId start) {
  TriangleId t = start;
  Handle came_from = kNone;
  const std::size_t limit = 64 + 4 * m_.triangles.size();
  for (std::size_t steps = 0; steps < limit; ++steps) {
    const Triangle& T = m_.triangles[t];
    int o[3];
    for (unsigned e = 0; e < 3; ++e) {
      o[e] = make_handle(t, e) == came_from
                 ? 1
                 : orient2d(m_.points[T.v[next3(e)]], m_.points[T.v[prev3(e)]], p);
    }
    walk_rng_ ^= walk_rng_ << 13;
    walk_rng_ ^= walk_rng_ >> 17;
    walk_rng_ ^= walk_rng_ << 5;
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
      came_from = s;
      t = s >> 2;
      moved = true;
      break;
    }
    if (moved) continue;
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

// Bowyer–Watson insertion of a free Steiner point p lying in (or on a non-segment edge of) t0.
Refiner::InsertKind Refiner::insert_free(const Point& p, TriangleId t0) {
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
        stack_.push_back(Mesh::lprev(s));
        stack_.push_back(Mesh::lnext(s));
        continue;
      }
    }
    boundary_.push_back(h);
  }
  // The cavity must be star-shaped from p (p strictly inside every boundary edge), and p must not
  // encroach a subsegment on its boundary (those are the subsegments p would see).
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
        if (unsplittable_.empty() || !unsplittable_.count(pair_key(m_.org(h), m_.dest(h)))) {
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

  // Replace the cavity by the star of p: triangle i = (p, a_i, a_{i+1}) over boundary edge i.
  ensure_capacity();
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
  if (n <= kScatteredStar) {
    for (std::size_t i = 0; i < n; ++i) enqueue_if_bad(slots_[i]);
  } else {
    // Pushed so that the bucket pops them as ring position n/2 + r(0), n/2 + r(1), ... (mod n),
    // r the bit reversal: the point's far side first, then its sides, then the quarters between.
    const int bits = static_cast<int>(std::bit_width(n - 1));
    for (std::size_t j = std::size_t{1} << bits; j-- > 0;) {
      std::size_t r = 0;
      for (int b = 0; b < bits; ++b) r |= ((j >> b) & 1) << (bits - 1 - b);
      if (r < n) enqueue_if_bad(slots_[(r + n / 2) % n]);
    }
  }
  return InsertKind::kInserted;
}

// Fallback insertion by Lawson flips (never across subsegments); used only if the cavity test
// above ever finds the cavity not star-shaped.
void Refiner::insert_lawson(const Point& p, TriangleId t0) {
  ensure_capacity();
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

// ---- subsegments -------------------------------------------------------------------------------

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

bool Refiner::split_all_pending() {
  bool any = false;
  while (!pending_.empty() && !stop_) {
    const Pending p = pending_.back();
    pending_.pop_back();
    if (!unsplittable_.empty() && unsplittable_.count(pair_key(p.u, p.w))) continue;
    const Handle h = find_subsegment(p);
    if (h == kNone || !may_split(h)) continue;
    if (budget_reached()) {
      stop_ = true;
      stop_reason_ = "steiner budget";
      break;
    }
    // Segment splits can cascade for long (points on a circle: every hull edge encroached).
    if (opt_.time_budget_seconds > 0.0 && (++segment_splits_timed_ & 15) == 0 &&
        seconds_since(started_) > opt_.time_budget_seconds) {
      stop_ = true;
      stop_reason_ = "time budget";
      break;
    }
    if (split_subsegment(h)) any = true;
  }
  return any;
}

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

// Can subsegment h = a→b (triangle of h in the domain) be split at the rounded point p? It must lie
// strictly between a and b along the segment, and the new triangles on finite sides must be
// counter-clockwise. (On a ghost side anything goes: restore_hull() makes the hull convex again.)
bool Refiner::split_point_valid(Handle h, const Point& p) const {
  const VertexId a = m_.org(h), b = m_.dest(h), c = m_.apex(h);
  const Point& pa = m_.points[a];
  const Point& pb = m_.points[b];
  if (p == pa || p == pb) return false;
  const double ux = pb.x - pa.x, uy = pb.y - pa.y;
  if ((p.x - pa.x) * ux + (p.y - pa.y) * uy <= 0.0) return false;
  if ((pb.x - p.x) * ux + (pb.y - p.y) * uy <= 0.0) return false;
  if (orient2d(pa, p, m_.points[c]) <= 0 || orient2d(p, pb, m_.points[c]) <= 0) return false;
  const VertexId d = m_.apex(m_.sym(h));
  if (d == kInfinite) return true;
  return orient2d(pb, p, m_.points[d]) > 0 && orient2d(p, pa, m_.points[d]) > 0;
}

// A split point on a hull subsegment is rounded, so the hull may turn reflex at it (p inside) or
// at a neighbour (p outside, next to collinear hull vertices). Reflex hull vertices are removed as
// incremental convex hull construction does: the ghost edge at the vertex is flipped, which turns
// the two ghosts into a thin finite triangle — marked kOutside, as it is not domain — and one
// ghost. `work` holds ghosts whose second finite corner is to be checked.
// General Lawson flipping from the edges on stack_: after a flip the four outer edges of the
// quadrilateral are rechecked. Segments and ghost edges are never flipped, nor an edge between the
// domain and the outside (they are always segments anyway). Needed after a boundary split: the
// rounded split point is not exactly on the subsegment, and next to the thin outside triangles of
// a convex-hull boundary an edge at the new vertex itself can fail the Delaunay test.
void Refiner::relax() {
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

void Refiner::restore_hull(std::vector<TriangleId>& work) {
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
  // borders a ghost; parent links give the path back.
  struct Node {
    TriangleId t;
    std::size_t parent;
  };
  std::vector<Node> nodes{{start, kNone}};
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
      bool seen = false;
      for (const Node& x : nodes) seen = seen || x.t == n;
      if (!seen && thin(n)) nodes.push_back({n, i});
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

bool Refiner::split_subsegment(Handle h) {
  if (!m_.in_domain(h >> 2)) h = m_.sym(h);
  if (!m_.in_domain(h >> 2)) return false;
  const VertexId a = m_.org(h), b = m_.dest(h);
  const Point pa = m_.points[a], pb = m_.points[b];
  // Concentric shells (Ruppert; Shewchuk): with exactly one endpoint shared with another segment
  // at an acute angle, split at a power of two P from it with 1.5P ≤ L < 3P.
  if (conforming_ && squared_distance(pa, pb) < conforming_guard2_) {
    // The conforming splits went far below the input's smallest feature: stop (termination guard).
    stop_ = true;
    stop_reason_ = kStopBeyondFeatureSize;
    return false;
  }
  const bool shared_a = shares_acute_segment(h);
  const bool shared_b = shares_acute_segment(m_.sym(h));
  const double length = distance(pa, pb);
  Point from = pa, to = pb;
  double t = 0.5;
  if (shared_a != shared_b && length > 0.0) {
    if (shared_b) std::swap(from, to);
    const int k = std::ilogb(length / 1.5);
    t = std::ldexp(1.0, k) / length;
  }
  auto at = [&](double s) {
    if (s == 0.5) return midpoint(from, to);
    return Point{snap_to_range(from.x + s * (to.x - from.x)), snap_to_range(from.y + s * (to.y - from.y))};
  };
  // Try the intended point, then its ulp neighbours, then slightly shifted parameters: at double
  // precision the point is almost never exactly on the segment, and near-degenerate neighbours or
  // the hull may reject a particular rounding.
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
  for (const Handle side : {h, m_.sym(h)}) {
    if (!m_.in_domain(side >> 2)) continue;
    const Point& c = m_.points[m_.apex(side)];
    const double magnitude = std::max({std::fabs(pa.x), std::fabs(pa.y), std::fabs(pb.x), std::fabs(pb.y),
                                       std::fabs(c.x), std::fabs(c.y)});
    const double cross = 2.0 * std::fabs(signed_area(pa, pb, c));  // the apex's distance to the line,
    if (cross < kThinSide * magnitude * length) {                   // times length
      unsplittable_.insert(pair_key(a, b));
      ++stats_.precision_skips;
      return false;
    }
  }
  Point p;
  bool ok = search(p);
  unfolded_.clear();
  if (!ok && unfold_hull_slivers(h)) ok = search(p);
  if (!ok) {
    unsplittable_.insert(pair_key(a, b));
    ++stats_.precision_skips;
    return false;
  }
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
  if (ghost_side) {
    // split_edge left the ghosts (b, v, ∞) in the old ghost's slot and (v, a, ∞) in a new one.
    const TriangleId u = opposite[2] >> 2, u1 = opposite[3] >> 2;
    hull_work_.clear();
    const Triangle& U = m_.triangles[u];
    unsigned j = 0;
    while (U.v[j] != kInfinite) ++j;
    hull_work_.push_back(m_.sym(make_handle(u, prev3(j))) >> 2);  // the ghost ending at b
    hull_work_.push_back(u1);                                      // check at a
    hull_work_.push_back(u);                                       // check at v
    for (const TriangleId g : unfolded_) {
      // Every corner of an unfolded stretch of hull may be reflex: check at both finite corners.
      if (!m_.is_ghost(g)) continue;
      hull_work_.push_back(g);
      const Triangle& G = m_.triangles[g];
      unsigned k = 0;
      while (G.v[k] != kInfinite) ++k;
      hull_work_.push_back(m_.sym(make_handle(g, prev3(k))) >> 2);
    }
    restore_hull(hull_work_);
  }
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
  return true;
}

// ---- bookkeeping -------------------------------------------------------------------------------

void Refiner::mark_hull_segments() {
  const std::size_t slots = m_.triangles.size();
  for (TriangleId g = 0; g < slots; ++g) {
    if (m_.is_dead(g) || !m_.is_ghost(g)) continue;
    const Triangle& G = m_.triangles[g];
    unsigned k = 0;
    while (G.v[k] != kInfinite) ++k;
    const Handle hull_edge = make_handle(g, k);
    if (!m_.is_segment(hull_edge) && m_.in_domain(m_.sym(hull_edge) >> 2)) {
      m_.set_segment(hull_edge, 1);
      ++stats_.hull_edges_marked;
    }
  }
}

// The termination guard. Delaunay refinement provably terminates only for angle bounds up to
// 20.7° (Ruppert 1995; Shewchuk 2002, with circumcenters and concentric shells), Triangle's
// documentation reports it usually terminating up to 33° and usually not above 34°, and Üngör's
// off-centers carry the same guarantee. In the proofs every vertex refinement inserts is at least a
// constant fraction of the local feature size from its nearest neighbour, so no edge gets shorter
// than a fraction of the input's smallest feature; above the bound new vertices crowd ever closer
// (at 50° on a unit square, without end). So: the smallest feature of the input is taken as the
// shortest edge of the carved mesh, or the shortest distance from a vertex to a subsegment of its
// triangle not ending at it, if shorter; with an area bound, no more than the side of a triangle
// of that area; an angle-bad triangle (not exempted by the Miller–Pav–Walkington rule) whose
// shortest edge is below kFeatureGuardFraction of that stops the refinement with its own stop
// reason. With a custom quality test the caller passes the length (RefineOptions::
// feature_guard_length): BRH computes it once from its input, as its passes refine in turn.
void Refiner::set_feature_guard() {
  if (opt_.feature_guard_length >= 0.0 || custom_test_ || alpha_ <= 0.0) return;  // given, or none
  const double length = feature_guard_length(m_, max_area_);
  guard_length2_ = length * length;
}

// Conforming Delaunay: subsegments with no domain triangle beside them (dangling segments in a
// hole, segments outside the domain) are unmarked, and the outside region is made Delaunay across
// them, so that only subsegments of the domain remain to be made locally Delaunay. The guard of
// the conforming splits is set at kFeatureGuardFraction of the smallest feature.
void Refiner::prepare_conforming() {
  const std::size_t slots = m_.triangles.size();
  stack_.clear();
  for (TriangleId t = 0; t < slots; ++t) {
    if (m_.is_dead(t) || m_.is_ghost(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if (m_.is_segment(h) && !m_.in_domain(t) && !m_.in_domain(m_.sym(h) >> 2)) m_.clear_segment(h);
      stack_.push_back(h);
    }
  }
  relax();
  const double length = feature_guard_length(m_, -1.0);
  if (length > 0.0) conforming_guard2_ = length * length;
}

// With an area bound the final size is known in advance to within a few per cent (about 1.6
// triangles per max_area of domain for uniform refinement, measured): reserving once avoids the
// transient doubling of the triangle arrays, which dominates peak memory on large runs.
void Refiner::reserve_for_area_bound() {
  if (max_area_ <= 0.0) return;
  const double area = m_.domain_area();
  // No more than the Steiner budget allows (each point adds two triangles; a budget of 32 on a
  // domain of area 5.6e14 with --max-area 2 reserved 9.8 GB), and no reservation beyond 1e8
  // triangles (2.4 GB): past that the arrays grow as they are used.
  const double expected = std::min(1.7 * area / max_area_, 2.0 * static_cast<double>(opt_.max_steiner) + 16.0);
  if (!(expected < 1e8)) return;
  const std::size_t tris = m_.triangles.size() + static_cast<std::size_t>(expected);
  const std::size_t verts = m_.points.size() + static_cast<std::size_t>(expected * 0.5);
  if (tris > m_.triangles.capacity()) {
    m_.triangles.reserve(tris);
    m_.flags.reserve(tris);
    if (!m_.segment_marker.empty()) m_.segment_marker.reserve(3 * tris);
  }
  if (verts > m_.points.capacity()) {
    m_.points.reserve(verts);
    m_.vertex_kind.reserve(verts);
    m_.vertex_marker.reserve(verts);
  }
}

void Refiner::run() {
  const auto t0 = Clock::now();
  // Seeded: the mesh was refined before (hull marked, no encroached subsegment); only the seeds
  // and what the splits make are looked at. A seed slot that is dead, a ghost or outside is
  // ignored (the caller's list may be stale).
  std::vector<TriangleId> seeds;
  if (seeded_) {
    for (const TriangleId t : opt_.seed_triangles) {
      if (t < m_.triangles.size() && m_.in_domain(t)) seeds.push_back(t);
    }
  } else {
    mark_hull_segments();
    reserve_for_area_bound();
    set_feature_guard();
    if (conforming_) prepare_conforming();
  }
  // Phase 1: every encroached subsegment, before any triangle (Ruppert's order).
  const std::size_t slots = seeded_ ? seeds.size() : m_.triangles.size();
  for (std::size_t i = 0; i < slots; ++i) {
    const TriangleId t = seeded_ ? seeds[i] : static_cast<TriangleId>(i);
    if (!m_.in_domain(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if (!m_.is_segment(h)) continue;
      const TriangleId other = m_.sym(h) >> 2;
      if (!seeded_ && m_.in_domain(other) && other < t) continue;  // checked from the other side
      check_subsegment(h);
    }
  }
  split_all_pending();
  const auto t1 = Clock::now();
  stats_.seconds_segments = std::chrono::duration<double>(t1 - t0).count();
  // Phase 2: bad triangles.
  if (seeded_) {
    for (const TriangleId t : seeds) {
      if (m_.in_domain(t)) enqueue_if_bad(t);  // a segment split may have replaced it
    }
  } else {
    for (TriangleId t = 0; t < m_.triangles.size(); ++t) {
      if (m_.in_domain(t)) enqueue_if_bad(t);
    }
  }
  std::size_t iterations = 0;
  while (!stop_) {
    if (!pending_.empty()) {
      split_all_pending();
      continue;
    }
    BucketQueue::Entry entry;
    if (!queue_.pop(entry)) break;
    const TriangleId t = entry.t;
    if (m_.triangles[t].v[0] != entry.v0 || !m_.in_domain(t)) continue;
    Eval ev;
    if (!evaluate(t, ev)) continue;
    if (ev.angle_bad && !ev.size_bad && mpw_leaves(t, ev)) {
      ++stats_.skipped_mpw;
      continue;
    }
    if (ev.angle_bad && !ev.size_bad && ev.shortest2 < guard_length2_) {
      stop_ = true;
      stop_reason_ = kStopBeyondFeatureSize;
      break;
    }
    if (budget_reached()) {
      stop_ = true;
      stop_reason_ = "steiner budget";
      break;
    }
    // (One clock read in 16 splits: a split costs far more, and on inputs where each split flips
    // thousands of edges, such as points on a circle, 256 splits could take seconds.)
    if (opt_.time_budget_seconds > 0.0 && (++iterations & 15) == 0 &&
        seconds_since(t0) > opt_.time_budget_seconds) {
      stop_ = true;
      stop_reason_ = "time budget";
      break;
    }
    split_triangle(t, ev);
  }
  stats_.seconds_triangles = seconds_since(t1);
  // What is left: triangles the test still calls bad (MPW, or precision limits). Every triangle
  // made was tested when it was made, so after a clean run with the local default test there is
  // nothing to count; a custom test may depend on more than the triangle, so it is always rerun.
  std::size_t left = 0;
  if (seeded_) {
    // Only the seeds and the triangles made were tested; a slot tested twice is counted once.
    std::sort(tested_.begin(), tested_.end());
    tested_.erase(std::unique(tested_.begin(), tested_.end()), tested_.end());
    for (const TriangleId t : tested_) {
      if (!m_.in_domain(t)) continue;
      Eval ev;
      if (evaluate(t, ev)) ++left;
    }
  } else if (stop_ || custom_test_ || stats_.skipped_mpw > 0 || stats_.precision_skips > 0 || protected_skips_ > 0) {
    for (TriangleId t = 0; t < m_.triangles.size(); ++t) {
      if (!m_.in_domain(t)) continue;
      Eval ev;
      if (evaluate(t, ev)) ++left;
    }
  }
  stats_.left_small_angle = left;
  if (protected_skips_ > 0) stats_.left_protected = left;
  if (!stop_reason_.empty()) {
    stats_.stop_reason = stop_reason_;
  } else if (left > 0 && protected_skips_ > 0) {
    stats_.stop_reason = std::to_string(left);
    stats_.stop_reason += kStopProtectedSuffix;
  } else if (left > 0) {
    stats_.stop_reason = std::to_string(left);
    stats_.stop_reason += " triangles left near small input angles";
  } else {
    stats_.stop_reason = "bound reached";
  }
  stats_.seconds = seconds_since(t0);
}

}  // namespace

// Hull edges count as subsegments, as the first unseeded pass marks them (mark_hull_segments)
// before it measures: a caller measuring the unrefined mesh gets the length that pass would.
double feature_guard_length(const Mesh& mesh, double max_area) {
  double smallest2 = std::numeric_limits<double>::infinity();
  const std::size_t slots = mesh.triangles.size();
  for (TriangleId t = 0; t < slots; ++t) {
    if (!mesh.in_domain(t)) continue;
    const Triangle& T = mesh.triangles[t];
    for (unsigned e = 0; e < 3; ++e) {
      const Point& a = mesh.points[T.v[next3(e)]];
      const Point& b = mesh.points[T.v[prev3(e)]];
      const double l2 = squared_distance(a, b);
      smallest2 = std::min(smallest2, l2);
      const Handle h = make_handle(t, e);
      if (!(mesh.is_segment(h) || mesh.is_ghost(mesh.sym(h) >> 2)) || l2 == 0.0) continue;
      // Distance from the opposite corner to the subsegment a–b (to its nearer end if the foot of
      // the perpendicular is outside it).
      const Point& c = mesh.points[T.v[e]];
      const double ux = b.x - a.x, uy = b.y - a.y;
      const double s = std::clamp(((c.x - a.x) * ux + (c.y - a.y) * uy) / l2, 0.0, 1.0);
      const double dx = c.x - (a.x + s * ux), dy = c.y - (a.y + s * uy);
      smallest2 = std::min(smallest2, dx * dx + dy * dy);
    }
  }
  if (!(smallest2 > 0.0) || !std::isfinite(smallest2)) return 0.0;
  if (max_area > 0.0) smallest2 = std::min(smallest2, max_area);
  // Per-triangle area bounds (regional limits, a refined mesh's .area) bound it the same way.
  if (!mesh.area_bound.empty()) {
    for (TriangleId t = 0; t < slots; ++t) {
      const double bound = mesh.area_bound[t];
      if (bound > 0.0 && mesh.in_domain(t)) smallest2 = std::min(smallest2, bound);
    }
  }
  return std::sqrt(smallest2) * kFeatureGuardFraction;
}

RefineStats refine(Mesh& mesh, const RefineOptions& options) {
  RefineStats stats;
  const auto t0 = Clock::now();
  if (options.min_angle_deg > 60.0) {
    throw InputError("", 0, "minimum angle bound above 60 degrees cannot be met");
  }
  if (options.min_angle_deg <= 0.0 && options.max_area <= 0.0 && !options.is_bad && mesh.area_bound.empty() &&
      !options.conforming_delaunay) {
    // Nothing asked: the constrained Delaunay triangulation is returned unchanged.
    stats.stop_reason = "bound reached";
    stats.seconds = seconds_since(t0);
    return stats;
  }
  Refiner refiner(mesh, options, stats);
  refiner.run();
  return stats;
}

}  // namespace mwst
