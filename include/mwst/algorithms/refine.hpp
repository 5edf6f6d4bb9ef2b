// mwst/algorithms/refine.hpp — Delaunay refinement (DR) and the engine bundle removal (BRH) reuses.
//
// Ruppert's algorithm with Chew's diametral lenses and Shewchuk's practical rules (Triangle 1.6),
// Üngör's off-centers, concentric-shell segment splitting and the Miller–Pav–Walkington rule for
// small input angles. The engine is general: a bucketed queue of bad triangles, a pluggable "is
// this triangle bad" test and a pluggable Steiner-point rule (the defaults are direct code paths).
// docs/algorithms/refine.md describes the method and the measurements behind its choices.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mwst/algorithms/stop_reason.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst {

enum class SteinerRule { kOffCenter, kCircumcenter };

// Where refinement may put Steiner points on input segments (Triangle's -Y and -YY). A subsegment
// refinement may not split is never split, even when encroached: a Steiner point that encroaches
// it is inserted all the same (the mesh stays constrained Delaunay), and a triangle whose Steiner
// point lies beyond or on it is left as it is and counted (RefineStats::left_protected).
enum class SegmentSplitting {
  kAllowed,      // anywhere (the default)
  kNotBoundary,  // not on subsegments of the triangulation's boundary (-Y)
  kNever,        // on no subsegment (-YY)
};

// Which vertices encroach a subsegment: those in its diametral circle (Ruppert), or only those in
// its diametral lens, the intersection of the two disks through both endpoints whose arcs meet the
// subsegment at the angle bound (Chew; Triangle's default). Lenses are smaller, so fewer segment
// splits happen and the mesh is lighter (docs/algorithms/refine.md).
enum class Encroachment { kDiametralLens, kDiametralCircle };

// The order in which bad triangles are split. Shortest edge first (Triangle's order; buckets of
// the squared shortest edge) or worst quality first (buckets of sin² of the smallest angle).
enum class RefineOrder { kShortestEdgeFirst, kWorstQualityFirst };

// Off-center distance factor: the off-center is placed at kOffCenterFactor · (|pq|/2)·cot(α/2)
// from the midpoint of the shortest edge pq. 1.0 makes the new triangle on pq meet the bound
// exactly, so rounding leaves it just below and it is split again; Triangle 1.6 uses 0.95. 0.90
// gives lighter meshes for slightly more Steiner points, and weight is what mwst minimises
// (docs/algorithms/refine.md has the measurements).
inline constexpr double kOffCenterFactor = 0.90;

// Decides whether a triangle is "bad" (to be split). The default (empty) is the angle test:
// smallest angle below RefineOptions::min_angle_deg. Either way a triangle whose area is above
// RefineOptions::max_area is bad too.
using BadTriangleTest = std::function<bool(const Mesh&, TriangleId)>;

// Chooses the Steiner point of a bad triangle. The default (empty) is RefineOptions::rule.
using SteinerPointRule = std::function<Point(const Mesh&, TriangleId)>;

struct RefineOptions {
  double min_angle_deg = 20.0;   // 0 = no angle bound
  double max_area = -1.0;        // ≤ 0: no area bound
  std::size_t max_steiner = static_cast<std::size_t>(-1);
  double time_budget_seconds = -1.0;  // ≤ 0: none
  // Under a time budget, the seconds set aside within it for each vertex the refinement adds: the
  // caller's work after the refinement (measuring the mesh, writing it out) grows with the mesh, so
  // the refinement stops once its time plus this much per added vertex reaches the budget. 0: none.
  double time_reserve_per_vertex = 0.0;
  SteinerRule rule = SteinerRule::kOffCenter;
  double offcenter_factor = kOffCenterFactor;
  Encroachment encroachment = Encroachment::kDiametralLens;
  RefineOrder order = RefineOrder::kShortestEdgeFirst;
  BadTriangleTest is_bad;        // empty: the angle test (the area bound applies either way)
  SteinerPointRule steiner_point;  // empty: circumcenter or off-center per `rule`
  SegmentSplitting segment_splitting = SegmentSplitting::kAllowed;
  // Conforming Delaunay (Triangle's -D): a subsegment is also split while it is not locally
  // Delaunay, i.e. while the apex of a triangle on one side (in the domain or carved away, not a
  // ghost) lies strictly inside the circumcircle of the triangle on the other side. With every
  // other edge kept locally Delaunay this makes the whole triangulation of the convex hull
  // Delaunay (the Delaunay lemma), so every domain triangle has an empty circumcircle. Subsegments
  // with no domain triangle beside them are unmarked first (they bound nothing that is output).
  // Every such split is of a subsegment encroached in Ruppert's sense (an apex in its diametral
  // circle), so with concentric-shell splitting the splits stop, as in Ruppert's proof; the
  // termination guard stops them otherwise.
  bool conforming_delaunay = false;
  // Seeded (incremental) refinement, for a mesh a previous refine() pass already refined (hull
  // edges marked, no encroached subsegment left) when only a few triangles are to be re-examined.
  // Used only when non-empty and is_bad is set: then only these triangles (live, in-domain slots;
  // others are ignored) and the triangles the splits make are tested and queued, and only the
  // subsegments on their edges are checked for encroachment; the whole-mesh scans (hull marking,
  // encroachment, initial queue, final recount) are skipped, so a pass costs time proportional
  // to its work, not to the mesh. RefineStats::left_small_angle then counts the bad triangles
  // among those tested. Empty: the whole mesh, as always (the output does not depend on this
  // field then).
  std::vector<TriangleId> seed_triangles;
  // The termination guard's edge length (see feature_guard_length): an angle-bad triangle the test
  // calls bad whose shortest edge is shorter stops the refinement with StopKind::kBeyondFeatureSize.
  // < 0: computed from the mesh at the start of an unseeded run with the default test, none with
  // a custom one; 0: none; > 0: this length (a caller refining in passes, as BRH, computes it once
  // from its input and passes it to every pass, seeded or not).
  double feature_guard_length = -1.0;
  // The input segment (its two input endpoints) of every vertex refinement put on a segment, for
  // the Miller–Pav–Walkington rule (a skinny triangle between two segments meeting at a small
  // input angle is left). Null: the pass keeps its own, which is right for one pass. A caller
  // refining in passes (BRH) keeps one map for all of them: a pass with a fresh map took the
  // vertices earlier passes put on segments for input vertices, the rule no longer saw the small
  // angle, and the splits near it did not end (BRH on a fan of 0.01° wedges).
  std::unordered_map<VertexId, std::pair<VertexId, VertexId>>* segment_origins = nullptr;
  // The point location walk crosses a fan of triangles around one vertex whose far edges lie on
  // one line (a point fan) in one step where its path there is forced (docs/algorithms/refine.md,
  // "The point fan"). The result is the same either way, to the bit: false walks every triangle,
  // for tests that compare the two.
  bool fan_shortcut = true;
};

// The termination guard's edge length for a carved mesh not yet refined: kFeatureGuardFraction
// (1/1024, src/algorithms/refine/termination_guard.cpp) of its smallest feature, the shortest edge of a domain triangle or distance
// from a corner to a subsegment or hull edge of its triangle not ending at it, and with an area
// bound (max_area > 0) at most √max_area. 0 if the mesh has no positive feature.
MWST_API double feature_guard_length(const Mesh& mesh, double max_area);

struct RefineStats {
  std::size_t steiner_inserted = 0;   // free Steiner points
  std::size_t segment_splits = 0;     // Steiner points on segments
  std::size_t left_small_angle = 0;   // bad triangles left because they cannot be improved (0 when out of time: not counted)
                                      // (near small input angles, Miller–Pav–Walkington;
                                      // with seeds: among the triangles tested)
  std::size_t hull_edges_marked = 0;  // hull edges of a convex-hull domain made subsegments
  std::size_t rejected = 0;           // Steiner points not inserted (they encroached a subsegment
                                      // or lay beyond one); the subsegment was split instead
  std::size_t skipped_mpw = 0;        // times a skinny triangle was left by the MPW rule
  std::size_t left_protected = 0;     // bad triangles left because their Steiner point lies on
                                      // or beyond a subsegment that may not be split
                                      // (segment_splitting), counted at the end
  std::size_t conforming_splits = 0;  // conforming_delaunay: splits of subsegments not locally Delaunay
  std::size_t precision_skips = 0;    // points not insertable at double precision (duplicate
                                      // vertex, or no valid rounded split point)
  // The Bowyer–Watson cavities grown for free Steiner points (inserted or not): how many, the
  // triangles in them all, the largest, and cavity_histogram[k], the number of cavities of 2^k to
  // 2^(k+1) − 1 triangles. Their total is the insertion cost that ordinary inputs keep at a few
  // triangles per point and nearly cocircular rings (points on a circle) can make quadratic.
  std::size_t cavities = 0;
  std::size_t cavity_triangles = 0;
  std::size_t largest_cavity = 0;
  std::array<std::size_t, 32> cavity_histogram{};
  std::size_t circumcenters_for_large_cavities = 0;  // off-centers whose cavity was too large,
                                                     // replaced by the circumcenter
  // The point location walks: triangles stepped through one at a time, and triangles crossed in
  // one step by the fan shortcut (RefineOptions::fan_shortcut). Their sum is what the walks would
  // have stepped through without it.
  std::size_t walk_steps = 0;
  std::size_t walk_steps_skipped = 0;
  StopReason stop;                    // kBoundReached, kSteinerBudget, kTimeBudget,
                                      // kSmallInputAngles (count left), kProtectedSegments (count
                                      // left), kBeyondFeatureSize (the termination guard)
  double seconds = 0.0;               // total
  double seconds_segments = 0.0;      // first phase: splitting the initially encroached subsegments
  double seconds_triangles = 0.0;     // second phase: splitting bad triangles
};

// Mesh::area_bound, when sized, bounds each triangle's area as well (a triangle above its own
// bound is bad), and the triangles refinement makes inherit the bound of the one they replace.
//
// Refines a carved constrained Delaunay mesh in place (Ruppert / Shewchuk / Üngör). The mesh stays
// constrained Delaunay; every free Steiner point lies inside the domain; triangles outside the
// domain (kOutside) are only touched where a boundary subsegment is split. With min_angle_deg ≤ 0,
// no max_area and no custom test the mesh is returned unchanged. Hull edges of the domain that are
// not subsegments (a point set, or Triangle's -c) are first marked as subsegments with marker 1.
MWST_API RefineStats refine(Mesh& mesh, const RefineOptions& options);

}  // namespace mwst
