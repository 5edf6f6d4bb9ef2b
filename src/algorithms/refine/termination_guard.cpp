// src/algorithms/refine/termination_guard.cpp — the termination guard of Delaunay refinement
// (refine.hpp: feature_guard_length; the stop StopKind::kBeyondFeatureSize).
//
// Delaunay refinement provably terminates only for angle bounds up to
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
#include "algorithms/refine/refiner.hpp"

#include <limits>

namespace mwst {

namespace refinement {

namespace {

// The termination guard (Refiner::set_feature_guard): an angle-bad triangle whose shortest edge is
// below this fraction of the input's smallest feature stops the refinement. Measured on the 13
// data sets, 10k points on a circle and on an ellipse, at 5° to 33° with both rules: no triangle
// split had a shortest edge below 0.41 of the smallest feature (0.0025 at 34° with circumcenters,
// a run of 17 s); the runaways tried (a 1° spike at 38° to 55°, a unit square at 50°, data sets
// and 10k points on a circle at 37° to 55°) stop within a second.
constexpr double kFeatureGuardFraction = 1.0 / 1024.0;

}  // namespace

void Refiner::set_feature_guard() {
  if (opt_.feature_guard_length >= 0.0 || custom_test_ || alpha_ <= 0.0) return;  // given, or none
  const double length = feature_guard_length(m_, max_area_);
  guard_length2_ = length * length;
}

}  // namespace refinement

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
  return std::sqrt(smallest2) * refinement::kFeatureGuardFraction;
}

}  // namespace mwst
