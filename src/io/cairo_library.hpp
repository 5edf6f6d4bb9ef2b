// src/io/cairo_library.hpp — cairo, loaded when the first picture is drawn. Internal to mwst_draw.
//   cairo()  — the functions of libcairo.so.2 that draw.cpp calls, as a table of pointers typed
//              by cairo's own headers (every call is checked against cairo.h), loaded on the first
//              call (thread-safe); a ResourceError (mwst/algorithms/pipeline.hpp) when the library
//              or one of its functions cannot be found.
// Linked in, cairo and the twenty libraries it needs (fontconfig, freetype, X11, png, ...) were
// loaded and relocated at the start of every run of the command line: about 10 ms of CPU per
// process (13.4 against 3.8 ms for a program without them), more than a whole small refinement,
// for pictures that most runs never draw. Loaded on demand, only `mwst draw`, `--draw` and the
// figures pay it.
#pragma once

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>

namespace mwst::io {

// The cairo functions draw.cpp uses, without their "cairo_" prefix.
#define MWST_CAIRO_FUNCTIONS(X) \
  X(arc) \
  X(close_path) \
  X(create) \
  X(destroy) \
  X(fill) \
  X(font_options_create) \
  X(font_options_destroy) \
  X(font_options_set_antialias) \
  X(font_options_set_hint_metrics) \
  X(font_options_set_hint_style) \
  X(font_options_set_subpixel_order) \
  X(image_surface_create) \
  X(line_to) \
  X(move_to) \
  X(new_sub_path) \
  X(paint) \
  X(pdf_surface_create_for_stream) \
  X(pdf_surface_set_metadata) \
  X(restore) \
  X(save) \
  X(select_font_face) \
  X(set_fill_rule) \
  X(set_font_options) \
  X(set_font_size) \
  X(set_line_cap) \
  X(set_line_width) \
  X(set_source_rgb) \
  X(show_text) \
  X(status) \
  X(status_to_string) \
  X(stroke) \
  X(surface_destroy) \
  X(surface_finish) \
  X(surface_flush) \
  X(surface_status) \
  X(surface_write_to_png_stream) \
  X(svg_surface_create_for_stream) \
  X(text_extents)

// Each member is a pointer to the cairo function of its name: cairo().move_to is cairo_move_to.
struct CairoLibrary {
#define MWST_CAIRO_POINTER(name) decltype(&::cairo_##name) name = nullptr;
  MWST_CAIRO_FUNCTIONS(MWST_CAIRO_POINTER)
#undef MWST_CAIRO_POINTER
};

// libcairo.so.2, loaded on the first call and kept for the life of the process.
const CairoLibrary& cairo();

}  // namespace mwst::io
