// `mwst triangle [-SWITCHES]... INPUT` — Triangle's command line: the same switches
// (mwst/io/triangle_switches.hpp), input files and output names, so that a script calling `triangle`
// runs after a change of program name.
//
// INPUT is a name with or without its extension: "box" or "box.node" reads box.node; "box.poly" or
// -p reads box.poly; with -r (or INPUT ending in .ele) the mesh box.node + box.ele is read, with -p
// also box.poly (its segments, holes and regions) and with -a alone box.area. The output is
// box.1.node, box.1.ele, ... (a name that ends in an iteration number gets it incremented:
// box.1 → box.2; -I keeps the input's name and then writes no file that would replace an input,
// saying "NOT writing a .poly file." for it), all written only after the whole computation succeeded. Unless -Q, a summary
// in Triangle's words: the files opened and written, the phases' times and the statistics.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_set>
#include <vector>

#include "cli/commands.hpp"
#include "mwst/algorithms/arrays.hpp"
#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/algorithms/pipeline.hpp"
#include "mwst/io/triangle_switches.hpp"
#include "mesh/keys.hpp"

namespace mwst::cli {

namespace {

constexpr std::string_view kUsage =
    "usage: mwst triangle [-prq_a_ADYS_cjevnzBPNEIOQVh] INPUT\n"
    "Triangle's command line (Shewchuk's Triangle 1.6): the same switches, input and output files.\n"
    "  -p  triangulate a .poly (segments, holes, regions)   -r  refine INPUT.node + INPUT.ele\n"
    "  -q  minimum angle 20 degrees, or -q<angle>            -a<area>  maximum triangle area\n"
    "  -a  the .poly regions' / .area file's area limits      -A  regional attributes in the .ele\n"
    "  -D  conforming Delaunay    -Y  no Steiner points on boundary segments (-YY: on any segment)\n"
    "  -S<n>  at most n Steiner points (-S: none)   -c  keep the convex hull\n"
    "  -j  no unused vertices in the .node   -e  .edge   -v  Voronoi (.v.node, .v.edge)   -n  .neigh\n"
    "  -z  number from 0   -B  no boundary markers   -P -N -E  no .poly, .node, .ele\n"
    "  -I  no iteration number   -O  ignore holes   -Q  quiet   -V  verbose   -h  this help\n"
    "Accepted and ignored (Triangle's own algorithm choices): -i -F -l -s -C -X.\n"
    "Refused: -u (user-defined constraints), -g (.off output), -o2 (second-order triangles).\n"
    "Method: dr (Delaunay refinement) with -q, -a or -D, else dt. See README.md, \"mwst triangle\".\n";

bool ends_with(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

// The input's name without its extension, and what the extension implies (Triangle: .poly is -p,
// .ele is -r).
std::string input_stem(const std::string& input, TriangleSwitches& switches) {
  for (const std::string_view ext : {".node", ".poly", ".ele", ".area"}) {
    if (!ends_with(input, ext)) continue;
    if (ext == ".poly") switches.poly = true;
    if (ext == ".ele" || ext == ".area") switches.refine = true;
    return input.substr(0, input.size() - ext.size());
  }
  return input;
}

struct TriangleInput {
  Pslg pslg;
  std::vector<std::string> paths;  // the files read
};

TriangleInput read_triangle_input(const std::string& stem, const TriangleSwitches& switches) {
  TriangleInput in;
  const auto opening = [&](const std::string& path) { in.paths.push_back(path); };
  if (switches.refine) {
    opening(stem + ".node");
    in.pslg = io::read_node(stem + ".node");
    if (switches.poly) {
      opening(stem + ".poly");
      Pslg poly = io::read_poly(stem + ".poly");
      if (poly.points != in.pslg.points) {
        throw InputError(stem + ".poly", 0, "its vertices differ from those of " + stem + ".node");
      }
      in.pslg.segments = std::move(poly.segments);
      in.pslg.segment_lines = std::move(poly.segment_lines);
      in.pslg.holes = std::move(poly.holes);
      in.pslg.regions = std::move(poly.regions);
      in.pslg.is_poly = true;
      in.pslg.source = poly.source;
    }
    opening(stem + ".ele");
    io::read_triangles(in.pslg, stem + ".ele");
    if (switches.options.regional_area_limits) {
      opening(stem + ".area");
      io::read_triangle_areas(in.pslg, stem + ".area");
    }
  } else if (switches.poly) {
    opening(stem + ".poly");
    in.pslg = io::read_poly(stem + ".poly");
  } else {
    opening(stem + ".node");
    in.pslg = io::read_node(stem + ".node");
  }
  if (switches.ignore_holes) in.pslg.holes.clear();
  return in;
}

long milliseconds(double seconds) { return static_cast<long>(seconds * 1000.0 + 0.5); }

void print_statistics(const TriangleInput& in, const MeshArrays& mesh, const TriangleSwitches& switches) {
  std::size_t boundary_edges = 0, interior_edges = 0;
  for (const std::int32_t across : mesh.neighbours) {
    if (across < 0) ++boundary_edges;
    else ++interior_edges;
  }
  const std::size_t edges = boundary_edges + interior_edges / 2;
  std::cout << "\nStatistics:\n\n"
            << "  Input vertices: " << in.pslg.points.size() << '\n';
  if (switches.refine) std::cout << "  Input triangles: " << in.pslg.triangles.size() / 3 << '\n';
  if (in.pslg.is_poly) {
    std::cout << "  Input segments: " << in.pslg.segments.size() << '\n'
              << "  Input holes: " << in.pslg.holes.size() << '\n';
  }
  std::cout << "\n  Mesh vertices: " << mesh.report.vertices << '\n'
            << "  Mesh triangles: " << mesh.triangle_count() << '\n'
            << "  Mesh edges: " << edges << '\n'
            << "  Mesh exterior boundary edges: " << boundary_edges << '\n';
  if (in.pslg.is_poly || switches.options.convex_hull) {
    // Subsegments on the exterior boundary are counted there; the rest are interior boundaries.
    const std::size_t subsegments = mesh.segment_count();
    std::unordered_set<std::uint64_t> segment_keys;
    for (std::size_t s = 0; s < subsegments; ++s) segment_keys.insert(undirected_key(mesh.segments[2 * s], mesh.segments[2 * s + 1]));
    std::size_t exterior_subsegments = 0;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
      for (unsigned k = 0; k < 3; ++k) {
        if (mesh.neighbours[3 * t + k] >= 0) continue;
        const std::uint32_t a = mesh.triangles[3 * t + (k + 1) % 3], b = mesh.triangles[3 * t + (k + 2) % 3];
        exterior_subsegments += segment_keys.count(undirected_key(a, b));
      }
    }
    std::cout << "  Mesh interior boundary edges: " << subsegments - exterior_subsegments << '\n'
              << "  Mesh subsegments (constrained edges): " << subsegments << '\n';
  }
  if (switches.verbosity > 0) {
    char line[160];
    std::snprintf(line, sizeof line, "  Method %s: %zu Steiner points, angles %.3f to %.3f degrees, weight %.6f\n",
                  mesh.report.method.c_str(), mesh.report.steiner, mesh.report.min_angle, mesh.report.max_angle,
                  mesh.report.weight_total);
    std::cout << '\n' << line;
    if (!mesh.report.stop_reason.empty()) std::cout << "  Stopped: " << mesh.report.stop_reason << '\n';
  }
  std::cout << '\n';
}

// The files Triangle would write for these switches, numbered as Triangle numbers them.
io::TriangleOutput output_files_of(const TriangleSwitches& switches, const TriangulateOptions& options,
                                   const TriangleInput& in) {
  io::TriangleOutput what;
  what.node = !switches.no_node_output;
  what.ele = !switches.no_ele_output;
  what.poly = (switches.poly || options.convex_hull) && !switches.no_poly_output;
  what.edges = switches.edges;
  what.neighbours = switches.neighbours;
  what.voronoi = switches.voronoi;
  what.boundary_markers = !switches.no_boundary_markers;
  what.triangle_attributes = switches.region_attributes;
  what.jettison = switches.jettison;
  // Triangle numbers its output as the input's first vertex is numbered; -z where nothing decides.
  what.first_index = in.pslg.points.empty() ? (switches.zero_based ? 0 : 1) : in.pslg.first_index;
  return what;
}

// What Triangle prints after a run: the files opened, the warnings, each phase's time, the files
// written (and those not written because they would replace an input), and the statistics.
void print_run(const TriangleInput& in, const MeshArrays& mesh, const TriangleSwitches& switches,
               const std::vector<std::string>& written, const std::vector<std::string>& not_written) {
  for (const std::string& path : in.paths) std::cout << "Opening " << path << ".\n";
  for (const std::string& w : mesh.report.warnings) warn(w);
  if (!switches.ignored.empty() && switches.verbosity > 0) {
    warn("switches " + switches.ignored + " choose Triangle's own algorithms; mwst ignores them");
  }
  for (const auto& [phase, seconds] : mesh.report.seconds) {
    std::cout << phase << " milliseconds:  " << milliseconds(seconds) << '\n';
  }
  std::cout << '\n';
  for (const std::string& path : written) std::cout << "Writing " << path << ".\n";
  for (const std::string& ext : not_written) std::cout << "NOT writing a " << ext << " file.\n";
  std::cout << "\nTotal running time milliseconds:  " << milliseconds(mesh.report.total_seconds()) << '\n';
  print_statistics(in, mesh, switches);
}

// Refuses (before any work) an output name PREFIX.ext that would replace one of the inputs.
void refuse_replacing_inputs(const TriangleInput& in, const std::string& prefix) {
  for (const std::string& input : in.paths) {
    for (const char* ext : {".node", ".ele", ".poly", ".edge", ".neigh", ".v.node", ".v.edge"}) {
      refuse_overwrite(input, prefix + ext);
    }
  }
}

// Triangulates the input as flat arrays, with a progress line unless `quiet`; the library's
// errors and warnings name option fields, and are said here in the switches the user gave.
MeshArrays triangulate_with_progress(const TriangleInput& in, TriangulateOptions& options, bool quiet) {
  MeshArrays mesh;
  {
    ProgressLine progress(!quiet);
    options.progress = progress.callback();
    try {
      mesh = triangulate_arrays(in.pslg, options);
    } catch (const std::invalid_argument& e) {
      throw UsageError(with_flag_names(e.what(), Spelling::kTriangle));
    } catch (const ResourceError& e) {
      throw ResourceError(with_flag_names(e.what(), Spelling::kTriangle));
    }
    progress.finish();
  }
  for (std::string& w : mesh.report.warnings) w = with_flag_names(w, Spelling::kTriangle);
  return mesh;
}

// The steps: the switches and the input's name, the options checked, the input read, the output
// names checked, triangulate_with_progress, the files formatted and written at once, the summary.
int run_triangle(const std::vector<std::string>& arguments) {
  std::vector<std::string> switch_arguments, inputs;
  for (const std::string& argument : arguments) {
    if (argument == "--help") {
      std::cout << kUsage;
      return kExitOk;
    }
    (argument.size() >= 1 && argument[0] == '-' ? switch_arguments : inputs).push_back(argument);
  }
  TriangleSwitches switches;
  try {
    switches = parse_triangle_switches(switch_arguments);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("triangle: ") + e.what());
  }
  if (switches.help) {
    std::cout << kUsage;
    return kExitOk;
  }
  if (inputs.size() != 1) {
    throw UsageError("triangle: give exactly one INPUT file (found " + std::to_string(inputs.size()) +
                     "); 'mwst triangle -h' for the switches");
  }
  const std::string stem = input_stem(inputs.front(), switches);
  TriangulateOptions options = switches.options;
  options.memory_budget_bytes = memory_budget();
  use_one_heap();
  try {
    check_options(options);
  } catch (const std::invalid_argument& e) {
    throw UsageError(with_flag_names(e.what(), Spelling::kTriangle));
  }
  const bool quiet = switches.quiet;

  const TriangleInput in = read_triangle_input(stem, switches);
  const io::TriangleOutput what = output_files_of(switches, options, in);

  // Every output name, before any work: one that would replace an input is refused (with -I:
  // left out, and said so).
  const std::string prefix = switches.no_iteration_numbers ? stem : next_iteration(stem);
  const auto is_input = [&](const std::string& path) {
    return std::find(in.paths.begin(), in.paths.end(), path) != in.paths.end();
  };
  if (!switches.no_iteration_numbers) refuse_replacing_inputs(in, prefix);
  const MeshArrays mesh = triangulate_with_progress(in, options, quiet);

  OutputFiles out;
  std::vector<std::string> not_written;
  std::vector<io::TriangleFile> files;
  for (io::TriangleFile& file : io::format_triangle_files(mesh, in.pslg.holes, in.pslg.regions, what)) {
    if (is_input(prefix + file.extension)) {
      not_written.push_back(file.extension);
    } else {
      files.push_back(std::move(file));
    }
  }
  out.write_files(prefix, files);
  out.commit();
  // Only now, so that a failed run prints exactly one line.
  if (!quiet) print_run(in, mesh, switches, out.written(), not_written);
  return kExitOk;
}

}  // namespace

void register_triangle(CLI::App& app, Action& action) {
  auto arguments = std::make_shared<std::vector<std::string>>();
  CLI::App* sub = app.add_subcommand(
      "triangle", "Triangle's command line: mwst triangle [-prq_a_ADYS_cjevnzBPNEIOQVh] INPUT (-h for the switches)");
  // Everything after `triangle` is Triangle's (its -h included), not CLI11's.
  sub->set_help_flag();
  sub->prefix_command();
  sub->callback([arguments, sub, &action] {
    *arguments = sub->remaining();
    action = [arguments] { return run_triangle(*arguments); };
  });
}

}  // namespace mwst::cli
