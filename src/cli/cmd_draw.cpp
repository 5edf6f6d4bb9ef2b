// `mwst draw INPUT PREFIX -o FILE.png|.svg|.pdf [--size N] [--title TEXT]`: a picture of the mesh
// PREFIX.node/.ele made for INPUT, drawn by the renderer of mwst/io/draw.hpp as the figures of Boyacı,
// Erten, Üngör, "Triangulations Loosing Bundles and Weight" show triangulations: thin edges, input
// segments and the domain boundary bold, Steiner points (mesh vertices that are not input points)
// marked. Any triangulation is accepted (mwst's, Triangle's, ...); the format follows the extension.
#include <memory>
#include <string>

#include "cli/commands.hpp"
#include "mwst/io/draw.hpp"
#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"

namespace mwst::cli {

namespace {

struct DrawArgs {
  std::string input;
  std::string prefix;
  std::string output;
  double size = 800.0;
  std::string title;
  bool title_given = false;
};

int run_draw(const DrawArgs& a) {
  io::PictureFormat format;
  try {
    format = io::picture_format(a.output);
  } catch (const InputError& e) {
    throw UsageError(e.located());
  }
  for (const char* ext : {".node", ".ele", ".poly"}) refuse_overwrite(a.prefix + ext, a.output);
  refuse_overwrite(a.input, a.output);

  const Pslg input = io::read_input(a.input);
  const io::MeshFiles mesh = io::read_mesh(a.prefix);
  io::Picture picture;
  try {
    picture = io::picture_of(mesh, input);
  } catch (const InputError& e) {
    throw InputError(a.prefix + ".ele", 0, e.what());
  }
  if (a.title_given) {
    picture.title = a.title;
  } else {
    picture.title = a.prefix + ": " + std::to_string(mesh.triangles.size()) + " triangles, " +
                    std::to_string(picture.marked.size()) + " Steiner points";
  }
  io::DrawOptions options;
  options.panel_size = a.size;
  OutputFiles out;
  out.write(a.output, io::render_pictures({picture}, format, options));
  out.commit();
  return kExitOk;
}

}  // namespace

void register_draw(CLI::App& app, Action& action) {
  auto args = std::make_shared<DrawArgs>();
  CLI::App* sub = app.add_subcommand(
      "draw", "Draw a mesh PREFIX.node/.ele to a PNG, SVG or PDF picture (segments bold, Steiner points marked)");
  sub->add_option("INPUT", args->input, "The .node or .poly the mesh was made from (its segments are drawn bold)")
      ->type_name("FILE")
      ->required();
  sub->add_option("PREFIX", args->prefix, "The mesh files' prefix")->required();
  sub->add_option("-o,--output", args->output, "The picture: FILE.png, FILE.svg or FILE.pdf")
      ->type_name("FILE")
      ->required();
  sub->add_option("--size", args->size, "Larger side of the drawing in pixels (PNG) or points (SVG, PDF)")
      ->check(CLI::Range(16.0, 16000.0))
      ->capture_default_str();
  CLI::Option* title = sub->add_option("--title", args->title,
                                       "Title above the drawing (default: PREFIX and the counts; '' for none)");
  sub->callback([args, title, &action] {
    args->title_given = title->count() > 0;
    action = [args] { return run_draw(*args); };
  });
}

}  // namespace mwst::cli
