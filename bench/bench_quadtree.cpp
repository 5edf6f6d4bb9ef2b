// bench/bench_quadtree.cpp — quadtree refinement (mwst::quadtree_refinement; Bern, Eppstein,
// Gilbert 1994, the QTR method of Boyacı, Erten, Üngör).
//
//   bench_quadtree                    growth: uniform points in the unit square, n = 1e4 … 1e6;
//                                     CPU and wall seconds, leaves, triangles, triangles per CPU
//                                     second, peak memory and bytes per triangle, and CPU time
//                                     over n·log2(n) + triangles (constant if the run time is
//                                     O(n log n + output), as BEG prove); CGAL's Delaunay
//                                     triangulation of the same points as a reference row, and
//                                     the first write of as much fresh memory as QTR's peak as
//                                     another (what the host charges for the pages alone)
//   bench_quadtree --max N            stop the growth table at N points
//   bench_quadtree --data DATA_DIR    the paper's data sets: Steiner points, triangles, interior
//                                     weight relative to the (constrained) Delaunay triangulation
//                                     (DT = 100, as the paper's Table 1), angle range, seconds
//
// Every run happens in a forked child (as bench_common.hpp does): the input is made before the
// clock starts; the child reports wall and CPU seconds and the memory it added at its peak. No
// public quadtree mesher exists to run beside it (the paper used Tripoint, which is not
// available; CGAL has none): CGAL's Delaunay triangulation of the same points is the reference row
// of the growth table, and the CDT of the same input the reference in the data-set table.
#include <time.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_common.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/algorithms/quadtree.hpp"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace {

using namespace mwst;
using CgalK = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalDt = CGAL::Delaunay_triangulation_2<CgalK>;

double cpu_now() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// What a child reports about one quadtree run.
struct Run {
  double wall = 0, cpu = 0, peak_mib = 0;
  double tree = 0, mesh = 0;  // wall seconds of the two main phases
  double leaves = 0, triangles = 0, steiner = 0, fallback = 0;
  double min_angle = 0, max_angle = 0, weight_interior = 0;
};

// Runs quadtree refinement of `g` in a forked child, `repeats` times; the best wall time.
bool run_forked(const Pslg& g, int repeats, Run& best) {
  best.wall = 1e300;
  for (int r = 0; r < repeats; ++r) {
    int fds[2];
    if (pipe(fds) != 0) return false;
    std::fflush(stdout);
    const pid_t pid = fork();
    if (pid == 0) {
      close(fds[0]);
      Run out;
      try {
        bench::Probe probe;
        const double c0 = cpu_now();
        probe.start();
        QuadtreeStats stats;
        const Mesh mesh = quadtree_refinement(g, {}, &stats);
        probe.stop();
        out.cpu = cpu_now() - c0;
        out.wall = probe.seconds();
        out.peak_mib = probe.added_peak_mib();
        out.tree = stats.seconds_tree;
        out.mesh = stats.seconds_mesh;
        out.leaves = static_cast<double>(stats.leaves);
        out.fallback = stats.fallback ? 1 : 0;
        const Metrics m = measure(mesh);
        out.triangles = static_cast<double>(m.triangles);
        out.steiner = static_cast<double>(m.steiner);
        out.min_angle = m.min_angle_deg;
        out.max_angle = m.max_angle_deg;
        out.weight_interior = m.weight_interior;
      } catch (const std::exception& e) {
        out.wall = -1;
        std::fprintf(stderr, "child failed: %s\n", e.what());
      }
      if (write(fds[1], &out, sizeof out) != static_cast<ssize_t>(sizeof out)) _exit(2);
      _exit(0);
    }
    close(fds[1]);
    Run got;
    const ssize_t n = read(fds[0], &got, sizeof got);
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    if (n != static_cast<ssize_t>(sizeof got) || got.wall < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      return false;
    }
    if (got.wall < best.wall) {
      const double peak = std::max(best.peak_mib, got.peak_mib);
      best = got;
      best.peak_mib = peak;
    } else {
      best.peak_mib = std::max(best.peak_mib, got.peak_mib);
    }
  }
  return true;
}

// CGAL's Delaunay triangulation of the same points (range insertion), the reference row: CGAL has no
// quadtree mesher (its Mesh_2 is Delaunay refinement, bench_refine compares with it).
bench::Measurement cgal_delaunay(const std::vector<Point>& pts, int repeats) {
  return bench::measure_forked(
      [&](bench::Probe& probe) {
        std::vector<CgalK::Point_2> input;
        input.reserve(pts.size());
        for (const Point& p : pts) input.emplace_back(p.x, p.y);
        probe.start();
        CgalDt dt(input.begin(), input.end());
        probe.stop();
        probe.set_count(dt.number_of_faces());
      },
      repeats);
}

// The host's cost of providing fresh memory, the second reference row: `mib` MiB (QTR's peak)
// mapped and written one byte per page, in a forked child. The kernel clears every page on its
// first write, and under a hypervisor that returns a guest's freed memory to the host, the host
// provides it again first (seen here: 1.6 µs per 4 KiB page, 4.4–6.5 s for 3 GiB, several times
// a bare machine's cost). QTR writes that much memory at least once, so this much of its time
// is the machine's, whatever the code does with the pages.
bench::Measurement first_touch(double mib, int repeats) {
  return bench::measure_forked(
      [&](bench::Probe& probe) {
        const auto bytes = static_cast<std::size_t>(mib * 1048576.0);
        static const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
        probe.start();
        void* at = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (at == MAP_FAILED) throw std::runtime_error("mmap failed");
        auto* bytes_at = static_cast<volatile unsigned char*>(at);
        for (std::size_t i = 0; i < bytes; i += page) bytes_at[i] = 1;
        probe.stop();
        ::munmap(at, bytes);
        probe.set_count(bytes / page);
      },
      repeats);
}

void growth(std::size_t max_n) {
  std::printf("Quadtree refinement of n uniform points in the unit square (%s)\n\n",
              bench::hardware_line().c_str());
  std::printf("| n | method | CPU s | wall s | tree s | mesh s | leaves | triangles | triangles / point | "
              "triangles / CPU s | peak MiB | bytes / triangle | CPU µs / (n log2 n + triangles) |\n");
  std::printf("|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  // (n, QTR wall, CGAL wall) for the ratios printed below the table: timings on one host move by
  // tens of percent from hour to hour, their ratio within one run much less.
  std::vector<std::array<double, 3>> ratios;
  for (const std::size_t n : {std::size_t{10000}, std::size_t{30000}, std::size_t{100000}, std::size_t{300000},
                              std::size_t{1000000}}) {
    if (n > max_n) break;
    Pslg g;
    g.points = bench::uniform_points(n, 42);
    const int repeats = n >= 300000 ? 1 : 3;
    Run r;
    if (!run_forked(g, repeats, r)) {
      std::printf("| %zu | mwst QTR | failed | | | | | | | | | | |\n", n);
      continue;
    }
    const double nd = static_cast<double>(n);
    const double work = nd * std::log2(nd) + r.triangles;
    std::printf("| %zu | mwst QTR | %.3f | %.3f | %.3f | %.3f | %.0f | %.0f | %.1f | %.3g | %.1f | %.0f | %.4f |%s\n",
                n, r.cpu, r.wall, r.tree, r.mesh, r.leaves, r.triangles, r.triangles / nd, r.triangles / r.cpu,
                r.peak_mib, r.peak_mib * 1048576.0 / r.triangles, 1e6 * r.cpu / work,
                r.fallback != 0 ? " (fallback)" : "");
    const bench::Measurement c = cgal_delaunay(g.points, repeats);
    if (c.ok) {
      const double t = static_cast<double>(c.count);
      std::printf("| %zu | CGAL DT2 (reference) | %.3f | %.3f | | | | %.0f | %.1f | %.3g | %.1f | %.0f | %.4f |\n", n,
                  c.best_cpu, c.best_seconds, t, t / nd, t / c.best_cpu, c.peak_mib, c.peak_mib * 1048576.0 / t,
                  1e6 * c.best_cpu / (nd * std::log2(nd) + t));
      ratios.push_back({nd, r.wall, c.best_seconds});
    }
    const bench::Measurement touch = first_touch(r.peak_mib, repeats);
    if (touch.ok) {
      std::printf("| %zu | first write of QTR's peak MiB (reference) | %.3f | %.3f | | | | | | | %.1f | | |\n", n,
                  touch.best_cpu, touch.best_seconds, r.peak_mib);
    }
    std::fflush(stdout);
  }
  std::printf("\nWall time of QTR over CGAL DT2's on the same points in this run:");
  for (const auto& [n, qtr, cgal] : ratios) std::printf(" n = %.0f: %.1f ×;", n, qtr / cgal);
  std::printf("\n");
}

void data_sets(const std::string& dir) {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    const auto ext = e.path().extension();
    if (ext == ".poly" || ext == ".node") files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  std::printf("Quadtree refinement of the data sets (%s)\n\n", bench::hardware_line().c_str());
  std::printf("| data | points | segments | Steiner | triangles | interior weight (DT = 100) | min angle | "
              "max angle | QTR s | CDT s |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const std::string& path : files) {
    const Pslg g = io::read_input(path);
    Run r;
    if (!run_forked(g, 3, r)) {
      std::printf("| %s | failed | | | | | | | | |\n", path.c_str());
      continue;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const Mesh dt = constrained_delaunay(g);
    const double cdt_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const Metrics md = measure(dt);
    std::printf("| %s | %zu | %zu | %.0f | %.0f | %.1f | %.2f | %.2f | %.4f | %.4f |%s\n",
                std::filesystem::path(path).filename().string().c_str(), g.points.size(), g.segments.size(),
                r.steiner, r.triangles, 100.0 * r.weight_interior / md.weight_interior, r.min_angle, r.max_angle,
                r.wall, cdt_seconds, r.fallback != 0 ? " (fallback)" : "");
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t max_n = 1000000;
  std::string data;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--max") == 0 && i + 1 < argc) {
      max_n = static_cast<std::size_t>(std::strtoull(argv[++i], nullptr, 10));
    } else if (std::strcmp(argv[i], "--data") == 0 && i + 1 < argc) {
      data = argv[++i];
    } else {
      std::fprintf(stderr, "usage: bench_quadtree [--max N] [--data DIR]\n");
      return 2;
    }
  }
  if (!data.empty()) {
    data_sets(data);
    return 0;
  }
  growth(max_n);
  return 0;
}
