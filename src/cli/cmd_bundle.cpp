// `mwst bundle INPUT PREFIX [--json]`: the exact bundle number (mwst/bundle.hpp) of the mesh
// PREFIX.node/.ele — the largest k such that some open disk containing no mesh vertex meets the
// interiors of k triangles (Boyacı, Erten, Üngör, "Triangulations Loosing Bundles and Weight") —
// with a witness disk and its triangles. Any triangulation is accepted (Delaunay or not, any domain,
// holes included); INPUT is the graph the mesh was made for (read for its name and to report a bad
// path early; the mesh files alone define the triangulation). Triangles are named by their position
// in PREFIX.ele counted from 1, as `mwst check` does. --json prints
// {"bundle_number": K, "disk": {"x":…, "y":…, "r":…}, "triangles": [...], ...} on stdout.
#include <chrono>
#include <iostream>
#include <memory>
#include <string>

#include "cli/commands.hpp"
#include "mwst/bundle.hpp"
#include "mwst/error.hpp"
#include "mwst/io.hpp"
#include "mwst/version.hpp"

namespace mwst::cli {

namespace {

struct BundleArgs {
  std::string input;
  std::string prefix;
  bool json = false;
};

int run_bundle(const BundleArgs& a) {
  const Pslg input = io::read_input(a.input);
  const io::MeshFiles mesh = io::read_mesh(a.prefix);
  const auto start = std::chrono::steady_clock::now();
  BundleResult r;
  try {
    r = bundle_number(mesh.points, mesh.triangles);
  } catch (const InputError& e) {
    throw InputError(a.prefix + ".ele", 0, e.what());
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  nlohmann::json triangles = nlohmann::json::array();
  for (const std::uint32_t t : r.triangles) triangles.push_back(t + 1);
  if (a.json) {
    const nlohmann::json j = {
        {"version", kVersionString},
        {"input", input.source},
        {"mesh", a.prefix},
        {"triangle_count", mesh.triangles.size()},
        {"bundle_number", r.bundle_number},
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
  std::cout << a.prefix << ": bundle number " << r.bundle_number << " (" << mesh.triangles.size()
            << " triangles; circumdisks of the Delaunay triangles alone give " << r.circumdisk_bound << ")\n";
  if (r.bundle_number > 0) {
    std::cout.precision(17);
    std::cout << "  witness: the open disk centred (" << r.disk_center.x << ", " << r.disk_center.y
              << ") of radius " << r.disk_radius << " contains no vertex and meets triangles";
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
  sub->callback([args, &action] { action = [args] { return run_bundle(*args); }; });
}

}  // namespace mwst::cli
