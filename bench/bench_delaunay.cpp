// bench/bench_delaunay.cpp — mwst::delaunay (Hilbert-order incremental Lawson insertion with exact
// predicates, src/mesh/delaunay.cpp) against CGAL 5.5's Delaunay_triangulation_2 with the
// Exact_predicates_inexact_constructions_kernel (range insertion, which spatially sorts: CGAL's
// fastest documented way to build a Delaunay triangulation), side by side in one run.
//
// Data: 1M uniform points in the unit square, 1M Kuzmin points (clustered), the 1000 × 1000 integer
// grid (shuffled; every unit square is cocircular), 100k points on the unit circle (cos/sin,
// rounded: nearly all incircle tests are near-degenerate), 10M uniform points.
//
// Table 1, algorithm only: best of 3 runs, each in a forked child; peak memory is the increase of
// the resident set over the run (input excluded; see bench_common.hpp). Both sides get the points
// already in memory (mwst: std::vector<mwst::Point>, CGAL: std::vector<Point_2>) and both copy them
// internally (mwst::delaunay takes its input by value; CGAL's range insert copies to sort).
//
// Table 2, whole process: the points are written once to a .node file; each run is a fresh process
// that reads it, triangulates and writes PREFIX.node / PREFIX.ele: `mwst triangulate` when the
// command line is built, mwst in-process (io::read_node + delaunay + io::write_mesh), and CGAL with a
// small std::from_chars / std::to_chars reader and writer. Peak is the process's whole peak RSS.
//
// Usage: bench_delaunay [--quick] [--repeats N] [--tmp DIR]
//   --quick: skip the 10M case and the whole-process table's largest inputs.
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_common.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mwst/io/triangle_files.hpp"

namespace {

using namespace mwst;
using namespace mwst::bench;

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalDt = CGAL::Delaunay_triangulation_2<K>;
using InfoVb = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, K>;
using InfoDt = CGAL::Delaunay_triangulation_2<K, CGAL::Triangulation_data_structure_2<InfoVb>>;

struct DataSet {
  std::string name;
  std::function<std::vector<Point>()> make;
  bool large;  // skipped by --quick
};

// ---- whole-process child modes (this program re-executed) ------------------------------------------

int child_mwst_file(const std::string& input, const std::string& prefix) {
  const Pslg g = io::read_node(input);
  const Mesh m = delaunay(g.points);
  io::write_mesh(m, prefix, 1);
  return 0;
}

int child_cgal_file(const std::string& input, const std::string& prefix) {
  const std::vector<Point> pts = fast_read_node(input);
  std::vector<std::pair<K::Point_2, std::uint32_t>> with_index;
  with_index.reserve(pts.size());
  for (std::uint32_t i = 0; i < pts.size(); ++i) with_index.push_back({K::Point_2(pts[i].x, pts[i].y), i});
  InfoDt dt(with_index.begin(), with_index.end());
  std::vector<std::array<std::uint32_t, 3>> tris;
  tris.reserve(dt.number_of_faces());
  for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
    tris.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  }
  fast_write_mesh(prefix, pts, tris);
  return 0;
}

// Writes points as a 1-based .node file (shortest round-trip decimals).
void write_node(const std::string& path, const std::vector<Point>& pts) {
  fast_write_mesh(path.substr(0, path.size() - 5), pts, {});
  std::filesystem::remove(path.substr(0, path.size() - 5) + ".ele");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 4 && std::string(argv[1]) == "--child-mwst-file") return child_mwst_file(argv[2], argv[3]);
  if (argc == 4 && std::string(argv[1]) == "--child-cgal-file") return child_cgal_file(argv[2], argv[3]);
  bool quick = false;
  int repeats = 3;
  std::string tmp = "/tmp";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      quick = true;
    } else if (a == "--repeats" && i + 1 < argc) {
      repeats = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--tmp" && i + 1 < argc) {
      tmp = argv[++i];
    } else {
      std::fprintf(stderr, "usage: bench_delaunay [--quick] [--repeats N] [--tmp DIR]\n");
      return 2;
    }
  }
  std::printf("bench_delaunay: mwst::delaunay vs CGAL %s Delaunay_triangulation_2 (EPICK)\n", CGAL_VERSION_STR);
  std::printf("hardware: %s\n", hardware_line().c_str());
  std::printf("best of %d runs; each run in its own process\n", repeats);

  const std::vector<DataSet> sets = {
      {"uniform", [] { return uniform_points(1000000, 1); }, false},
      {"kuzmin", [] { return kuzmin_points(1000000, 2); }, false},
      {"grid 1000x1000", [] { return grid_points(1000, 3); }, false},
      {"circle", [] { return circle_points(100000, 4); }, false},
      {"uniform", [] { return uniform_points(10000000, 5); }, true},
  };

  // ---- table 1: algorithm only ----------------------------------------------------------------------
  print_header("Algorithm only (points in memory → triangulation in memory); peak = added resident memory");
  std::vector<std::string> node_files;
  for (const DataSet& set : sets) {
    if (quick && set.large) continue;
    const std::vector<Point> pts = set.make();
    Row cgal{"CGAL DT2 range insert", set.name, pts.size(), {}, 0.0, 0.0};
    std::size_t cgal_triangles = 0, mwst_triangles = 0;
    cgal.m = measure_forked(
        [&](Probe& probe) {
          std::vector<K::Point_2> input;
          input.reserve(pts.size());
          for (const Point& p : pts) input.emplace_back(p.x, p.y);
          probe.start();
          CgalDt dt(input.begin(), input.end());
          probe.stop();
          probe.set_count(dt.number_of_faces());
        },
        repeats);
    cgal_triangles = cgal.m.count;
    set_reference(cgal, cgal.m);
    Row ours{"mwst delaunay", set.name, pts.size(), {}, 0.0, 0.0};
    set_reference(ours, cgal.m);
    ours.m = measure_forked(
        [&](Probe& probe) {
          probe.start();
          const Mesh m = delaunay(pts);
          probe.stop();
          probe.set_count(m.domain_triangle_count());
        },
        repeats);
    mwst_triangles = ours.m.count;
    print_row(ours);
    print_row(cgal);
    if (mwst_triangles != cgal_triangles) {
      std::printf("| WARNING: triangle counts differ: mwst %zu, CGAL %zu | | | | | | | |\n", mwst_triangles,
                  cgal_triangles);
    }
  }

  // ---- table 2: whole process -----------------------------------------------------------------------
  std::string cli;
#ifdef MWST_BINARY
  if (executable_exists(MWST_BINARY)) cli = MWST_BINARY;
#endif
  const std::string self = std::filesystem::canonical("/proc/self/exe").string();
  print_header("Whole process (read .node → triangulate → write .node/.ele); peak = process peak RSS");
  if (cli.empty()) std::printf("(the mwst command line is not built: its row is omitted)\n\n");
  for (std::size_t k = 0; k < sets.size(); ++k) {
    const DataSet& set = sets[k];
    if (quick && set.large) continue;
    const std::vector<Point> pts = set.make();
    const std::string file = tmp + "/mwst_bench_dt_" + std::to_string(k) + ".node";
    const std::string out = tmp + "/mwst_bench_dt_out_" + std::to_string(k);
    write_node(file, pts);
    Row cgal{"CGAL read+DT2+write", set.name, pts.size(), {}, 0.0, 0.0};
    cgal.m = measure_process({self, "--child-cgal-file", file, out}, repeats);
    set_reference(cgal, cgal.m);
    if (!cli.empty()) {
      Row row{"mwst triangulate (CLI)", set.name, pts.size(), {}, 0.0, 0.0};
      set_reference(row, cgal.m);
      row.m = measure_process({cli, "triangulate", file, "-o", out, "--quiet"}, repeats);
      print_row(row);
    }
    Row inproc{"mwst read+delaunay+write", set.name, pts.size(), {}, 0.0, 0.0};
    set_reference(inproc, cgal.m);
    inproc.m = measure_process({self, "--child-mwst-file", file, out}, repeats);
    print_row(inproc);
    print_row(cgal);
    for (const char* ext : {".node", ".ele", ".poly"}) std::filesystem::remove(out + ext);
    std::filesystem::remove(file);
  }
  return 0;
}
