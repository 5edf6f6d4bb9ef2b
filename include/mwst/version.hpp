// mwst/version.hpp — the version of mwst (semantic versioning: a program built against MAJOR.x
// works with any later MAJOR.y; the shared library's soname is libmwst.so.MAJOR). The top-level
// CMakeLists.txt refuses to configure if MWST_VERSION_STRING differs from its project() version.
#pragma once

#define MWST_VERSION_MAJOR 0
#define MWST_VERSION_MINOR 2
#define MWST_VERSION_PATCH 0
#define MWST_VERSION_STRING "0.2.0"

namespace mwst {

inline constexpr int kVersionMajor = MWST_VERSION_MAJOR;
inline constexpr int kVersionMinor = MWST_VERSION_MINOR;
inline constexpr int kVersionPatch = MWST_VERSION_PATCH;
inline constexpr const char* kVersionString = MWST_VERSION_STRING;  // "MAJOR.MINOR.PATCH"

}  // namespace mwst
