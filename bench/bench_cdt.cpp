// bench/bench_cdt.cpp — mwst::constrained_delaunay (Delaunay of the vertices, then cavity segment
// insertion after Shewchuk–Brown 2015, then flood-fill carving: src/mesh/constrain.cpp, carve.cpp)
// against CGAL 5.5's Constrained_Delaunay_triangulation_2 (Exact_predicates_inexact_constructions
// kernel, Exact_predicates_tag), side by side in one run.
//
// Data: a polygon with about 1M vertices: a fine circle (200k vertices, radius 1) with a few hundred
// circular holes (radius 0.035 on a 0.1 grid, about 3100 vertices each), every vertex from rounded
// cos/sin, so consecutive vertices are nearly collinear and the predicates' exact stages are used.
//
// CGAL is measured two ways and the faster is the reference of the ratio column:
//   "insert_constraints": cdt.insert_constraints(points, index pairs) (spatially sorts the points,
//       inserts them, then the constraints by vertex handle);
//   "insert + constraints": range insertion of (point, index) pairs (spatial sort), then
//       insert_constraint(handle, handle) per segment.
// Both then mark the domain by the usual nesting-level flood fill (CGAL's polygon triangulation
// example): mwst's timing includes its carving too.
//
// Table 1: algorithm only (in memory), forked child per run, peak = added resident memory.
// Table 2: whole process: read .poly → triangulate → write .node/.ele/.poly (mwst command line when
// built; mwst in-process with io::read_poly / io::write_mesh; CGAL with a small from_chars reader).
//
// Usage: bench_cdt [--vertices N] [--repeats N] [--tmp DIR] [--write-input F.poly]
// (--write-input writes the benchmark polygon and stops: for profiling the command line on it)
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <charconv>
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
using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, K>;
using Fbi = CGAL::Triangulation_face_base_with_info_2<int, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbi>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;

// The benchmark polygon: outer circle plus circular holes; about `total` vertices.
Pslg circle_with_holes(std::size_t total) {
  Pslg g;
  g.is_poly = true;
  const std::size_t outer = total / 5;
  std::vector<Point> centres;
  const double spacing = 0.1, radius = 0.035;
  for (int i = -10; i <= 10; ++i) {
    for (int j = -10; j <= 10; ++j) {
      const Point c{i * spacing, j * spacing};
      if (std::hypot(c.x, c.y) + radius < 0.93) centres.push_back(c);
    }
  }
  const std::size_t per_hole = (total - outer) / centres.size();
  auto ring = [&](Point c, double r, std::size_t n) {
    const auto first = static_cast<std::uint32_t>(g.points.size());
    for (std::size_t k = 0; k < n; ++k) {
      const double a = 2.0 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(n);
      g.points.push_back({c.x + r * std::cos(a), c.y + r * std::sin(a)});
      g.segments.push_back({first + static_cast<std::uint32_t>(k),
                            first + static_cast<std::uint32_t>((k + 1) % n), 1});
    }
  };
  ring({0.0, 0.0}, 1.0, outer);
  for (const Point& c : centres) {
    ring(c, radius, per_hole);
    g.holes.push_back(c);
  }
  g.point_markers.assign(g.points.size(), 0);
  return g;
}

// Domain marking for CGAL: nesting level by flood fill, crossing a constrained edge adds one; the
// domain is the odd levels. Returns the number of domain faces.
std::size_t mark_domain(Cdt& cdt) {
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = -1;
  std::vector<Cdt::Face_handle> stack, next_level;
  std::size_t in_domain = 0;
  next_level.push_back(cdt.infinite_face());
  for (int level = 0; !next_level.empty(); ++level) {
    stack.swap(next_level);
    next_level.clear();
    while (!stack.empty()) {
      const Cdt::Face_handle f = stack.back();
      stack.pop_back();
      if (f->info() != -1) continue;
      f->info() = level;
      if (level % 2 == 1) ++in_domain;
      for (int i = 0; i < 3; ++i) {
        const Cdt::Face_handle n = f->neighbor(i);
        if (n->info() != -1) continue;
        (cdt.is_constrained(Cdt::Edge(f, i)) ? next_level : stack).push_back(n);
      }
    }
  }
  return in_domain;
}

void cgal_with_insert_constraints(Cdt& cdt, const std::vector<K::Point_2>& pts,
                                  const std::vector<std::pair<std::size_t, std::size_t>>& pairs) {
  cdt.insert_constraints(pts.begin(), pts.end(), pairs.begin(), pairs.end());
}

void cgal_with_handles(Cdt& cdt, const std::vector<std::pair<K::Point_2, std::uint32_t>>& pts,
                       const std::vector<std::pair<std::size_t, std::size_t>>& pairs) {
  cdt.insert(pts.begin(), pts.end());
  std::vector<Cdt::Vertex_handle> handle(pts.size());
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) handle[v->info()] = v;
  for (const auto& [a, b] : pairs) cdt.insert_constraint(handle[a], handle[b]);
}

// ---- files ---------------------------------------------------------------------------------------

void write_poly(const std::string& path, const Pslg& g) {
  std::string buf;
  buf.reserve(g.points.size() * 64);
  char tmp[64];
  auto put = [&](auto v) {
    const auto r = std::to_chars(tmp, tmp + sizeof tmp, v);
    buf.append(tmp, r.ptr);
  };
  put(g.points.size());
  buf += " 2 0 0\n";
  for (std::size_t i = 0; i < g.points.size(); ++i) {
    put(i + 1), buf += ' ', put(g.points[i].x), buf += ' ', put(g.points[i].y), buf += '\n';
  }
  put(g.segments.size());
  buf += " 0\n";
  for (std::size_t i = 0; i < g.segments.size(); ++i) {
    put(i + 1), buf += ' ', put(g.segments[i].a + 1), buf += ' ', put(g.segments[i].b + 1), buf += '\n';
  }
  put(g.holes.size());
  buf += '\n';
  for (std::size_t i = 0; i < g.holes.size(); ++i) {
    put(i + 1), buf += ' ', put(g.holes[i].x), buf += ' ', put(g.holes[i].y), buf += '\n';
  }
  std::ofstream(path, std::ios::binary) << buf;
}

// Minimal .poly reader for the CGAL side (the format write_poly produces, comments allowed).
void fast_read_poly(const std::string& path, std::vector<Point>& pts,
                    std::vector<std::pair<std::size_t, std::size_t>>& segments) {
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const char* p = text.data();
  const char* const end = p + text.size();
  auto next_line = [&] {
    while (p < end && *p != '\n') ++p;
    if (p < end) ++p;
  };
  auto skip_space = [&] {
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
  };
  auto next_record = [&] {
    for (;;) {
      skip_space();
      if (p < end && (*p == '#' || *p == '\n')) {
        next_line();
        continue;
      }
      return;
    }
  };
  auto read_size = [&] {
    std::size_t v = 0;
    skip_space();
    p = std::from_chars(p, end, v).ptr;
    return v;
  };
  auto read_double = [&] {
    double v = 0;
    skip_space();
    p = std::from_chars(p, end, v).ptr;
    return v;
  };
  next_record();
  pts.resize(read_size());
  next_line();
  for (auto& q : pts) {
    next_record();
    read_size();
    q.x = read_double();
    q.y = read_double();
    next_line();
  }
  next_record();
  segments.resize(read_size());
  next_line();
  for (auto& s : segments) {
    next_record();
    read_size();
    s.first = read_size() - 1;
    s.second = read_size() - 1;
    next_line();
  }
}

int child_mwst_file(const std::string& input, const std::string& prefix) {
  const Pslg g = io::read_poly(input);
  const Mesh m = constrained_delaunay(g);
  io::write_mesh(m, prefix, 1);
  return 0;
}

int child_cgal_file(const std::string& input, const std::string& prefix) {
  std::vector<Point> pts;
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  fast_read_poly(input, pts, pairs);
  std::vector<std::pair<K::Point_2, std::uint32_t>> with_index;
  with_index.reserve(pts.size());
  for (std::uint32_t i = 0; i < pts.size(); ++i) with_index.push_back({K::Point_2(pts[i].x, pts[i].y), i});
  Cdt cdt;
  cgal_with_handles(cdt, with_index, pairs);
  mark_domain(cdt);
  std::vector<std::array<std::uint32_t, 3>> tris;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (f->info() % 2 == 1) tris.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  }
  fast_write_mesh(prefix, pts, tris);
  // The subsegments, as mwst writes PREFIX.poly.
  std::string buf;
  char tmp[32];
  auto put = [&](std::size_t v) {
    const auto r = std::to_chars(tmp, tmp + sizeof tmp, v);
    buf.append(tmp, r.ptr);
  };
  buf += "0 2 0 0\n";
  std::size_t count = 0;
  std::string body;
  for (auto e = cdt.finite_edges_begin(); e != cdt.finite_edges_end(); ++e) {
    if (!cdt.is_constrained(*e)) continue;
    const auto a = e->first->vertex(Cdt::cw(e->second))->info(), b = e->first->vertex(Cdt::ccw(e->second))->info();
    ++count;
    buf.swap(body);
    put(count), buf += ' ', put(a + 1), buf += ' ', put(b + 1), buf += " 1\n";
    buf.swap(body);
  }
  put(count);
  buf += " 1\n" + body + "0\n";
  std::ofstream(prefix + ".poly", std::ios::binary) << buf;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 4 && std::string(argv[1]) == "--child-mwst-file") return child_mwst_file(argv[2], argv[3]);
  if (argc == 4 && std::string(argv[1]) == "--child-cgal-file") return child_cgal_file(argv[2], argv[3]);
  std::size_t vertices = 1000000;
  int repeats = 3;
  std::string tmp = "/tmp", write_input;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--vertices" && i + 1 < argc) {
      vertices = std::max<std::size_t>(1000, std::strtoul(argv[++i], nullptr, 10));
    } else if (a == "--repeats" && i + 1 < argc) {
      repeats = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--tmp" && i + 1 < argc) {
      tmp = argv[++i];
    } else if (a == "--write-input" && i + 1 < argc) {
      write_input = argv[++i];
    } else {
      std::fprintf(stderr, "usage: bench_cdt [--vertices N] [--repeats N] [--tmp DIR] [--write-input F.poly]\n");
      return 2;
    }
  }
  const Pslg g = circle_with_holes(vertices);
  if (!write_input.empty()) {  // the benchmark's polygon for profiling, then stop
    write_poly(write_input, g);
    return 0;
  }
  std::printf("bench_cdt: mwst::constrained_delaunay vs CGAL %s Constrained_Delaunay_triangulation_2 (EPICK)\n",
              CGAL_VERSION_STR);
  std::printf("hardware: %s\n", hardware_line().c_str());
  std::printf("input: circle with %zu holes, %zu vertices, %zu segments; best of %d runs, each in its own process\n",
              g.holes.size(), g.points.size(), g.segments.size(), repeats);
  const std::string data = "circle+" + std::to_string(g.holes.size()) + " holes";

  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  pairs.reserve(g.segments.size());
  for (const Segment& s : g.segments) pairs.push_back({s.a, s.b});

  print_header("Algorithm only (graph in memory → carved CDT in memory); peak = added resident memory");
  Row cgal1{"CGAL CDT2 insert_constraints + mark", data, g.points.size(), {}, 0.0, 0.0};
  cgal1.m = measure_forked(
      [&](Probe& probe) {
        std::vector<K::Point_2> pts;
        pts.reserve(g.points.size());
        for (const Point& p : g.points) pts.emplace_back(p.x, p.y);
        probe.start();
        Cdt cdt;
        cgal_with_insert_constraints(cdt, pts, pairs);
        const std::size_t domain = mark_domain(cdt);
        probe.stop();
        probe.set_count(domain);
      },
      repeats);
  Row cgal2{"CGAL CDT2 insert + insert_constraint + mark", data, g.points.size(), {}, 0.0, 0.0};
  cgal2.m = measure_forked(
      [&](Probe& probe) {
        std::vector<std::pair<K::Point_2, std::uint32_t>> pts;
        pts.reserve(g.points.size());
        for (std::uint32_t i = 0; i < g.points.size(); ++i) pts.push_back({K::Point_2(g.points[i].x, g.points[i].y), i});
        probe.start();
        Cdt cdt;
        cgal_with_handles(cdt, pts, pairs);
        const std::size_t domain = mark_domain(cdt);
        probe.stop();
        probe.set_count(domain);
      },
      repeats);
  // The faster CGAL variant is the reference.
  const Measurement& best_cgal =
      !cgal2.m.ok || (cgal1.m.ok && cgal1.m.best_seconds <= cgal2.m.best_seconds) ? cgal1.m : cgal2.m;
  set_reference(cgal1, best_cgal);
  set_reference(cgal2, best_cgal);
  Row ours{"mwst constrained_delaunay", data, g.points.size(), {}, 0.0, 0.0};
  ours.m = measure_forked(
      [&](Probe& probe) {
        probe.start();
        const Mesh m = constrained_delaunay(g);
        probe.stop();
        probe.set_count(m.domain_triangle_count());
      },
      repeats);
  set_reference(ours, best_cgal);
  print_row(ours);
  print_row(cgal1);
  print_row(cgal2);
  std::printf("\ndomain triangles: mwst %zu, CGAL %zu / %zu\n", ours.m.count, cgal1.m.count, cgal2.m.count);

  std::string cli;
#ifdef MWST_BINARY
  if (executable_exists(MWST_BINARY)) cli = MWST_BINARY;
#endif
  const std::string self = std::filesystem::canonical("/proc/self/exe").string();
  const std::string file = tmp + "/mwst_bench_cdt.poly", out = tmp + "/mwst_bench_cdt_out";
  write_poly(file, g);
  print_header("Whole process (read .poly → carved CDT → write .node/.ele/.poly); peak = process peak RSS");
  if (cli.empty()) std::printf("(the mwst command line is not built: its row is omitted)\n\n");
  Row cgal{"CGAL read+CDT2+mark+write", data, g.points.size(), {}, 0.0, 0.0};
  cgal.m = measure_process({self, "--child-cgal-file", file, out}, repeats);
  set_reference(cgal, cgal.m);
  if (!cli.empty()) {
    Row row{"mwst triangulate (CLI)", data, g.points.size(), {}, 0.0, 0.0};
    set_reference(row, cgal.m);
    row.m = measure_process({cli, "triangulate", file, "-o", out, "--quiet"}, repeats);
    print_row(row);
  }
  Row inproc{"mwst read+cdt+write", data, g.points.size(), {}, 0.0, 0.0};
  set_reference(inproc, cgal.m);
  inproc.m = measure_process({self, "--child-mwst-file", file, out}, repeats);
  print_row(inproc);
  print_row(cgal);
  for (const char* ext : {".node", ".ele", ".poly"}) std::filesystem::remove(out + ext);
  std::filesystem::remove(file);
  return 0;
}
