// `mwst triangulate INPUT [-o PREFIX] [--method dt|dr|brh|qtr|opt] [--min-angle DEG]
//  [--steiner offcenter|circumcenter] [--bundle-k K] [--flip] [--max-area A] [--max-steiner N]
//  [--convex-hull] [--strict] [--bundle] [--time-limit SECONDS] [--exact-polish] [--opt-trials N] [--json FILE]
//  [--draw FILE] [--max-memory BYTES] [--threads N] [--quiet]`
// Reads a Triangle .node/.poly, runs triangulate() (mwst/algorithms/pipeline.hpp: the methods of Boyacı,
// Erten, Üngör, "Triangulations Loosing Bundles and Weight", and ours) and writes PREFIX.node,
// PREFIX.ele, PREFIX.poly and the JSON report, all only after the computation succeeded. A run
// longer than 2 s shows a progress line on stderr when stderr is a terminal (not with --quiet).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "mwst/io/report.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/io/draw.hpp"
#include "mwst/error.hpp"
#include "mwst/algorithms/arrays.hpp"
#include "mwst/algorithms/pipeline.hpp"

namespace mwst::cli {

namespace {

// The time set aside under --time-limit for writing the output (with the mesh's measures before
// it), per second the input took to read: the output holds at least the input's mesh, and turning it
// into Triangle's files took 2-6 times as long as reading the input did (1M points or vertices of
// uniform, ellipse, holes and coastline inputs, on a loaded machine: the reading measures the
// machine's speed at the time). At most a quarter of the limit.
constexpr double kWritingPerReading = 5.0;
// And for each vertex a method adds (TriangulateOptions::time_reserve_per_vertex): the same
// proportion per input vertex, but at least this much. Writing a mesh out (to_arrays, the files),
// measuring it and the refinement's count of what is left took 2.2 µs per added vertex (dr with an
// area bound on 160k uniform points, 1.4M vertices added, 3M triangles, load 7 on 2 cores).
constexpr double kLeastWritingPerVertex = 3e-6;

struct TriangulateArgs {
  std::string input;
  std::string prefix;
  std::string method = "dt";
  double min_angle = 20.0;
  std::string steiner = "offcenter";
  std::size_t bundle_k = 0;
  bool flip = false;
  bool exact_polish = false;
  std::size_t opt_trials = kDefaultOptTrials;
  double max_area = -1.0;
  std::size_t max_steiner = 0;
  bool max_steiner_given = false;  // --max-steiner 0 is a budget of no Steiner points
  bool convex_hull = false;
  bool strict = false;
  bool bundle = false;
  double time_limit = -1.0;  // seconds; ≤ 0: none (the option itself only accepts > 0)
  std::vector<std::string> given;  // the options given, as --long-name (kFieldFlags maps them to fields)
  std::string json;
  std::string draw;
  bool quiet = false;
  std::string max_memory;  // --max-memory (parse_bytes); empty: the default budget
  unsigned threads = 0;    // TriangulateOptions::threads
};

std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

void print_summary(const Report& r, const std::vector<std::string>& written) {
  std::cout << r.input << ": method " << r.method << ": " << r.vertices << " vertices (" << r.steiner
            << " Steiner), " << r.triangles << " triangles\n"
            << "  weight " << fixed(r.weight_total, 6) << " = boundary " << fixed(r.weight_boundary, 6)
            << " + interior " << fixed(r.weight_interior, 6) << "\n"
            << "  angles " << fixed(r.min_angle, 3) << " to " << fixed(r.max_angle, 3) << " degrees";
  if (!r.stop_reason.empty()) std::cout << "; stopped: " << r.stop_reason;
  std::cout << "; " << fixed(r.total_seconds(), 3) << " s\n";
  if (!written.empty()) {
    std::cout << "  wrote";
    for (const std::string& path : written) std::cout << ' ' << path;
    std::cout << '\n';
  }
}

int run_triangulate(const TriangulateArgs& a) {
  TriangulateOptions options;
  options.method = *parse_method(a.method);  // CLI11 checked the name
  options.min_angle_deg = a.min_angle;
  options.steiner = *parse_steiner_rule(a.steiner);
  options.bundle_k = a.bundle_k;
  options.flip = a.flip;
  options.threads = a.threads;
  options.max_area = a.max_area;
  if (a.max_steiner_given) options.max_steiner = a.max_steiner;
  options.convex_hull = a.convex_hull;
  options.strict = a.strict;
  options.bundle = a.bundle;
  options.time_budget_seconds = a.time_limit;
  options.exact_polish = a.exact_polish;
  options.opt_trials = a.opt_trials;
  if (!a.max_memory.empty()) set_memory_budget(*parse_bytes(a.max_memory));  // CLI11 checked it
  options.memory_budget_bytes = memory_budget();
  use_one_heap();
#ifdef __GLIBC__
  // BRH's exact tests build and free arrays of megabytes (DT(V), the candidate lists, each phase's
  // scratch): arrays of 4 MB or more get their own mappings, returned to the system when freed
  // (glibc's adaptive threshold would keep them in the heap, whose resident size never drops), as
  // `mwst bundle` does with 1 MB and use_one_heap with 1 MiB (BRH allocates more often: 4 MB costs
  // it ~3% CPU instead of ~12%).
  if (options.method == Method::kBrh) mallopt(M_MMAP_THRESHOLD, 4 << 20);
#endif
  try {
    check_options(options);
  } catch (const std::invalid_argument& e) {
    throw UsageError(with_flag_names(e.what(), Spelling::kTriangulate));
  }
  io::PictureFormat draw_format{};
  if (!a.draw.empty()) {
    try {
      draw_format = io::picture_format(a.draw);
    } catch (const mwst::InputError& e) {
      throw UsageError(std::string("--draw: ") + e.what());
    }
  }

  const std::string prefix = a.prefix.empty() ? default_prefix(a.input) : a.prefix;
  for (const char* ext : {".node", ".ele", ".poly"}) refuse_overwrite(a.input, prefix + ext);
  if (!a.json.empty() && a.json != "-") refuse_overwrite(a.input, a.json);

  ProgressLine progress(!a.quiet);
  options.progress = progress.callback();
  const auto reading_started = std::chrono::steady_clock::now();
  const Pslg pslg = io::read_input(a.input);
  if (options.time_budget_seconds > 0.0) {
    // --time-limit counts the whole run, from the process's start: reading the input, and writing
    // the output after the library has stopped. The library's budget is what is left once the
    // input is read and a reserve for writing the input-sized part of the output is set aside (at
    // least a moment, so that the limit stays set); the methods set aside more for every vertex
    // they add (time_reserve_per_vertex).
    const double reading = std::chrono::duration<double>(std::chrono::steady_clock::now() - reading_started).count();
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - process_start()).count();
    const double writing_reserve = std::min(kWritingPerReading * reading, 0.25 * a.time_limit);
    options.time_budget_seconds = std::max(a.time_limit - elapsed - writing_reserve, 1e-6);
    const double vertices = static_cast<double>(std::max<std::size_t>(pslg.points.size(), 1));
    options.time_reserve_per_vertex = std::max(kLeastWritingPerVertex, kWritingPerReading * reading / vertices);
  }
  Mesh mesh;
  Report report;
  try {
    report = triangulate(pslg, options, &mesh);
  } catch (const std::invalid_argument& e) {
    throw UsageError(with_flag_names(e.what(), Spelling::kTriangulate));
  } catch (const ResourceError& e) {
    throw ResourceError(with_flag_names(e.what(), Spelling::kTriangulate));
  }
  progress.finish();
  report.options.time_budget_seconds = a.time_limit;  // the report gives the limit as the user gave it
  // The library's warnings name option fields; the user gave flags.
  for (std::string& w : report.warnings) w = with_flag_names(w, Spelling::kTriangulate);
  // An option the method does not read is said so, not silently dropped.
  for (const std::string& option : a.given) {
    if (!method_reads_option(options.method, field_of_triangulate_flag(option))) {
      report.warnings.push_back(option + " has no effect with --method " + a.method);
    }
    // opt reads --min-angle for its DR and BRH starts only: its moves keep no angle bound.
    if (option == "--min-angle" && options.method == Method::kOpt) {
      report.warnings.push_back("--min-angle bounds only the angles of opt's starting meshes (its dr and brh "
                                "starts), not of its result: opt's moves lower the weight whatever the angles");
    }
  }

  OutputFiles out;
  MeshArrays arrays = to_arrays(mesh);
  interpolate_vertex_attributes(pslg, options.convex_hull, arrays);
  out.write_mesh(arrays, prefix, pslg.first_index, pslg.holes, pslg.regions);
  if (!a.json.empty()) out.write_json(a.json, to_json(report));
  if (!a.draw.empty()) out.write(a.draw, io::render_pictures({io::picture_of(mesh)}, draw_format));
  out.commit();
  // Only now, so that a failed run prints exactly one line.
  if (!a.quiet) {
    for (const std::string& w : report.warnings) warn(w);
    if (a.json != "-") print_summary(report, out.written());
  }
  return kExitOk;
}

}  // namespace

void register_triangulate(CLI::App& app, Action& action) {
  auto args = std::make_shared<TriangulateArgs>();
  CLI::App* sub = app.add_subcommand("triangulate", "Triangulate a .node point set or .poly graph");
  sub->add_option("INPUT", args->input, "Triangle .node (point set: its convex hull) or .poly file")
      ->type_name("FILE")
      ->required();
  sub->add_option("-o,--output", args->prefix,
                  "Output prefix for PREFIX.node/.ele/.poly (default: INPUT without its extension + .1, "
                  "or with its iteration number incremented: foo.1.poly -> foo.2)")
      ->type_name("PREFIX");
  sub->add_option("--method", args->method,
                  "dt = (constrained) Delaunay, dr = Delaunay refinement, brh = bundle removal, "
                  "qtr = quadtree refinement, opt = weight optimiser")
      ->check(CLI::IsMember({"dt", "dr", "brh", "qtr", "opt"}))
      ->capture_default_str();
  sub->add_option("--min-angle", args->min_angle, "Minimum angle bound in degrees, in [0, 60); dr terminates provably up to 20.7, in practice up to about 33; above that it may stop with \"no progress: size beyond the local-feature-size bound\"")
      ->check(number_in(0.0, 60.0))
      ->capture_default_str();
  sub->add_option("--steiner", args->steiner, "Steiner point rule for refinement")
      ->check(CLI::IsMember({"offcenter", "circumcenter"}))
      ->capture_default_str();
  sub->add_option("--bundle-k", args->bundle_k,
                  "BRH bundle size k >= 3 (default ceil(4*pi/alpha)+3 from --min-angle)")
      ->check(whole_number());
  sub->add_flag("--flip", args->flip, "Weight-reducing edge flips (EFH) after the method");
  sub->add_option("--max-area", args->max_area, "Refine triangles larger than this area (dr, brh, opt; --flip and opt's moves keep the bound)")
      ->check(number_above(0.0));
  CLI::Option* max_steiner =
      sub->add_option("--max-steiner", args->max_steiner,
                      "Stop refining after this many Steiner points (opt: no start or search holds more, "
                      "beyond the crossing points of the input's segments)")
          ->check(whole_number());
  sub->add_flag("--convex-hull", args->convex_hull, "Triangulate the whole convex hull (holes still carve)");
  sub->add_flag("--strict", args->strict, "Refuse crossing segments instead of splitting them");
  sub->add_flag("--bundle", args->bundle, "Add the exact bundle number to the report");
  sub->add_option("--time-limit", args->time_limit,
                  "Stop dr, brh, qtr and opt so that the whole process, from its start (reading the input, opt's "
                  "starts, refinements and searches, --flip, --bundle, writing the output) ends within "
                  "SECONDS + max(5%, 1 s), unless reading, the Delaunay triangulation and writing it alone take longer; "
                  "time is set aside for the writing (five times the reading's, at most a quarter of the limit, and "
                  "3 us or more per vertex added); qtr: its quadtree and mesh, then the mesh is the constrained "
                  "Delaunay triangulation of the input; the mesh is still valid and the report's stop_reason says "
                  "\"time budget\"")
      ->type_name("SECONDS")
      ->check(number_above(0.0));
  sub->add_flag("--exact-polish", args->exact_polish,
                "opt: also search from the exact minimum weight triangulation (MWT) of each start's "
                "vertices, and after the search replace the mesh by the MWT of its vertices when one is "
                "found (within size limits) and lighter, search again, repeat; never heavier, slower");
  sub->add_option("--opt-trials", args->opt_trials,
                  "opt: iterated local search trials per start (default min(600, 300000 / triangles)); "
                  "fewer is faster, 0 stops after the kicks")
      ->type_name("N")
      ->check(whole_number());
  sub->add_option("--json", args->json, "Write the JSON report to FILE ('-' = standard output)")
      ->type_name("FILE");
  sub->add_option("--draw", args->draw, "Draw the mesh to FILE.png, .svg or .pdf")->type_name("FILE");
  sub->add_option("--max-memory", args->max_memory,
                  "Memory budget in bytes, with K, M, G or T (powers of 1024): past it the run stops with exit "
                  "code 4 and no output, and an --max-area whose mesh cannot fit is refused up front "
                  "(default: 75% of the machine's memory, or less if the process may use less)")
      ->type_name("BYTES")
      ->check(byte_count());
  sub->add_option("--threads", args->threads,
                  "Worker threads (0 = all hardware threads); the results do not depend on it")
      ->type_name("N")
      ->capture_default_str();
  sub->add_flag("-q,--quiet", args->quiet, "No summary, no warnings and no progress line");
  sub->callback([args, max_steiner, sub, &action] {
    args->max_steiner_given = max_steiner->count() > 0;
    for (const CLI::Option* option : sub->get_options([](const CLI::Option* o) { return o->count() > 0; })) {
      args->given.push_back(option->get_name());
    }
    action = [args] { return run_triangulate(*args); };
  });
}

}  // namespace mwst::cli
