// mwst/algorithms/bundle.hpp — the exact bundle number of a triangulation (Boyacı, Erten, Üngör,
// "Triangulations Loosing Bundles and Weight").
//
// k triangles form a k-bundle if their interiors all meet one open disk that contains no vertex of
// the triangulation; the bundle number of a triangulation T (Delaunay or not, of any domain, with
// holes) is the largest such k. V is the set of vertices of the counted triangles (for a Mesh: of
// its in-domain triangles); the disk may extend anywhere else, through holes and concavities. The
// maximum is taken over the pencils of disks through the edges of DT(V), the Delaunay
// triangulation of all of V; circumdisks alone give only a lower bound. Every combinatorial
// decision is exact, except that a pencil circle tangent to an edge's interior (an irrational
// threshold) is ordered against the others by its rounded value; the witness disk is rounded to
// double. Cost: O(n log n) in practice, on several threads. docs/algorithms/bundle-number.md
// describes the method, its exactness and its cost.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

#include "mwst/geometry/geometry.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst {

struct BundleOptions {
  // Fill BundleResult::per_triangle: for every triangle, the largest bundle it belongs to (the
  // largest number of triangles met by one vertex-empty open disk that meets it). What bundle
  // removal (BRH) asks of a skinny triangle.
  bool per_triangle = false;
  // Worker threads (0: std::thread::hardware_concurrency()). Small inputs run on one thread. The
  // result does not depend on the number of threads.
  unsigned threads = 0;
  // bundle_number(Mesh) throws KBundleTimeout once this passes (time_point::max(): never).
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  // 0: no budget, the exact answer whatever it costs. Otherwise the most (circumdisk, triangle)
  // candidate pairs kept (4 bytes each; at least one per circumdisk), which bounds memory and
  // time: each circumdisk's list is first capped at an equal share of the budget, then the lists cut short get equal shares of
  // what is left. If a list is still cut short (a circumdisk meeting that many triangles: points on
  // a circle, where every circumdisk is about the whole circle and meets about every triangle),
  // BundleResult::exact may be false and the result holds exact bounds instead (see there). When
  // no list is cut short the result is the exact one, the same as without a budget. Ignored with
  // per_triangle.
  std::size_t candidate_budget = 0;
};

struct BundleResult {
  std::uint32_t bundle_number = 0;  // 0 only for an empty triangulation; lower_bound if !exact
  // With a candidate budget (BundleOptions::candidate_budget) that cuts some list short:
  // lower_bound ≤ the bundle number ≤ upper_bound, both exact; exact is true if they meet. The
  // pencils with no list cut short are swept exactly; the lower bound is the best of those and of
  // a few circumdisks cut short counted in full (one flood each, no list kept); the witness below
  // is then its disk and triangles. The upper bound: per pencil not swept, the number of triangles
  // whose bounding boxes meet a box holding its two circumdisks (all its disks lie in their union),
  // the pencils of the largest such bounds swept exactly within the budget (which may also raise
  // the lower bound); see docs/algorithms/bundle-number.md, "Budget". Without a cut: exact,
  // lower_bound = upper_bound = bundle_number.
  bool exact = true;
  std::uint32_t lower_bound = 0, upper_bound = 0;
  std::size_t truncated_disks = 0;  // circumdisks whose lists were cut short
  // A witness: an open disk (centre and radius rounded to double) containing no vertex and meeting
  // the interiors of bundle_number triangles, and those triangles (ascending; Mesh version: triangle
  // slots; triangle-list version: indices into the list). Radius 0 if there is no triangle.
  Point disk_center;
  double disk_radius = 0.0;
  std::vector<std::uint32_t> triangles;
  // The largest number of triangles met by a circumdisk of a triangle of DT(V): the lower bound a
  // circumdisk-only check gives (≤ bundle_number). Read off the ends of the pencils swept; for the
  // pencils skipped (see `pencils` below) counted as circumdisk_bundle_per_triangle() counts.
  // (Without `exact`: the largest found, itself a lower bound.)
  std::uint32_t circumdisk_bound = 0;
  // If BundleOptions::per_triangle: indexed like `triangles` above (Mesh: by slot, 0 for slots that
  // are not in the domain; list: by index).
  std::vector<std::uint32_t> per_triangle;
  // Work done: pencils (Delaunay edges of V; cocircular diagonals excluded), (pencil, triangle)
  // candidate pairs, threshold comparisons that needed exact arithmetic. Without per_triangle, a
  // pencil with no more candidates than the best count found so far is not swept (it cannot beat
  // it); which pencils those are depends on the number of threads, so these counters do too (the
  // results above do not).
  std::size_t pencils = 0;
  std::size_t candidate_pairs = 0;
  // Distinct circumdisks of Delaunay triangles whose candidate lists were built: the Delaunay
  // triangles of one circle (cocircular vertices) share one disk and one list (1 for points on a
  // circle).
  std::size_t disks = 0;
  std::size_t exact_comparisons = 0;
};

// The bundle number of the in-domain triangles of `mesh` (Mesh::in_domain). The mesh must be valid
// (validate()): its carved-away and ghost triangles are used to walk across holes and concavities.
MWST_API BundleResult bundle_number(const Mesh& mesh, const BundleOptions& options = {});

// The bundle number of a triangulation given as a triangle list (what `mwst bundle` reads from
// PREFIX.node/.ele): triangles are vertex index triples, either orientation. Throws InputError if an
// index is out of range, a triangle is degenerate (collinear corners) or repeated, two used points
// coincide, or the triangles overlap (crossing edges, or a vertex inside another triangle or on
// another triangle's edge). Points not used by any triangle are ignored.
MWST_API BundleResult bundle_number(const std::vector<Point>& points,
                           const std::vector<std::array<std::uint32_t, 3>>& triangles,
                           const BundleOptions& options = {});
// The same, taking the points and triangles over: they are freed as soon as they are copied, so
// that a million-triangle input is held once, not twice (`mwst bundle`).
MWST_API BundleResult bundle_number(std::vector<Point>&& points, std::vector<std::array<std::uint32_t, 3>>&& triangles,
                                    const BundleOptions& options = {});

// The cheap variant for bundle removal: for every triangle slot of `mesh`, the largest number of
// in-domain triangles met by a circumdisk of a triangle of DT(V) that meets it (0 for slots not in
// the domain). A lower bound of BundleResult::per_triangle (circumdisks are the ends of the
// pencils); no pencil sweep, so several times faster. Exact: whether a triangle edge crosses a
// circumdisk between two corners outside it is a degree-8 sign, decided by a filter with rigorous
// error bounds and otherwise in integer arithmetic (GMP) — the flat Delaunay triangles of nearly
// collinear hull vertices have circumdisks of radius 10¹⁷ that rounding cannot place.
MWST_API std::vector<std::uint32_t> circumdisk_bundle_per_triangle(const Mesh& mesh, unsigned threads = 0);

// What in_k_bundle did.
struct KBundleStats {
  std::size_t flooded = 0;                 // Delaunay triangles whose candidate lists were built
  std::size_t disks_counted = 0;           // circumdisks counted up to k (the first stage)
  std::size_t seed_fan_steps = 0;          // first stage: Delaunay triangles around the seed corners walked
  std::size_t flood_visits = 0;            // mesh triangles the floods of both stages popped
  std::size_t decided_by_circumdisks = 0;  // queries met by a circumdisk meeting ≥ k triangles
  std::size_t decided_by_hints = 0;        // of them, by the Delaunay triangle of KBundleCache::hints
  std::size_t decided_by_bound = 0;        // queries no pencil of which could reach k candidates
  std::size_t decided_by_pencils = 0;      // queries found in a k-bundle by the pencil sweep
  std::size_t pencils_swept = 0;
  std::size_t pencils_reused = 0;  // of those, answered from a KBundleCache
  std::size_t pencils_one_sided = 0;  // of those, swept from one list and a lens (over DT(V))
  std::size_t lens_visits = 0;        // mesh triangles the lens floods of those popped
  std::size_t candidate_pairs = 0;    // (pencil, candidate triangle) pairs the sweeps classified
  bool local = false;  // answered from the Delaunay triangulation of the vertices near the queries
  bool kept_dt = false;  // DT(V) was a KBundleCache's, with the vertices added since inserted
};

// For each in-domain triangle slot in `queries`: does it belong to a k-bundle (some vertex-empty
// open disk meeting it meets at least k in-domain triangles)? 1 or 0, in the order of `queries`
// (0 for slots not in the domain). Exactly as BundleResult::per_triangle[t] >= k, but it looks only
// near the queries, and it stops counting at k. First, per query, the Delaunay triangles whose
// circumdisks meet it (S(t)) are walked until one is found whose circumdisk meets the query and at
// least k triangles — counted by a flood that stops at k, once per Delaunay triangle — which
// decides: O(k) per query even where every circumdisk meets most of the mesh (points on a circle
// or an ellipse). For the queries left, the pencils of the edges of S(t) are swept (a disk of a
// pencil meets the query only if one of its ends does); their ends are flooded in full, except an
// end meeting k triangles or more (it meets no query left): a pencil with one such end is swept
// from its other end's list and the lens of the large end next to the edge, flooded until it
// counts k (one-sided pencils), one with two is not swept. (Over the DT(W) of the local attempt,
// S(t) and its neighbours are flooded in full, and the pencils of edges of S(t) whose two lists
// hold at least k triangles are swept.) With few queries (fewer than 1/256 of the triangle slots) it first tries the Delaunay triangulation of
// the vertices within 12 rings of mesh triangles around them instead of DT(V), over a copy of the
// mesh region around them (those rings and every triangle around their vertices; 32 rings if a
// flood would leave it, then the whole mesh), so in time proportional to the region, not to the
// mesh; it uses it only if every Delaunay triangle it needs has a vertex-empty circumdisk (so is
// one of DT(V)); otherwise it builds DT(V) over the whole mesh. The answer is the same either way. What bundle removal (BRH) asks of its
// skinny triangles.
//
// A pencil sweep's result (for each candidate triangle, the largest count of a disk of the pencil
// meeting it) is a function of the pencil's edge pq, the apices of its two Delaunay triangles and
// the candidate triangles (their vertices); `cache`, if given, keeps the results of the larger
// pencils of one call, keyed by exactly those (mesh vertex ids), and the next call reuses a result
// whose key matches in full, instead of sweeping again. Across BRH's passes the mesh changes only
// near its splits, so most pencils, e.g. those of the flat circumdisks along the hull of a point
// set, come back unchanged. The answers are the same with or without it.
class MWST_API KBundleCache {
 public:
  KBundleCache();
  ~KBundleCache();
  KBundleCache(const KBundleCache&) = delete;
  KBundleCache& operator=(const KBundleCache&) = delete;
  // After a call that used the cache: per query answered 0 (in the order of `queries`), a box (x0,
  // y0, x1, y1; closed) holding every mesh triangle that meets some vertex-empty open disk meeting
  // the query (a query answered 1 gets the box of its own corners). A query answered 0 stays 0 while its triangle, the vertices and the triangles meeting
  // this box are unchanged, and the hull is (bundle removal relies on it between its passes: a
  // disk putting it in a k-bundle after a change must meet a triangle made by the change).
  std::vector<std::array<double, 4>> reach;
  // Witnesses, in and out (used with or without reuse_sweeps). `hints`, if it holds one entry per
  // query: the corners (mesh vertex ids; kNone: no hint) of a Delaunay triangle whose circumdisk
  // decided that query in an earlier call. A query whose hint is still a triangle of DT(V) (its
  // disk still vertex-empty), whose circumdisk still meets k triangles or more and meets the query
  // (all decided exactly, as in the first stage) is answered 1 without walking S(t). It is the
  // answer the walk would give (the question is exact), at O(k) instead of the walk's cost.
  // `witnesses` (set by every call): per query, the corners of the Delaunay triangle whose
  // circumdisk answered it 1 in the first stage, or kNone (answered 0, or by the pencils).
  std::vector<std::array<VertexId, 3>> hints;
  std::vector<std::array<VertexId, 3>> witnesses;
  // False: the call neither reuses nor keeps sweeps, nor sets `reach`; it only keeps (and reuses)
  // DT(V). A call over the whole mesh keeps DT(V) here, and the next such call inserts only the
  // vertices added since (Lawson flips keep it Delaunay) if every vertex it holds is still a
  // vertex of T at the same place; otherwise it builds DT(V) again.
  bool reuse_sweeps = true;
  // False (with reuse_sweeps): `reach` is set, but no sweep is reused or kept (a call whose sweeps
  // would seldom come back: keeping them costs memory, ~40% of BRH's peak on 160k polygons).
  bool keep_sweeps = true;
  // False (with reuse_sweeps): a call that answers no query 1 leaves every `reach` box empty
  // (nothing known) instead of computing them. A caller that refines only where a query was
  // answered 1 has no use for them then: bundle removal stops when its exact test finds nothing,
  // and that test is the only one on most inputs (holes, circle, ellipse at 160k: ~0.15 s of CPU).
  bool reach_when_all_no = true;
  struct Impl;
  std::unique_ptr<Impl> impl;
};

// Thrown by in_k_bundle when its deadline passes before it has answered (the cache then holds
// nothing of the call).
struct MWST_API KBundleTimeout : std::runtime_error {
  KBundleTimeout() : std::runtime_error("in_k_bundle: the deadline passed") {}
};

// `deadline`: bundle removal's time budget. On meshes of thousands of slivers (inputs whose
// segments cross thousands of times), every disk meets most of the mesh and nearly every test is
// near-degenerate, and one call can take many seconds; past the deadline it throws KBundleTimeout
// instead of answering.
MWST_API std::vector<std::uint8_t> in_k_bundle(const Mesh& mesh, std::uint32_t k, const std::vector<TriangleId>& queries,
                                      KBundleStats* stats = nullptr, unsigned threads = 0,
                                      KBundleCache* cache = nullptr,
                                      std::chrono::steady_clock::time_point deadline =
                                          std::chrono::steady_clock::time_point::max());

}  // namespace mwst
