// bench/bench_refine.cpp — Delaunay refinement (mwst::refine) against CGAL's
// refine_Delaunay_mesh_2 in the same run, and the quality measurements behind refine's choices.
//
//   bench_refine                 speed: 20° refinement of the unit square holding 100k uniform
//                                points, mwst and CGAL side by side; then the --max-area refinement
//                                of the unit square to about 15M triangles (mwst; CGAL too with
//                                --cgal-large, which takes minutes)
//   bench_refine --n N --large-triangles T   other sizes
//   bench_refine --quality DATA_DIR          weight and Steiner tables over the data sets: both
//                                Steiner rules at several bounds, off-center factors, lens versus
//                                circle, shortest-edge-first versus worst-quality-first
//
// Every speed run happens in a forked child (bench_common.hpp): wall and CPU seconds of the
// refinement alone (the CDT is built before the clock starts, for both libraries) and of the whole
// (CDT + refinement), and the peak memory the child added. CGAL's angle criterion is
// B = sin²(α) (Delaunay_mesh_size_criteria_2; B = 0.125 is its 20.7° default).
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <time.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "bench_common.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/algorithms/refine.hpp"

namespace {

using namespace mwst;

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Delaunay_mesh_vertex_base_2<K>;
using Fb = CGAL::Delaunay_mesh_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Cdt>;

double cpu_now() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}
double wall_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// What a child reports.
struct Result {
  double wall_refine = 0, cpu_refine = 0, wall_total = 0, cpu_total = 0, peak_mib = 0;
  double triangles = 0, vertices = 0, ok = 0;
};

// Runs fn in a forked child, best of `repeats` by refinement CPU time; the largest peak.
Result run_forked(const std::function<Result()>& fn, int repeats) {
  Result best;
  best.cpu_refine = 1e300;
  for (int r = 0; r < repeats; ++r) {
    int fds[2];
    if (pipe(fds) != 0) return {};
    std::fflush(stdout);
    const pid_t pid = fork();
    if (pid == 0) {
      close(fds[0]);
      Result res;
      try {
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
    if (res.cpu_refine < best.cpu_refine) {
      const double peak = std::max(best.peak_mib, res.peak_mib);
      best = res;
      best.peak_mib = peak;
    } else {
      best.peak_mib = std::max(best.peak_mib, res.peak_mib);
    }
  }
  return best;
}

Pslg square_with_points(std::size_t n, std::uint64_t seed) {
  Pslg g;
  g.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const auto inner = bench::uniform_points(n, seed);
  g.points.insert(g.points.end(), inner.begin(), inner.end());
  for (std::uint32_t i = 0; i < 4; ++i) g.segments.push_back({i, (i + 1) % 4, 1});
  g.is_poly = true;
  return g;
}

Result run_mwst(const Pslg& g, const RefineOptions& options) {
  Result r;
  const double w0 = wall_now(), c0 = cpu_now();
  Mesh mesh = constrained_delaunay(g);
  const double w1 = wall_now(), c1 = cpu_now();
  refine(mesh, options);
  const double w2 = wall_now(), c2 = cpu_now();
  r.wall_refine = w2 - w1;
  r.cpu_refine = c2 - c1;
  r.wall_total = w2 - w0;
  r.cpu_total = c2 - c0;
  r.triangles = static_cast<double>(mesh.domain_triangle_count());
  r.vertices = static_cast<double>(mesh.points.size());
  return r;
}

Result run_cgal(const Pslg& g, double min_angle_deg, double max_edge) {
  Result r;
  const double w0 = wall_now(), c0 = cpu_now();
  Cdt cdt;
  std::vector<K::Point_2> pts;
  pts.reserve(g.points.size());
  for (const auto& p : g.points) pts.emplace_back(p.x, p.y);
  cdt.insert(pts.begin(), pts.end());
  for (const auto& s : g.segments) cdt.insert_constraint(pts[s.a], pts[s.b]);
  const double w1 = wall_now(), c1 = cpu_now();
  const double s = std::sin(min_angle_deg * std::numbers::pi / 180.0);
  CGAL::refine_Delaunay_mesh_2(cdt, Criteria(s * s, max_edge));
  const double w2 = wall_now(), c2 = cpu_now();
  r.wall_refine = w2 - w1;
  r.cpu_refine = c2 - c1;
  r.wall_total = w2 - w0;
  r.cpu_total = c2 - c0;
  std::size_t faces = 0;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) faces += f->is_in_domain() ? 1 : 0;
  r.triangles = static_cast<double>(faces);
  r.vertices = static_cast<double>(cdt.number_of_vertices());
  return r;
}

void print_speed_header(const char* title) {
  std::printf("\n%s\n\n", title);
  std::printf("| method | triangles | refine s (wall) | refine s (CPU) | total s (CPU) | triangles/s (CPU) | "
              "peak MiB | bytes/vertex | refine CPU / CGAL |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
}

void print_speed_row(const char* method, const Result& r, double cgal_cpu) {
  if (r.ok == 0) {
    std::printf("| %s | failed | | | | | | | |\n", method);
    return;
  }
  char ratio[32] = "—";
  if (cgal_cpu > 0) std::snprintf(ratio, sizeof ratio, "%.3f", r.cpu_refine / cgal_cpu);
  std::printf("| %s | %.0f | %.3f | %.3f | %.3f | %.3g | %.1f | %.0f | %s |\n", method, r.triangles, r.wall_refine,
              r.cpu_refine, r.cpu_total, r.triangles / r.cpu_refine, r.peak_mib,
              r.peak_mib * 1048576.0 / r.vertices, ratio);
  std::fflush(stdout);
}

// ---- quality ----------------------------------------------------------------------------------

struct Quality {
  double interior = 0;  // weight without the boundary
  std::size_t steiner = 0;
  double min_angle = 0;
  std::string stop;
};

Quality refine_quality(const Pslg& g, const RefineOptions& options) {
  Mesh mesh = constrained_delaunay(g);
  const RefineStats stats = refine(mesh, options);
  const Metrics m = measure(mesh);
  return {m.weight_interior, m.steiner, m.min_angle_deg, to_string(stats.stop)};
}

int quality(const std::string& dir) {
  std::vector<std::pair<std::string, Pslg>> sets;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    const std::string ext = e.path().extension().string();
    if (ext != ".poly" && ext != ".node") continue;
    const std::string name = e.path().filename().string();
    // The .poly twins of the .node sets are the same data.
    if (ext == ".poly" && std::filesystem::exists(e.path().parent_path() / (e.path().stem().string() + ".node"))) continue;
    sets.emplace_back(name, io::read_input(e.path().string()));
  }
  std::sort(sets.begin(), sets.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::map<std::string, double> dt;
  for (const auto& [name, g] : sets) {
    Mesh mesh = constrained_delaunay(g);
    dt[name] = measure(mesh).weight_interior;
  }
  auto norm = [&](const std::string& name, double w) { return 100.0 * w / dt[name]; };

  // 1. Weight (interior, DT = 100) and Steiner points against the bound, both rules.
  const double bounds[] = {5, 10, 15, 20, 25, 30, 34};
  std::printf("\nInterior weight (DT = 100) / Steiner points; off-center (O) and circumcenter (C)\n\n| data |");
  for (double b : bounds) std::printf(" %g° O | %g° C |", b, b);
  std::printf("\n|---|");
  for (std::size_t i = 0; i < 2 * std::size(bounds); ++i) std::printf("---:|");
  std::printf("\n");
  std::map<std::pair<int, double>, std::pair<double, double>> sums;  // (rule, bound) → sums
  for (const auto& [name, g] : sets) {
    std::printf("| %s |", name.c_str());
    for (double b : bounds) {
      for (int rule = 0; rule < 2; ++rule) {
        RefineOptions o;
        o.min_angle_deg = b;
        o.rule = rule == 0 ? SteinerRule::kOffCenter : SteinerRule::kCircumcenter;
        const Quality q = refine_quality(g, o);
        std::printf(" %.1f / %zu |", norm(name, q.interior), q.steiner);
        sums[{rule, b}].first += norm(name, q.interior);
        sums[{rule, b}].second += static_cast<double>(q.steiner);
      }
    }
    std::printf("\n");
    std::fflush(stdout);
  }
  std::printf("| mean / total |");
  for (double b : bounds) {
    for (int rule = 0; rule < 2; ++rule) {
      std::printf(" %.1f / %.0f |", sums[{rule, b}].first / static_cast<double>(sets.size()), sums[{rule, b}].second);
    }
  }
  std::printf("\n");

  // 2. Variants at a few bounds, summed over the data sets.
  struct Variant {
    const char* name;
    std::function<void(RefineOptions&)> set;
  };
  const std::vector<Variant> variants = {
      {"off-center 1.00", [](RefineOptions& o) { o.offcenter_factor = 1.0; }},
      {"off-center 0.95 (Triangle)", [](RefineOptions& o) { o.offcenter_factor = 0.95; }},
      {"off-center 0.90", [](RefineOptions& o) { o.offcenter_factor = 0.90; }},
      {"off-center 0.80", [](RefineOptions& o) { o.offcenter_factor = 0.80; }},
      {"lens (default)", [](RefineOptions& o) { o.encroachment = Encroachment::kDiametralLens; }},
      {"diametral circle", [](RefineOptions& o) { o.encroachment = Encroachment::kDiametralCircle; }},
      {"shortest edge first", [](RefineOptions& o) { o.order = RefineOrder::kShortestEdgeFirst; }},
      {"worst quality first", [](RefineOptions& o) { o.order = RefineOrder::kWorstQualityFirst; }},
  };
  const double vbounds[] = {10, 20, 30};
  std::printf("\nVariants (off-center rule unless named): mean interior weight (DT = 100) / total Steiner points over %zu data sets\n\n| variant |",
              sets.size());
  for (double b : vbounds) std::printf(" %g° |", b);
  std::printf("\n|---|");
  for (std::size_t i = 0; i < std::size(vbounds); ++i) std::printf("---:|");
  std::printf("\n");
  for (const auto& v : variants) {
    std::printf("| %s |", v.name);
    for (double b : vbounds) {
      double w = 0, st = 0;
      for (const auto& [name, g] : sets) {
        RefineOptions o;
        o.min_angle_deg = b;
        v.set(o);
        const Quality q = refine_quality(g, o);
        w += norm(name, q.interior);
        st += static_cast<double>(q.steiner);
      }
      std::printf(" %.2f / %.0f |", w / static_cast<double>(sets.size()), st);
    }
    std::printf("\n");
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t n = 100000;
  double large_triangles = 15e6;
  bool cgal_large = false;
  int repeats = 3;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quality" && i + 1 < argc) return quality(argv[++i]);
    if (a == "--n" && i + 1 < argc) n = std::strtoull(argv[++i], nullptr, 10);
    else if (a == "--large-triangles" && i + 1 < argc) large_triangles = std::strtod(argv[++i], nullptr);
    else if (a == "--cgal-large") cgal_large = true;
    else if (a == "--repeats" && i + 1 < argc) repeats = std::atoi(argv[++i]);
    else {
      std::fprintf(stderr, "usage: bench_refine [--n N] [--large-triangles T] [--cgal-large] [--repeats R] | --quality DATA_DIR\n");
      return 2;
    }
  }
  std::printf("%s\n", bench::hardware_line().c_str());

  // 1. 20° refinement of the unit square holding n uniform points.
  const Pslg g = square_with_points(n, 20240603);
  RefineOptions options;
  options.min_angle_deg = 20.0;
  char title[160];
  std::snprintf(title, sizeof title, "20° refinement, unit square + %zu uniform points (best of %d)", n, repeats);
  print_speed_header(title);
  const Result cgal = run_forked([&] { return run_cgal(g, 20.0, 0.0); }, repeats);
  const Result ours = run_forked([&] { return run_mwst(g, options); }, repeats);
  print_speed_row("CGAL refine_Delaunay_mesh_2", cgal, cgal.ok ? cgal.cpu_refine : 0.0);
  print_speed_row("mwst refine (off-center)", ours, cgal.ok ? cgal.cpu_refine : 0.0);
  RefineOptions circ = options;
  circ.rule = SteinerRule::kCircumcenter;
  const Result ours_c = run_forked([&] { return run_mwst(g, circ); }, repeats);
  print_speed_row("mwst refine (circumcenter)", ours_c, cgal.ok ? cgal.cpu_refine : 0.0);

  // 2. Area-bounded refinement of the empty unit square to about `large_triangles` triangles
  //    (20° as well). About 1.55 triangles per max_area of domain (measured).
  if (large_triangles > 0) {
    const Pslg sq = square_with_points(0, 1);
    RefineOptions big;
    big.min_angle_deg = 20.0;
    big.max_area = 1.55 / large_triangles;
    std::snprintf(title, sizeof title, "--max-area %.3g refinement of the unit square (20°), best of %d", big.max_area,
                  std::max(1, repeats - 1));
    print_speed_header(title);
    Result cg{};
    if (cgal_large) {
      // CGAL bounds edge length, not area: the edge of an equilateral triangle of that area.
      const double edge = std::sqrt(4.0 * big.max_area / std::sqrt(3.0));
      cg = run_forked([&] { return run_cgal(sq, 20.0, edge); }, 1);
      print_speed_row("CGAL refine_Delaunay_mesh_2 (edge bound)", cg, cg.cpu_refine);
    }
    const Result r = run_forked([&] { return run_mwst(sq, big); }, std::max(1, repeats - 1));
    print_speed_row("mwst refine --max-area", r, cgal_large && cg.ok ? cg.cpu_refine : 0.0);
  }
  return 0;
}
