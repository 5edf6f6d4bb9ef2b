// src/io/cairo_library.cpp — cairo() of cairo_library.hpp: dlopen of libcairo.so.2 (the soname
// cairo has kept since 1.0), then each function by name.
#include "io/cairo_library.hpp"

#include <dlfcn.h>

#include <string>

#include "mwst/algorithms/pipeline.hpp"

namespace mwst::io {
namespace {

constexpr const char* kCairoSoname = "libcairo.so.2";

[[noreturn]] void missing(const std::string& what) {
  throw ResourceError("drawing pictures needs the cairo library (" + std::string(kCairoSoname) +
                      ", Debian package libcairo2): " + what);
}

CairoLibrary load_cairo() {
  // Never closed: the functions stay valid for the rest of the process.
  void* handle = ::dlopen(kCairoSoname, RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) missing(::dlerror());
  CairoLibrary library;
#define MWST_CAIRO_LOAD(name)                                                                  \
  library.name = reinterpret_cast<decltype(library.name)>(::dlsym(handle, "cairo_" #name)); \
  if (library.name == nullptr) missing("it has no function cairo_" #name);
  MWST_CAIRO_FUNCTIONS(MWST_CAIRO_LOAD)
#undef MWST_CAIRO_LOAD
  return library;
}

}  // namespace

const CairoLibrary& cairo() {
  static const CairoLibrary library = load_cairo();
  return library;
}

}  // namespace mwst::io
