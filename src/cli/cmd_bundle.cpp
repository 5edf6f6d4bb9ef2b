// `mwst bundle INPUT PREFIX [--json]`: the exact bundle number (mwst/algorithms/bundle.hpp) of the mesh
// PREFIX.node/.ele — the largest k such that some open disk containing no mesh vertex meets the
// interiors of k triangles (Boyacı, Erten, Üngör, "Triangulations Loosing Bundles and Weight") —
// with a witness disk and its triangles. Any triangulation is accepted (Delaunay or not, any domain,
// holes included); INPUT is the graph the mesh was made for (read for its name and to report a bad
// path early; the mesh files alone define the triangulation). Triangles are named by their position
// in PREFIX.ele counted from 1, as `mwst check` does. --json prints
// {"bundle_number": K, "exact": true, "lower_bound": K, "upper_bound": K, "disk": {"x":…, "y":…,
// "r":…}, "triangles": [...], ...} on stdout.
//
// Budget (--candidate-budget, BundleOptions::candidate_budget): by default at most 12 (circumdisk,
// triangle) candidate pairs per triangle plus 2^20 are kept, which bounds memory (4 bytes a pair)
// and time. When a circumdisk meets more triangles than that allows (points on a circle: every
// circumdisk is about the whole circle), the exact number may be out of reach; the output then
// says so ("exact": false) and gives exact lower and upper bounds, with a witness disk for the
// lower one. --candidate-budget 0 asks for the exact number whatever it costs.
#include <chrono>
#include <future>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <iostream>
#include <memory>
#include <string>
#include <utility>

#include "cli/commands.hpp"
#include "mwst/algorithms/bundle.hpp"
#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/version.hpp"

namespace mwst::cli {

namespace {

struct BundleArgs {
  std::string input;
  std::string prefix;
  bool json = false;
  long long candidate_budget = -1;  // −1: 12 per triangle + 2^20; 0: none
};

std::size_t options_budget(const BundleArgs& a, std::size_t triangles) {
  return a.candidate_budget >= 0 ? static_cast<std::size_t>(a.candidate_budget) : 12 * triangles + (std::size_t{1} << 20);
}

int run_bundle(const BundleArgs& a) {
#ifdef __GLIBC__
  // Large arrays in their own mappings, returned to the system when freed: the input, the covering
  // mesh and each phase's scratch are freed as the computation goes, and glibc's adaptive
  // threshold would otherwise keep them in the heap, where the peak resident size never drops.
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
#endif
  // Each phase's fresh arrays on huge pages: one page fault per 2 MiB rather than per 4 KiB
  // (large_allocations.cpp).
  advise_huge_pages_for_large_allocations();
  // The input graph is read (for its name, and to report a bad input) while the mesh is: the
  // graph itself is not needed. An error in the input is reported first, as if it were read first.
  auto input = std::async(std::launch::async | std::launch::deferred, [&a] { return io::read_input(a.input).source; });
  io::MeshFiles mesh;
  try {
    mesh = io::read_mesh(a.prefix);
  } catch (...) {
    input.get();
    throw;
  }
  const std::string input_source = input.get();
  const std::size_t triangle_count = mesh.triangles.size();
  const auto start = std::chrono::steady_clock::now();
  BundleResult r;
  try {
    BundleOptions options;
    options.candidate_budget = options_budget(a, triangle_count);
    r = bundle_number(std::move(mesh.points), std::move(mesh.triangles), options);  // freed once copied
  } catch (const InputError& e) {
    throw InputError(a.prefix + ".ele", 0, e.what());
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  nlohmann::json triangles = nlohmann::json::array();
  for (const std::uint32_t t : r.triangles) triangles.push_back(t + 1);
  if (a.json) {
    const nlohmann::json j = {
        {"version", kVersionString},
        {"input", input_source},
        {"mesh", a.prefix},
        {"triangle_count", triangle_count},
        {"bundle_number", r.bundle_number},
        {"exact", r.exact},
        {"lower_bound", r.lower_bound},
        {"upper_bound", r.upper_bound},
        {"disk", {{"x", r.disk_center.x}, {"y", r.disk_center.y}, {"r", r.disk_radius}}},
        {"triangles", triangles},
        {"circumdisk_bound", r.circumdisk_bound},
        {"seconds", seconds},
    };
    OutputFiles out;
    out.write_json("-", j);
    out.commit();
    return kExitOk;
  }
  if (r.exact) {
    std::cout << a.prefix << ": bundle number " << r.bundle_number << " (" << triangle_count
              << " triangles; circumdisks of the Delaunay triangles alone give " << r.circumdisk_bound << ")\n";
  } else {
    std::cout << a.prefix << ": bundle number between " << r.lower_bound << " and " << r.upper_bound
              << " (not exact: " << r.truncated_disks << " circumdisks meet more triangles than the candidate budget of "
              << options_budget(a, triangle_count) << " pairs lets them hold; --candidate-budget 0 computes it "
              << "exactly, at a cost that grows with the square of such disks)\n";
  }
  if (r.bundle_number > 0) {
    std::cout.precision(17);
    std::cout << "  witness" << (r.exact ? "" : " of the lower bound") << ": the open disk centred (" << r.disk_center.x
              << ", " << r.disk_center.y << ") of radius " << r.disk_radius << " contains no vertex and meets triangles";
    for (const std::uint32_t t : r.triangles) std::cout << ' ' << t + 1;
    std::cout << '\n';
  }
  return kExitOk;
}

}  // namespace

void register_bundle(CLI::App& app, Action& action) {
  auto args = std::make_shared<BundleArgs>();
  CLI::App* sub = app.add_subcommand(
      "bundle", "Exact bundle number of a mesh PREFIX.node/.ele, with a witness disk and its triangles");
  sub->add_option("INPUT", args->input, "The .node or .poly the mesh was made from")->required();
  sub->add_option("PREFIX", args->prefix, "The mesh files' prefix")->required();
  sub->add_flag("--json", args->json,
                "Print {\"bundle_number\": K, \"disk\": {\"x\", \"y\", \"r\"}, \"triangles\": [...]} "
                "(triangles numbered from 1 in PREFIX.ele)");
  sub->add_option("--candidate-budget", args->candidate_budget,
                  "Keep at most N (circumdisk, triangle) pairs (default 12 per triangle + 2^20); past it the "
                  "output gives exact lower and upper bounds instead of the exact number; 0: no budget")
      ->check(CLI::NonNegativeNumber);
  sub->callback([args, &action] { action = [args] { return run_bundle(*args); }; });
}

}  // namespace mwst::cli
