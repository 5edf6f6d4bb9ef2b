// `mwst check INPUT PREFIX [--delaunay] [--min-angle DEG]`: reads an input graph and the mesh
// PREFIX.node/.ele(/.poly) written for it (by mwst or another mesher, e.g. Triangle) and validates
// the mesh against the input with check_triangulation() (mwst/mesh/check.hpp): orientation, manifold,
// domain coverage, segments present, and optionally constrained Delaunay and a minimum angle.
// Exit 0 if valid; 1 with one "mwst: PREFIX: ..." line per violation on stderr otherwise.
#include <iostream>
#include <memory>
#include <string>

#include "cli/commands.hpp"
#include "mwst/mesh/check.hpp"
#include "mwst/io/triangle_files.hpp"

namespace mwst::cli {

namespace {

struct CheckArgs {
  std::string input;
  std::string prefix;
  bool delaunay = false;
  double min_angle = 0.0;
};

int run_check(const CheckArgs& a) {
  const Pslg input = io::read_input(a.input);
  const io::MeshFiles mesh = io::read_mesh(a.prefix);
  CheckOptions options;
  options.delaunay = a.delaunay;
  options.min_angle_deg = a.min_angle;
  const CheckResult result = check_triangulation(input, mesh.points, mesh.triangles, mesh.segments, options);
  if (!result.ok()) {
    for (const std::string& m : result.messages) std::cerr << "mwst: " << a.prefix << ": " << m << '\n';
    if (result.violations > result.messages.size()) {
      std::cerr << "mwst: " << a.prefix << ": ... and " << result.violations - result.messages.size()
                << " more violations\n";
    }
    return kExitBadInput;
  }
  std::cout << a.prefix << ": valid: " << mesh.triangles.size() << " triangles on "
            << (result.convex_hull ? "the convex hull" : "the domain") << " of " << a.input;
  if (a.delaunay) std::cout << ", constrained Delaunay";
  if (a.min_angle > 0.0) std::cout << ", angles >= " << a.min_angle << " degrees";
  std::cout << '\n';
  return kExitOk;
}

}  // namespace

void register_check(CLI::App& app, Action& action) {
  auto args = std::make_shared<CheckArgs>();
  CLI::App* sub = app.add_subcommand("check", "Validate a mesh PREFIX.node/.ele(/.poly) against its input");
  sub->add_option("INPUT", args->input, "The .node or .poly the mesh was made from")->required();
  sub->add_option("PREFIX", args->prefix, "The mesh files' prefix")->required();
  sub->add_flag("--delaunay", args->delaunay,
                "Also require the constrained Delaunay property (exact incircle test)");
  sub->add_option("--min-angle", args->min_angle, "Also require every angle >= DEG degrees")
      ->check(CLI::Range(0.0, 180.0));
  sub->callback([args, &action] { action = [args] { return run_check(*args); }; });
}

}  // namespace mwst::cli
