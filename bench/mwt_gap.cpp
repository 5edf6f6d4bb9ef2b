// bench/mwt_gap.cpp — how far is a locally minimal mesh from optimal for its own vertex set? For
// each input, the paper's EFH (greedy weight-reducing flips after a method; Boyacı, Erten, Üngör,
// "Triangulations Loosing Bundles and Weight") is compared with the exact minimum weight
// triangulation of the same vertices and segments (exact_mwt, include/mwst/algorithms/mwt.hpp: diamond test,
// LMT-skeleton, polygon DP). This touches the paper's open problem 3, the MWT of a well-spaced
// point set: DR output (minimum angle 20°) is well spaced.
//
// Prints one Markdown row per input: vertices, EFH weight, MWT weight, gap % = (EFH − MWT)/MWT,
// candidate edges, fraction of the MWT's edges fixed by the LMT-skeleton, DP regions (largest),
// route, MWT seconds. "not solved" rows say why (exact_mwt never reports a heuristic as optimal).
//
// --cross-check also runs the visibility route alone (complete candidates, up to 500 vertices) and
// prints the difference of its weight from the reported one (evidence for the diamond route).
//
// Usage: mwt_gap [--n N]... [--seeds S] [--method dt|dr|brh|qtr] [--angle A] [--data DIR] [--cross-check]
//               [--max-visibility V]   (the visibility route's vertex limit, default 500)
//               [--max-crossings C]    (crossing pairs of candidates kept, default 2e7)
//               [--data-method dr|brh] (only one of the two methods on the data sets)
//   default: uniform N = 50, 100, 200, 500, 1000, 2000 (seeds 1..S, S = 3), DR at 20° then EFH;
//   --data DIR: every DIR/*.poly and *.node with DR+EFH and BRH+EFH.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "mwst/io/generate.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/algorithms/mwt.hpp"
#include "mwst/algorithms/pipeline.hpp"

namespace {

bool cross_check = false;
mwst::MwtOptions mwt_options;  // --max-visibility

void header() {
  std::printf("| input | method | vertices | EFH weight | MWT weight | gap %% | candidates | fixed by skeleton | DP regions (largest) | route | MWT s |%s\n",
              cross_check ? " visibility route − reported |" : "");
  std::printf("|---|---|---:|---:|---:|---:|---:|---:|---:|---|---:|%s\n", cross_check ? "---:|" : "");
}

// The visibility route alone, compared with the reported weight.
std::string cross_checked(const mwst::Mesh& mesh, const mwst::MwtResult& r) {
  if (!cross_check) return "";
  mwst::MwtOptions options;
  options.diamond_route = false;
  const mwst::MwtResult v = mwst::exact_mwt(mesh, options);
  if (!v.solved || !r.solved) return " - |";
  char text[64];
  std::snprintf(text, sizeof text, " %.3g |", v.weight - r.weight);
  return text;
}

void row(const std::string& name, const mwst::Pslg& pslg, mwst::Method method, double angle) {
  mwst::TriangulateOptions options;
  options.method = method;
  options.min_angle_deg = angle;
  options.flip = true;
  mwst::Mesh mesh;
  try {
    mwst::triangulate(pslg, options, &mesh);
  } catch (const std::exception& e) {
    std::printf("| %s | %s+efh | - | - | - | - | - | - | - | failed: %s | - |\n", name.c_str(),
                std::string(mwst::method_name(method)).c_str(), e.what());
    return;
  }
  const double efh = mwst::measure(mesh).weight_total;
  const mwst::MwtResult r = mwst::exact_mwt(mesh, mwt_options);
  const std::string method_label = std::string(mwst::method_name(method)) + "+efh";
  if (!r.solved) {
    std::printf("| %s | %s | %zu | %.10g | not solved | - | %zu | %.4f | %zu (%zu) | %s: %s | %.2f |%s\n", name.c_str(),
                method_label.c_str(), r.vertices, efh, r.candidate_edges,
                r.result_edges ? r.fixed_fraction() : 0.0, r.regions, r.largest_region, r.route.c_str(),
                r.reason.c_str(), r.seconds, cross_checked(mesh, r).c_str());
  } else {
    std::printf("| %s | %s | %zu | %.10g | %.10g | %.4f | %zu | %.4f | %zu (%zu) | %s | %.2f |%s\n", name.c_str(),
                method_label.c_str(), r.vertices, efh, r.weight, 100.0 * (efh - r.weight) / r.weight,
                r.candidate_edges, r.fixed_fraction(), r.regions, r.largest_region, r.route.c_str(), r.seconds,
                cross_checked(mesh, r).c_str());
  }
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::size_t> sizes;
  std::size_t seeds = 3;
  std::string data;
  std::string method_text = "dr";
  std::string data_method;  // --data-method: only this one of dr, brh
  double angle = 20.0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "mwt_gap: %s needs a value\n", arg.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (arg == "--n") {
      sizes.push_back(std::stoul(value()));
    } else if (arg == "--seeds") {
      seeds = std::stoul(value());
    } else if (arg == "--data") {
      data = value();
    } else if (arg == "--method") {
      method_text = value();
    } else if (arg == "--angle") {
      angle = std::stod(value());
    } else if (arg == "--max-crossings") {
      mwt_options.max_crossing_pairs = std::stoul(value());
    } else if (arg == "--data-method") {
      data_method = value();
    } else if (arg == "--max-visibility") {
      mwt_options.max_visibility_vertices = std::stoul(value());
    } else if (arg == "--cross-check") {
      cross_check = true;
    } else {
      std::fprintf(stderr, "usage: mwt_gap [--n N]... [--seeds S] [--method M] [--angle A] [--data DIR]\n");
      return 2;
    }
  }
  const auto method = mwst::parse_method(method_text);
  if (!method) {
    std::fprintf(stderr, "mwt_gap: unknown method %s\n", method_text.c_str());
    return 2;
  }
  header();
  if (!data.empty()) {
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(data)) {
      const auto ext = entry.path().extension();
      if (ext == ".poly" || ext == ".node") files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      const mwst::Pslg pslg = mwst::io::read_input(f.string());
      if (data_method.empty() || data_method == "dr") row(f.filename().string(), pslg, mwst::Method::kDr, angle);
      if (data_method.empty() || data_method == "brh") row(f.filename().string(), pslg, mwst::Method::kBrh, angle);
    }
    return 0;
  }
  if (sizes.empty()) sizes = {50, 100, 200, 500, 1000, 2000};
  for (std::size_t n : sizes) {
    for (std::size_t seed = 1; seed <= seeds; ++seed) {
      mwst::Pslg pslg;
      pslg.points = mwst::generate_points(mwst::Distribution::kUniform, n, seed);
      pslg.source = "uniform " + std::to_string(n) + " seed " + std::to_string(seed);
      row(pslg.source, pslg, *method, angle);
    }
  }
  return 0;
}
