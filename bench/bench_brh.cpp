// bench/bench_brh.cpp — time of the bundle removal heuristic (BRH, src/algorithms/refine/brh.cpp; Boyacı,
// Erten, Üngör, "Triangulations Loosing Bundles and Weight") against Delaunay refinement (DR,
// src/algorithms/refine/refine.cpp) at the same angle bound A, on an input where DR makes about 1M
// triangles. The target: BRH at most 3× DR's time.
//
// Input: the unit square holding N uniform random points (default N = 320000: DR at 20° makes about
// 1M triangles), or a .poly/.node file. Both methods start from the same constrained Delaunay
// triangulation, built before the clock starts; each run happens in a forked child (CPU seconds of
// all threads, and the peak memory the run added, bench_common.hpp). BRH is run with the default
// K = ⌈4π/A⌉ + 3 and with smaller K, where it splits more.
//
// Usage: bench_brh [--n N] [--input FILE] [--angle A] [--k K]... [--repeats R]
#include <time.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "bench_common.hpp"
#include "mwst/algorithms/brh.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/algorithms/pipeline.hpp"
#include "mwst/algorithms/refine.hpp"

namespace {

using namespace mwst;

double cpu_now() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double wall_now() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

struct Result {
  double cpu = 0, wall = 0, peak_mib = 0, triangles = 0, steiner = 0, rounds = 0, exact = 0, skinny_left = 0, ok = 0;
};

// Runs fn in a forked child `repeats` times: the run with the best CPU time (its wall time), the
// largest peak.
template <class Fn>
Result run_forked(Fn fn, int repeats) {
  Result best;
  best.cpu = 1e300;
  for (int r = 0; r < repeats; ++r) {
    int fds[2];
    if (pipe(fds) != 0) return {};
    std::fflush(stdout);
    const pid_t pid = fork();
    if (pid == 0) {
      close(fds[0]);
      Result res;
      try {
        malloc_trim(0);
        bench::reset_peak_rss();
        const long before = bench::status_kib("VmRSS");
        res = fn();
        res.peak_mib = static_cast<double>(bench::status_kib("VmHWM") - before) / 1024.0;
        res.ok = 1;
      } catch (const std::exception& e) {
        std::fprintf(stderr, "child failed: %s\n", e.what());
      }
      if (write(fds[1], &res, sizeof res) != static_cast<ssize_t>(sizeof res)) _exit(2);
      _exit(0);
    }
    close(fds[1]);
    Result res;
    const ssize_t got = read(fds[0], &res, sizeof res);
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    if (got != static_cast<ssize_t>(sizeof res) || res.ok == 0) return {};
    const double peak = std::max(best.peak_mib, res.peak_mib);
    if (res.cpu < best.cpu) best = res;
    best.peak_mib = peak;
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t n = 320000;
  std::string input;
  double angle = 20.0;
  std::vector<std::size_t> ks;
  int repeats = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&] { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
    if (a == "--n") {
      n = std::strtoull(value().c_str(), nullptr, 10);
    } else if (a == "--input") {
      input = value();
    } else if (a == "--angle") {
      angle = std::strtod(value().c_str(), nullptr);
    } else if (a == "--k") {
      ks.push_back(std::strtoull(value().c_str(), nullptr, 10));
    } else if (a == "--repeats") {
      repeats = std::max(1, std::atoi(value().c_str()));
    } else {
      std::fprintf(stderr, "usage: bench_brh [--n N] [--input FILE] [--angle A] [--k K]... [--repeats R]\n");
      return 2;
    }
  }
  if (ks.empty()) ks = {default_bundle_k(angle), 8, 6};

  Pslg g;
  std::string name;
  if (input.empty()) {
    g.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const auto inner = bench::uniform_points(n, 7);
    g.points.insert(g.points.end(), inner.begin(), inner.end());
    for (std::uint32_t i = 0; i < 4; ++i) g.segments.push_back({i, (i + 1) % 4, 1});
    g.is_poly = true;
    name = "unit square + " + std::to_string(n) + " uniform points";
  } else {
    g = io::read_input(input);
    name = input;
  }
  const Mesh cdt = constrained_delaunay(g);
  const double input_vertices = static_cast<double>(cdt.points.size());
  std::printf("# %s: %zu CDT triangles; %s\n", name.c_str(), cdt.domain_triangle_count(),
              bench::hardware_line().c_str());

  const Result dr = run_forked(
      [&] {
        Mesh m = cdt;
        RefineOptions o;
        o.min_angle_deg = angle;
        const double c0 = cpu_now(), w0 = wall_now();
        refine(m, o);
        Result r;
        r.cpu = cpu_now() - c0;
        r.wall = wall_now() - w0;
        r.triangles = static_cast<double>(m.domain_triangle_count());
        r.steiner = static_cast<double>(m.points.size()) - input_vertices;
        return r;
      },
      repeats);

  std::printf("\n| method | A | K | triangles | Steiner points | rounds (exact) | skinny left | CPU s | wall s | peak MiB | "
              "ratio to DR (CPU) |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  std::printf("| DR (refine) | %g | – | %.0f | %.0f | – | 0 | %.3f | %.3f | %.1f | 1.00 |\n", angle, dr.triangles,
              dr.steiner, dr.cpu, dr.wall, dr.peak_mib);
  std::fflush(stdout);
  for (const std::size_t k : ks) {
    const Result b = run_forked(
        [&] {
          Mesh m = cdt;
          BrhOptions o;
          o.min_angle_deg = angle;
          o.bundle_k = k;
          const double c0 = cpu_now(), w0 = wall_now();
          const BrhStats s = bundle_removal(m, o);
          Result r;
          r.cpu = cpu_now() - c0;
          r.wall = wall_now() - w0;
          r.triangles = static_cast<double>(m.domain_triangle_count());
          r.steiner = static_cast<double>(m.points.size()) - input_vertices;
          r.rounds = static_cast<double>(s.rounds);
          r.exact = static_cast<double>(s.exact_evaluations);
          r.skinny_left = static_cast<double>(s.skinny_left);
          return r;
        },
        repeats);
    std::printf("| BRH%s | %g | %zu | %.0f | %.0f | %.0f (%.0f) | %.0f | %.3f | %.3f | %.1f | %.2f |\n",
                k == default_bundle_k(angle) ? " (default K)" : "", angle, k, b.triangles, b.steiner, b.rounds,
                b.exact, b.skinny_left, b.cpu, b.wall, b.peak_mib, b.cpu / dr.cpu);
    std::fflush(stdout);
  }
  return 0;
}
