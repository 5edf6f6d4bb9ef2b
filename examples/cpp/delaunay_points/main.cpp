// The Delaunay triangulation of a point array, handed back as flat index arrays.
#include <cstdio>

#include <mwst/algorithms/arrays.hpp>
#include <mwst/geometry/geometry.hpp>

int main() {
  mwst::Pslg input;  // points only: the Delaunay triangulation of their convex hull
  input.points = {{0, 0}, {3, 0}, {3, 2}, {0, 2}, {1, 1}, {2, 1.2}};
  const mwst::MeshArrays dt = mwst::triangulate_arrays(input, mwst::TriangulateOptions{});

  std::printf("%zu vertices, %zu triangles\n", dt.vertex_count(), dt.triangle_count());
  double area = 0.0;
  for (std::size_t t = 0; t < dt.triangle_count(); ++t) {
    const std::uint32_t* v = &dt.triangles[3 * t];  // counter-clockwise
    const std::int32_t* n = &dt.neighbours[3 * t];  // across the edge opposite v[i]; -1: hull
    std::printf("triangle %zu: vertices %u %u %u, neighbours %d %d %d\n", t, v[0], v[1], v[2], n[0], n[1],
                n[2]);
    const auto point = [&](std::uint32_t i) { return mwst::Point{dt.vertices[2 * i], dt.vertices[2 * i + 1]}; };
    area += mwst::signed_area(point(v[0]), point(v[1]), point(v[2]));
  }
  std::printf("area %g\n", area);  // the convex hull's: 6
  return 0;
}
