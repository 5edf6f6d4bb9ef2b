// src/io/draw.cpp — pictures of triangulations with cairo (mwst/io/draw.hpp): the renderer behind
// `mwst draw`, `mwst triangulate --draw` and the Figure 4 panels of `mwst experiment` (the side by
// side pictures of DT, QTR, DR, BRH, BRH+EFH of Boyacı, Erten, Üngör, "Triangulations Loosing
// Bundles and Weight", plus our optimiser).
//
// Layout: panels of equal size in a grid (options.columns per row), each with a title band above
// it; every drawing is fitted to its panel keeping its aspect ratio (y points up, as in the data).
// Drawing order per panel: the triangles filled, the distinct edges stroked thin (each once), the
// bold segments, then the Steiner point disks; each in paths of at most kStrokeBatch pieces, since
// cairo's rasteriser slows down sharply on one path of very many pieces. PNG is
// rendered into an image surface and encoded by cairo; SVG and PDF go through cairo's stream
// surfaces. Everything is rendered into memory and written at once, so a failure leaves no file.
// cairo's functions come from cairo() (io/cairo_library.hpp), loaded by the first drawing.
#include "mwst/io/draw.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

#include "io/cairo_library.hpp"
#include "mwst/error.hpp"

namespace mwst::io {

namespace {

// ---- pictures from meshes ----------------------------------------------------------------------

struct PointHash {
  std::size_t operator()(const Point& p) const noexcept {
    std::uint64_t a = 0;
    std::uint64_t b = 0;
    // +0.0 and -0.0 compare equal, so they must hash equal.
    const double x = p.x == 0.0 ? 0.0 : p.x;
    const double y = p.y == 0.0 ? 0.0 : p.y;
    std::memcpy(&a, &x, sizeof a);
    std::memcpy(&b, &y, sizeof b);
    return static_cast<std::size_t>(a * 0x9E3779B97F4A7C15ull ^ (b + 0x632BE59BD9B4E019ull + (a << 6)));
  }
};

// ---- rendering ---------------------------------------------------------------------------------

// Edges per stroked path and triangles per filled path: cairo's rasteriser slows down sharply on
// one path of very many pieces.
constexpr std::size_t kStrokeBatch = 256;

struct Box {
  double min_x = 0.0, min_y = 0.0, max_x = 0.0, max_y = 0.0;
  bool empty = true;
  void add(const Point& p) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) return;
    if (empty) {
      min_x = max_x = p.x;
      min_y = max_y = p.y;
      empty = false;
      return;
    }
    min_x = std::min(min_x, p.x);
    max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y);
    max_y = std::max(max_y, p.y);
  }
  double width() const { return max_x - min_x; }
  double height() const { return max_y - min_y; }
};

Box bounding_box(const Picture& picture) {
  Box box;
  for (const auto& tri : picture.triangles) {
    for (const std::uint32_t v : tri) {
      if (v < picture.points.size()) box.add(picture.points[v]);
    }
  }
  for (const auto& s : picture.bold_segments) {
    box.add(s[0]);
    box.add(s[1]);
  }
  for (const std::uint32_t v : picture.marked) {
    if (v < picture.points.size()) box.add(picture.points[v]);
  }
  return box;
}

// Height over width of the drawing, kept in [1/5, 5] so that a degenerate picture (a sliver, a
// single segment) still gets a usable panel.
double aspect_of(const Box& box) {
  if (box.empty || !(box.width() > 0.0) || !(box.height() > 0.0)) return 1.0;
  return std::clamp(box.height() / box.width(), 0.2, 5.0);
}

// Maps data coordinates into a panel rectangle (x0, y0, w, h), centred, aspect ratio kept, y up.
class Transform {
 public:
  Transform(const Box& box, double x0, double y0, double w, double h) {
    const double bw = box.empty ? 1.0 : box.width();
    const double bh = box.empty ? 1.0 : box.height();
    const double sx = bw > 0.0 ? w / bw : 0.0;
    const double sy = bh > 0.0 ? h / bh : 0.0;
    scale_ = (sx > 0.0 && sy > 0.0) ? std::min(sx, sy) : std::max({sx, sy, 1.0});
    const double cx = box.empty ? 0.0 : 0.5 * (box.min_x + box.max_x);
    const double cy = box.empty ? 0.0 : 0.5 * (box.min_y + box.max_y);
    ox_ = x0 + 0.5 * w - scale_ * cx;
    oy_ = y0 + 0.5 * h + scale_ * cy;
  }
  double x(const Point& p) const { return ox_ + scale_ * p.x; }
  double y(const Point& p) const { return oy_ - scale_ * p.y; }

 private:
  double scale_ = 1.0, ox_ = 0.0, oy_ = 0.0;
};

void set_font(cairo_t* cr, double size, bool bold) {
  cairo().select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo().set_font_size(cr, size);
}

// Draws `text` centred on x at baseline y, shrunk to fit max_width if needed.
void centred_text(cairo_t* cr, const std::string& text, double x, double y, double size, double max_width,
                  bool bold) {
  if (text.empty()) return;
  set_font(cr, size, bold);
  cairo_text_extents_t ext;
  cairo().text_extents(cr, text.c_str(), &ext);
  if (ext.x_advance > max_width && ext.x_advance > 0.0) {
    set_font(cr, size * max_width / ext.x_advance, bold);
    cairo().text_extents(cr, text.c_str(), &ext);
  }
  cairo().move_to(cr, x - 0.5 * ext.x_advance, y);
  cairo().show_text(cr, text.c_str());
}

// Splits a note into lines of at most ~max_chars characters at spaces.
std::vector<std::string> wrap(const std::string& text, std::size_t max_chars) {
  std::vector<std::string> lines;
  std::string line;
  std::size_t i = 0;
  while (i < text.size()) {
    std::size_t j = text.find(' ', i);
    if (j == std::string::npos) j = text.size();
    const std::string word = text.substr(i, j - i);
    if (!line.empty() && line.size() + 1 + word.size() > max_chars) {
      lines.push_back(line);
      line.clear();
    }
    if (!line.empty()) line += ' ';
    line += word;
    i = j + 1;
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

// The triangles, filled in batches (the seams between batches lie under the stroked edges).
void fill_triangles(cairo_t* cr, const Picture& pic, const Transform& tf) {
  cairo().set_fill_rule(cr, CAIRO_FILL_RULE_WINDING);
  cairo().set_source_rgb(cr, 0.91, 0.94, 0.98);
  std::size_t in_path = 0;
  for (const auto& tri : pic.triangles) {
    if (++in_path == kStrokeBatch) {
      cairo().fill(cr);
      in_path = 1;
    }
    if (tri[0] >= pic.points.size() || tri[1] >= pic.points.size() || tri[2] >= pic.points.size()) continue;
    const Point& a = pic.points[tri[0]];
    const Point& b = pic.points[tri[1]];
    const Point& c = pic.points[tri[2]];
    cairo().move_to(cr, tf.x(a), tf.y(a));
    cairo().line_to(cr, tf.x(b), tf.y(b));
    cairo().line_to(cr, tf.x(c), tf.y(c));
    cairo().close_path(cr);
  }
  cairo().fill(cr);
}

// The distinct edges of the triangles (lower vertex first, sorted), each once.
std::vector<std::pair<std::uint32_t, std::uint32_t>> distinct_edges(const Picture& pic) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  edges.reserve(3 * pic.triangles.size());
  for (const auto& tri : pic.triangles) {
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t a = tri[static_cast<std::size_t>(i)];
      const std::uint32_t b = tri[static_cast<std::size_t>((i + 1) % 3)];
      if (a >= pic.points.size() || b >= pic.points.size()) continue;
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

// Strokes the distinct edges thin, each once, in batches; when `shortest` is not empty, records
// there the shortest edge drawn at each point (pixels).
void stroke_edges(cairo_t* cr, const Picture& pic, const Transform& tf, double edge_width,
                  std::vector<double>& shortest) {
  const std::vector<std::pair<std::uint32_t, std::uint32_t>> edges = distinct_edges(pic);
  cairo().set_source_rgb(cr, 0.25, 0.35, 0.55);
  cairo().set_line_width(cr, edge_width);
  cairo().set_line_cap(cr, CAIRO_LINE_CAP_BUTT);  // round caps on thin lines cost much, show nothing
  std::size_t in_path = 0;
  for (const auto& [a, b] : edges) {
    if (++in_path == kStrokeBatch) {
      cairo().stroke(cr);
      in_path = 1;
    }
    const double ax = tf.x(pic.points[a]), ay = tf.y(pic.points[a]);
    const double bx = tf.x(pic.points[b]), by = tf.y(pic.points[b]);
    cairo().move_to(cr, ax, ay);
    cairo().line_to(cr, bx, by);
    if (!shortest.empty()) {
      const double len = std::hypot(bx - ax, by - ay);
      shortest[a] = std::min(shortest[a], len);
      shortest[b] = std::min(shortest[b], len);
    }
  }
  cairo().stroke(cr);
}

// The input segments and the domain boundary, bold, in one path.
void stroke_bold_segments(cairo_t* cr, const Picture& pic, const Transform& tf, double bold_width) {
  for (const auto& s : pic.bold_segments) {
    cairo().move_to(cr, tf.x(s[0]), tf.y(s[0]));
    cairo().line_to(cr, tf.x(s[1]), tf.y(s[1]));
  }
  cairo().set_source_rgb(cr, 0.0, 0.0, 0.0);
  cairo().set_line_width(cr, bold_width);
  cairo().set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  cairo().stroke(cr);
}

// The Steiner points: disks of radius `marker_radius`, but no wider than a third of the shortest
// edge at the point (and at least a quarter of `marker_radius`), filled in batches.
void fill_steiner_disks(cairo_t* cr, const Picture& pic, const Transform& tf, const std::vector<double>& shortest,
                        double marker_radius) {
  cairo().set_source_rgb(cr, 0.85, 0.1, 0.1);
  std::size_t in_path = 0;
  for (const std::uint32_t v : pic.marked) {
    if (v >= pic.points.size()) continue;
    if (++in_path == kStrokeBatch) {
      cairo().fill(cr);
      in_path = 1;
    }
    const double r = std::clamp(shortest[v] / 3.0, 0.25 * marker_radius, marker_radius);
    cairo().new_sub_path(cr);
    cairo().arc(cr, tf.x(pic.points[v]), tf.y(pic.points[v]), r, 0.0, 2.0 * std::numbers::pi);
  }
  cairo().fill(cr);
}

// A note (e.g. why a method gave no mesh), wrapped and centred in the panel (x0, y0, w, h).
void draw_note(cairo_t* cr, const std::string& note, double x0, double y0, double w, double h, double size) {
  const auto max_chars = static_cast<std::size_t>(std::max(10.0, 1.8 * w / size));
  const std::vector<std::string> lines = wrap(note, max_chars);
  const double line_height = 1.3 * size;
  double y = y0 + 0.5 * h - 0.5 * line_height * static_cast<double>(lines.size()) + size;
  cairo().set_source_rgb(cr, 0.45, 0.1, 0.1);
  for (const std::string& line : lines) {
    centred_text(cr, line, x0 + 0.5 * w, y, size, w, false);
    y += line_height;
  }
}

// Draws one picture fitted into the panel (x0, y0, w, h): triangles, edges, bold segments,
// Steiner point disks, note.
void draw_panel(cairo_t* cr, const Picture& pic, double x0, double y0, double w, double h,
                const DrawOptions& o) {
  const Box box = bounding_box(pic);
  const Transform tf(box, x0, y0, w, h);
  // Shortest drawn edge at each point (pixels), for the size of the Steiner point disks.
  std::vector<double> shortest(pic.marked.empty() ? 0 : pic.points.size(), std::numeric_limits<double>::infinity());
  if (!pic.triangles.empty()) {
    fill_triangles(cr, pic, tf);
    stroke_edges(cr, pic, tf, o.edge_width, shortest);
  }
  if (!pic.bold_segments.empty()) stroke_bold_segments(cr, pic, tf, o.bold_width);
  if (!pic.marked.empty() && o.marker_radius > 0.0) fill_steiner_disks(cr, pic, tf, shortest, o.marker_radius);
  if (!pic.note.empty()) draw_note(cr, pic.note, x0, y0, w, h, o.font_size);
}

void check_cairo(cairo_status_t status, const char* what) {
  if (status != CAIRO_STATUS_SUCCESS) {
    throw InternalError(std::string("cairo: ") + what + ": " + cairo().status_to_string(status));
  }
}

cairo_status_t append_to_string(void* closure, const unsigned char* data, unsigned int length) {
  auto* out = static_cast<std::string*>(closure);
  try {
    out->append(reinterpret_cast<const char*>(data), length);
  } catch (...) {
    return CAIRO_STATUS_NO_MEMORY;
  }
  return CAIRO_STATUS_SUCCESS;
}

// SOURCE_DATE_EPOCH (seconds since 1970, UTC) as ISO 8601, if set and valid.
std::optional<std::string> source_date_epoch() {
  const char* text = std::getenv("SOURCE_DATE_EPOCH");
  if (text == nullptr || *text == '\0') return std::nullopt;
  char* end = nullptr;
  const long long seconds = std::strtoll(text, &end, 10);
  if (*end != '\0' || seconds < 0) return std::nullopt;
  const auto t = static_cast<std::time_t>(seconds);
  std::tm utc{};
  if (gmtime_r(&t, &utc) == nullptr) return std::nullopt;
  char buf[32];
  if (std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &utc) == 0) return std::nullopt;
  return std::string(buf);
}

struct SurfaceDeleter {
  void operator()(cairo_surface_t* s) const { cairo().surface_destroy(s); }
};
struct ContextDeleter {
  void operator()(cairo_t* c) const { cairo().destroy(c); }
};

// The page: every panel gets the same cell (a margin around it, a title band above the drawing
// when any panel has a title), its shape following the tallest drawing (aspect clamped); the
// cells fill rows of `columns` below the caption band.
struct PageLayout {
  double draw_w = 0.0, draw_h = 0.0;  // the drawing area of a panel
  double margin = 0.0, title_band = 0.0, caption_band = 0.0;
  double cell_w = 0.0, cell_h = 0.0;
  std::size_t columns = 1;
  double width = 0.0, height = 0.0;  // of the whole page, whole pixels (points)
};

// Lays out `panels` (not empty) with the sizes of `o`.
PageLayout page_layout(const std::vector<Picture>& panels, const DrawOptions& o) {
  PageLayout page;
  double aspect = 0.0;
  for (const Picture& pic : panels) aspect = std::max(aspect, aspect_of(bounding_box(pic)));
  page.draw_w = aspect <= 1.0 ? o.panel_size : o.panel_size / aspect;
  page.draw_h = aspect <= 1.0 ? o.panel_size * aspect : o.panel_size;
  bool any_title = false;
  for (const Picture& pic : panels) any_title = any_title || !pic.title.empty();
  page.margin = std::max(8.0, 0.8 * o.font_size);
  page.title_band = any_title ? 1.8 * o.font_size : 0.0;
  page.caption_band = o.caption.empty() ? 0.0 : 2.2 * o.font_size;
  page.cell_w = page.draw_w + 2.0 * page.margin;
  page.cell_h = page.draw_h + page.title_band + 2.0 * page.margin;
  page.columns = o.columns == 0 ? panels.size() : std::min(o.columns, panels.size());
  const std::size_t rows = (panels.size() + page.columns - 1) / page.columns;
  page.width = std::ceil(page.cell_w * static_cast<double>(page.columns));
  page.height = std::ceil(page.caption_band + page.cell_h * static_cast<double>(rows));
  return page;
}

// A cairo surface of `format` and the page's size: an image for PNG; for SVG and PDF a stream
// surface appending to `bytes`.
std::unique_ptr<cairo_surface_t, SurfaceDeleter> create_surface(PictureFormat format, double width, double height,
                                                                std::string& bytes) {
  std::unique_ptr<cairo_surface_t, SurfaceDeleter> surface;
  switch (format) {
    case PictureFormat::kPng:
      if (width > 32767.0 || height > 32767.0) throw InputError("", 0, "the picture would be too large for PNG");
      surface.reset(cairo().image_surface_create(CAIRO_FORMAT_ARGB32, static_cast<int>(width), static_cast<int>(height)));
      break;
    case PictureFormat::kSvg:
      surface.reset(cairo().svg_surface_create_for_stream(append_to_string, &bytes, width, height));
      break;
    case PictureFormat::kPdf:
      surface.reset(cairo().pdf_surface_create_for_stream(append_to_string, &bytes, width, height));
      cairo().pdf_surface_set_metadata(surface.get(), CAIRO_PDF_METADATA_CREATOR, "mwst");
      // The reproducible-builds convention: SOURCE_DATE_EPOCH, when set, is the creation date, so
      // that the same drawing gives the same bytes (otherwise cairo writes the current time).
      if (const std::optional<std::string> date = source_date_epoch()) {
        cairo().pdf_surface_set_metadata(surface.get(), CAIRO_PDF_METADATA_CREATE_DATE, date->c_str());
      }
      break;
  }
  check_cairo(cairo().surface_status(surface.get()), "creating the surface");
  return surface;
}

// Every font option explicit: cairo resolves its toy font face once per process with the options
// of the first surface that uses it, so leaving them to the surface would make the text of a PNG
// depend on whether a PDF was drawn before it (on another thread, say).
void set_font_options(cairo_t* cr) {
  cairo_font_options_t* font = cairo().font_options_create();
  cairo().font_options_set_antialias(font, CAIRO_ANTIALIAS_GRAY);
  cairo().font_options_set_subpixel_order(font, CAIRO_SUBPIXEL_ORDER_RGB);
  cairo().font_options_set_hint_style(font, CAIRO_HINT_STYLE_NONE);
  cairo().font_options_set_hint_metrics(font, CAIRO_HINT_METRICS_OFF);
  cairo().set_font_options(cr, font);
  cairo().font_options_destroy(font);
}

// Draws the page onto `surface`: white background, the caption, then each panel's title and
// drawing in its cell.
void draw_page(cairo_surface_t* surface, const std::vector<Picture>& panels, const PageLayout& page,
               const DrawOptions& o) {
  std::unique_ptr<cairo_t, ContextDeleter> context(cairo().create(surface));
  cairo_t* cr = context.get();
  check_cairo(cairo().status(cr), "creating the context");
  set_font_options(cr);
  cairo().set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo().paint(cr);
  if (!o.caption.empty()) {
    cairo().set_source_rgb(cr, 0.0, 0.0, 0.0);
    centred_text(cr, o.caption, 0.5 * page.width, 1.5 * o.font_size, 1.2 * o.font_size, page.width - 2.0 * page.margin,
                 true);
  }
  for (std::size_t i = 0; i < panels.size(); ++i) {
    const double x0 = page.cell_w * static_cast<double>(i % page.columns);
    const double y0 = page.caption_band + page.cell_h * static_cast<double>(i / page.columns);
    const Picture& pic = panels[i];
    if (!pic.title.empty()) {
      cairo().set_source_rgb(cr, 0.0, 0.0, 0.0);
      centred_text(cr, pic.title, x0 + 0.5 * page.cell_w, y0 + page.margin + 1.1 * o.font_size, o.font_size,
                   page.draw_w, false);
    }
    cairo().save(cr);
    draw_panel(cr, pic, x0 + page.margin, y0 + page.margin + page.title_band, page.draw_w, page.draw_h, o);
    cairo().restore(cr);
  }
  check_cairo(cairo().status(cr), "drawing");
}

// Completes the document: a PNG is encoded into `bytes`; SVG and PDF are finished (their stream
// already appends to `bytes`).
void finish_surface(cairo_surface_t* surface, PictureFormat format, std::string& bytes) {
  if (format == PictureFormat::kPng) {
    cairo().surface_flush(surface);
    check_cairo(cairo().surface_write_to_png_stream(surface, append_to_string, &bytes), "encoding PNG");
  } else {
    cairo().surface_finish(surface);
    check_cairo(cairo().surface_status(surface), "finishing the document");
  }
}

}  // namespace

Picture picture_of(const Mesh& mesh) {
  Picture pic;
  pic.points = mesh.points;
  std::vector<bool> used(mesh.points.size(), false);
  for (TriangleId t = 0; t < mesh.triangles.size(); ++t) {
    if (!mesh.in_domain(t)) continue;
    const auto& v = mesh.triangles[t].v;
    pic.triangles.push_back({v[0], v[1], v[2]});
    for (unsigned e = 0; e < 3; ++e) {
      used[v[e]] = true;
      const Handle h = make_handle(t, e);
      const TriangleId other = triangle_of(mesh.sym(h));
      const bool other_in = mesh.in_domain(other);
      // A boundary edge is seen from one domain triangle only; a segment between two domain
      // triangles from both: take it from the lower-numbered one.
      if (!other_in || (mesh.is_segment(h) && t < other)) {
        pic.bold_segments.push_back({mesh.points[mesh.org(h)], mesh.points[mesh.dest(h)]});
      }
    }
  }
  for (VertexId v = 0; v < used.size(); ++v) {
    if (!used[v] || v >= mesh.vertex_kind.size()) continue;
    const VertexKind kind = mesh.vertex_kind[v];
    if (kind == VertexKind::kSteiner || kind == VertexKind::kSteinerOnSegment) pic.marked.push_back(v);
  }
  return pic;
}

Picture picture_of(const MeshFiles& mesh, const Pslg& input) {
  Picture pic;
  pic.points = mesh.points;
  pic.triangles = mesh.triangles;
  const std::unordered_set<Point, PointHash> input_points(input.points.begin(), input.points.end());
  std::vector<bool> used(mesh.points.size(), false);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (const auto& tri : mesh.triangles) {
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t a = tri[static_cast<std::size_t>(i)];
      const std::uint32_t b = tri[static_cast<std::size_t>((i + 1) % 3)];
      if (a >= mesh.points.size() || b >= mesh.points.size()) {
        throw InputError("", 0, "a triangle names vertex " + std::to_string(std::max(a, b) + 1) +
                                    " of only " + std::to_string(mesh.points.size()));
      }
      used[a] = true;
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  // Boundary edges: those of exactly one triangle.
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) pic.bold_segments.push_back({mesh.points[edges[i].first], mesh.points[edges[i].second]});
    i = j;
  }
  for (const Segment& s : input.segments) {
    if (s.a < input.points.size() && s.b < input.points.size()) {
      pic.bold_segments.push_back({input.points[s.a], input.points[s.b]});
    }
  }
  for (std::size_t v = 0; v < mesh.points.size(); ++v) {
    if (used[v] && !input_points.contains(mesh.points[v])) pic.marked.push_back(static_cast<std::uint32_t>(v));
  }
  return pic;
}

PictureFormat picture_format(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  std::string ext;
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) ext = path.substr(dot + 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == "png") return PictureFormat::kPng;
  if (ext == "svg") return PictureFormat::kSvg;
  if (ext == "pdf") return PictureFormat::kPdf;
  throw InputError(path, 0, "unknown picture format '" + (ext.empty() ? std::string("(none)") : "." + ext) +
                                "': the name must end in .png, .svg or .pdf");
}

// The steps: page_layout, create_surface, draw_page (draw_panel per picture), finish_surface.
std::string render_pictures(const std::vector<Picture>& panels, PictureFormat format, const DrawOptions& o) {
  if (panels.empty()) throw InputError("", 0, "nothing to draw");
  if (!(o.panel_size > 0.0) || !std::isfinite(o.panel_size)) {
    throw InputError("", 0, "the panel size must be a positive number");
  }
  const PageLayout page = page_layout(panels, o);
  std::string bytes;
  const std::unique_ptr<cairo_surface_t, SurfaceDeleter> surface = create_surface(format, page.width, page.height, bytes);
  draw_page(surface.get(), panels, page, o);
  finish_surface(surface.get(), format, bytes);
  return bytes;
}

void draw_pictures(const std::vector<Picture>& panels, const std::string& path, const DrawOptions& options) {
  const PictureFormat format = picture_format(path);
  write_file_atomic(path, render_pictures(panels, format, options));
}

}  // namespace mwst::io
