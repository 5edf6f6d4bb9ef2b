// src/algorithms/optimize/exact_polish.cpp — the exact polish (exact_polish.hpp; off by default):
// the triangulation replaced by the exact minimum weight triangulation of its own vertices
// (exact_mwt, mwst/algorithms/mwt.hpp) whenever that is solved and lighter, then the search again.
#include "algorithms/optimize/exact_polish.hpp"

#include <utility>

#include "algorithms/optimize/optimizer.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/algorithms/mwt.hpp"

namespace mwst {

bool exact_polish_mesh(Mesh& mesh, const OptimizeOptions& options) {
  compact(mesh);
  if (mesh.points.size() > options.exact_polish_max_vertices) return false;
  MwtOptions mwt_options;
  mwt_options.diamond_route = true;
  mwt_options.max_visibility_vertices = options.exact_polish_visibility_vertices;
  mwt_options.max_candidate_edges = options.exact_polish_candidates_per_vertex * mesh.points.size();
  mwt_options.max_crossing_pairs = options.exact_polish_max_crossing_pairs;
  const double weight = measure(mesh).weight_total;
  MwtResult mwt = exact_mwt(mesh, mwt_options);
  if (!mwt.solved || !(mwt.weight < weight - options.min_relative_gain * weight)) return false;
  if (options.max_area > 0.0) {
    for (TriangleId t = 0; t < mwt.mesh.triangles.size(); ++t) {
      if (!mwt.mesh.in_domain(t)) continue;
      const auto& v = mwt.mesh.triangles[t].v;
      if (triangle_area(mwt.mesh.points[v[0]], mwt.mesh.points[v[1]], mwt.mesh.points[v[2]]) > options.max_area) {
        return false;
      }
    }
  }
  mesh = std::move(mwt.mesh);
  return true;
}

namespace opt {

// The exact polish: replace the triangulation by the MWT of its own vertices with its segments
// (same vertices, segments and markers, so the domain and the input vertices are unchanged; it
// excludes straight-angle slivers along segments, as EFH does) when it is solved and lighter by
// more than min_relative_gain, then the search and kicks again — relocations, removals and
// insertions now start from the lighter triangulation, and their local minimum is no heavier.
// Every step lowers the weight strictly, so the polished mesh is never heavier than before.
void Optimizer::exact_polish() {
  for (std::size_t round = 0; round < opt_.exact_polish_rounds && !out_of_time(); ++round) {
    if (!exact_polish_step()) return;
    local_search();
    kicks_and_search();
  }
}

// One exact MWT of the mesh's vertices within the size limits; true if it was kept (lighter).
bool Optimizer::exact_polish_step() {
  compact(m_);
  if (m_.points.size() > opt_.exact_polish_max_vertices) return false;
  ++stats_.exact_polish_tries;
  if (!exact_polish_mesh(m_, opt_)) return false;
  ++stats_.exact_polishes;
  return true;
}

}  // namespace opt

}  // namespace mwst
