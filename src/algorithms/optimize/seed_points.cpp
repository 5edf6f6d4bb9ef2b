// Seeded starting meshes for the optimiser (seed_points.hpp): Steiner points put where a light
// Steiner triangulation of a polygon tends to have them, before the local search moves, keeps or
// removes each.
//
// Where a domain is a strip between two boundary chains, a triangulation without Steiner points
// zig-zags across it (every edge about as long as the strip is wide), while one with Steiner
// points along the strip's middle joins each boundary vertex to the middle (half the width) —
// nearly half the weight when the boundary vertices are dense. The middle of a polygon is its
// medial axis; the circumcenters of its constrained Delaunay triangles are the vertices of the
// (constrained) Voronoi diagram of its boundary vertices, which approximate that axis, and a CDT
// triangle none of whose edges is on the domain boundary sits where the axis branches. The
// centroids of all triangles are a denser, unbiased seed. The search after it decides; these are
// only diverse starting points, which the partition crossover (crossover.cpp) then combines.
#include "algorithms/optimize/seed_points.hpp"

#include <cmath>
#include <vector>

#include "algorithms/optimize/separation.hpp"
#include "mwst/geometry/geometry.hpp"

namespace mwst {

std::size_t seed_steiner_points(Mesh& mesh, SeedPoints which) {
  // An edge is on the domain boundary if it is a subsegment or the triangle across it is not in
  // the domain (a carved triangle, or a ghost beyond a hull edge).
  auto on_boundary = [&](Handle h) { return mesh.is_segment(h) || !mesh.in_domain(triangle_of(mesh.sym(h))); };
  std::vector<Point> seeds;
  for (TriangleId t = 0; t < mesh.triangle_slots(); ++t) {
    if (!mesh.in_domain(t)) continue;
    const auto& v = mesh.triangles[t].v;
    const Point& a = mesh.point(v[0]);
    const Point& b = mesh.point(v[1]);
    const Point& c = mesh.point(v[2]);
    if (which == SeedPoints::kJunctionCircumcenters) {
      if (on_boundary(make_handle(t, 0)) || on_boundary(make_handle(t, 1)) || on_boundary(make_handle(t, 2))) {
        continue;
      }
      seeds.push_back(circumcenter(a, b, c));
    } else {
      seeds.push_back(Point{(a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0});
    }
  }
  // Insert each seed that lies strictly inside an in-domain triangle (a circumcenter may lie beyond
  // the boundary or on an edge; a rounded centroid of a needle may fall on an edge: skipped) and
  // is separated as the optimiser's own insertions are (OptimizeOptions::min_separation: here
  // default_min_separation of the mesh given, the same as opt's when it is the input's CDT).
  const double separation = default_min_separation(mesh);
  std::vector<Handle> beyond;
  std::size_t inserted = 0;
  Handle hint = kNone;
  for (const Point& p : seeds) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
    const Location where = mesh.locate(p, hint);
    if (where.kind != Location::Kind::kInTriangle || !mesh.in_domain(triangle_of(where.handle))) continue;
    const TriangleId t = triangle_of(where.handle);
    beyond.assign({mesh.sym(make_handle(t, 0)), mesh.sym(make_handle(t, 1)), mesh.sym(make_handle(t, 2))});
    if (separation > 0.0 && !point_is_separated(mesh, p, beyond, separation)) continue;
    const VertexId v = mesh.add_vertex(p, VertexKind::kSteiner);
    mesh.insert_vertex(v, where.handle, &hint);
    ++inserted;
  }
  return inserted;
}

}  // namespace mwst
