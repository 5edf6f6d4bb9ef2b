// The exact bundle number of a mesh read from Triangle's files PREFIX.node and PREFIX.ele: the
// largest number of triangles one vertex-empty open disk meets, with that disk as the witness.
#include <cstdio>
#include <string>

#include <mwst/algorithms/bundle.hpp>
#include <mwst/error.hpp>
#include <mwst/io/triangle_files.hpp>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s PREFIX   (reads PREFIX.node and PREFIX.ele)\n", argv[0]);
    return 2;
  }
  try {
    const mwst::io::MeshFiles mesh = mwst::io::read_mesh(argv[1]);
    const mwst::BundleResult bundle = mwst::bundle_number(mesh.points, mesh.triangles);
    std::printf("%zu triangles: bundle number %u\n", mesh.triangles.size(), bundle.bundle_number);
    std::printf("witness: the disk centred (%.17g, %.17g) of radius %.17g meets triangles", bundle.disk_center.x,
                bundle.disk_center.y, bundle.disk_radius);
    for (const std::uint32_t t : bundle.triangles) std::printf(" %u", t + 1);  // numbered as in PREFIX.ele
    std::printf("\n");
  } catch (const mwst::InputError& e) {
    std::fprintf(stderr, "%s\n", e.located().c_str());
    return 1;
  }
  return 0;
}
