// bench/bench_bundle.cpp — time of the exact bundle number (src/algorithms/bundle/bundle.cpp; Boyacı,
// Erten, Üngör, "Triangulations Loosing Bundles and Weight", k-bundles) on large meshes. The issue's
// target: the bundle number of a 1M-triangle refined mesh in under 10 s.
//
// Meshes: (1) the Delaunay triangulation of uniform random points (~2 triangles per point);
// (2) a Delaunay-refined mesh (mwst::refine, 20°, area bound chosen for the target size) of a data
// set with holes; (3) a randomly flipped (non-Delaunay) version of (1). For each: the full sweep,
// the sweep with per-triangle values (what bundle removal asks), and the cheap circumdisk variant.
// No peer exists: no other tool computes bundle numbers.
//
// Usage: bench_bundle [TRIANGLES] [DATA.poly]   (defaults 1000000 and data/Superior.poly)
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "mwst/algorithms/bundle.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/algorithms/refine.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// CPU seconds of the process so far, all threads (the machine may be shared: wall time alone can
// mislead).
double cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_utime.tv_sec) + 1e-6 * double(usage.ru_utime.tv_usec) + double(usage.ru_stime.tv_sec) +
         1e-6 * double(usage.ru_stime.tv_usec);
}

void run(const char* name, const mwst::Mesh& mesh) {
  const std::size_t triangles = mesh.domain_triangle_count();
  auto t0 = Clock::now();
  double c0 = cpu_seconds();
  const mwst::BundleResult r = mwst::bundle_number(mesh);
  const double full = seconds_since(t0), full_cpu = cpu_seconds() - c0;
  t0 = Clock::now();
  c0 = cpu_seconds();
  const mwst::BundleResult one = mwst::bundle_number(mesh, {.threads = 1});
  const double single = seconds_since(t0), single_cpu = cpu_seconds() - c0;
  t0 = Clock::now();
  c0 = cpu_seconds();
  const mwst::BundleResult rp = mwst::bundle_number(mesh, {.per_triangle = true});
  const double per = seconds_since(t0), per_cpu = cpu_seconds() - c0;
  t0 = Clock::now();
  c0 = cpu_seconds();
  const std::vector<std::uint32_t> cheap = mwst::circumdisk_bundle_per_triangle(mesh);
  const double circ = seconds_since(t0), circ_cpu = cpu_seconds() - c0;
  std::uint32_t per_max = 0;
  for (const std::uint32_t v : rp.per_triangle) per_max = v > per_max ? v : per_max;
  std::printf("%s: %zu triangles, bundle number %u (1 thread: %u; max per triangle %u), circumdisks %u\n", name,
              triangles, r.bundle_number, one.bundle_number, per_max, r.circumdisk_bound);
  std::printf("  %-34s %7.2f s wall %7.2f s cpu\n", "bundle_number (all threads)", full, full_cpu);
  std::printf("  %-34s %7.2f s wall %7.2f s cpu\n", "bundle_number (1 thread)", single, single_cpu);
  std::printf("  %-34s %7.2f s wall %7.2f s cpu\n", "with per-triangle values", per, per_cpu);
  std::printf("  %-34s %7.2f s wall %7.2f s cpu\n", "circumdisk_bundle_per_triangle", circ, circ_cpu);
  std::printf("  pencils %zu, candidate pairs %zu (%.1f per pencil), exact comparisons %zu\n", rp.pencils,
              rp.candidate_pairs, double(rp.candidate_pairs) / double(rp.pencils ? rp.pencils : 1),
              rp.exact_comparisons);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t target = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 1000000;
  // Default data set: found from this file's own path (…/bench/bench_bundle.cpp → …/data/).
  std::string source_dir = __FILE__;
  const std::size_t bench_at = source_dir.rfind("bench/");
  source_dir = bench_at == std::string::npos ? std::string() : source_dir.substr(0, bench_at);
  const std::string poly = argc > 2 ? argv[2] : source_dir + "data/Superior.poly";

  {  // (1) Delaunay of uniform points.
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<mwst::Point> pts(target / 2);
    for (auto& p : pts) p = {u(rng), u(rng)};
    mwst::Mesh mesh = mwst::delaunay(pts);
    run("delaunay uniform", mesh);

    // (3) The same, randomly flipped: not Delaunay.
    std::uniform_int_distribution<std::size_t> pick(0, mesh.triangle_slots() - 1);
    for (std::size_t k = 0; k < target; ++k) {
      const auto t = static_cast<mwst::TriangleId>(pick(rng));
      if (!mesh.in_domain(t)) continue;
      const mwst::Handle h = mwst::make_handle(t, static_cast<unsigned>(rng() % 3));
      if (!mesh.in_domain(mwst::triangle_of(mesh.sym(h)))) continue;
      const mwst::Point& a = mesh.points[mesh.org(h)];
      const mwst::Point& b = mesh.points[mesh.dest(h)];
      const mwst::Point& c = mesh.points[mesh.apex(h)];
      const mwst::Point& d = mesh.points[mesh.apex(mesh.sym(h))];
      if (mwst::orient2d(d, c, a) * mwst::orient2d(d, c, b) < 0) mesh.flip(h);
    }
    run("delaunay uniform, flipped", mesh);
  }

  {  // (2) A refined mesh of a domain with holes.
    const mwst::Pslg pslg = mwst::io::read_input(poly);
    const mwst::Mesh cdt = mwst::constrained_delaunay(pslg);
    const double area = mwst::measure(cdt).area;
    double max_area = 2.0 * area / double(target);
    mwst::Mesh mesh;
    for (int attempt = 0; attempt < 4; ++attempt) {
      mesh = cdt;
      mwst::RefineOptions options;
      options.min_angle_deg = 20.0;
      options.max_area = max_area;
      const auto t0 = Clock::now();
      mwst::refine(mesh, options);
      const std::size_t n = mesh.domain_triangle_count();
      std::printf("refine %s to %zu triangles in %.2f s\n", poly.c_str(), n, seconds_since(t0));
      if (n >= target * 9 / 10) break;
      max_area *= 0.9 * double(n) / double(target);
    }
    run("refined (20 deg, area bound)", mesh);
  }
  return 0;
}
