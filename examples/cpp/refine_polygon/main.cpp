// A polygon with holes (a Triangle .poly file) refined until every angle is at least 25 degrees,
// printing the weight of the result: its total edge length, split into boundary and interior.
#include <cstdio>
#include <exception>

#include <mwst/error.hpp>
#include <mwst/io/triangle_files.hpp>
#include <mwst/algorithms/pipeline.hpp>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s POLYGON.poly\n", argv[0]);
    return 2;
  }
  try {
    const mwst::Pslg polygon = mwst::io::read_poly(argv[1]);
    mwst::TriangulateOptions options;
    options.method = mwst::Method::kDr;  // Delaunay refinement (off-centers)
    options.min_angle_deg = 25.0;
    const mwst::Report report = mwst::triangulate(polygon, options);
    std::printf("%zu holes, %zu triangles, %zu Steiner points, angles %.3f to %.3f degrees\n",
                polygon.holes.size(), report.triangles, report.steiner, report.min_angle, report.max_angle);
    std::printf("weight %.6f = boundary %.6f + interior %.6f\n", report.weight_total, report.weight_boundary,
                report.weight_interior);
  } catch (const mwst::InputError& e) {
    std::fprintf(stderr, "%s\n", e.located().c_str());
    return 1;
  }
  return 0;
}
