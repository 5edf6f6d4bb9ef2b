// mwst/version.hpp — the version of mwst (semantic versioning: from 1.0 a program built against
// MAJOR.x works with any later MAJOR.y, and the shared library's soname is libmwst.so.MAJOR; before
// 1.0 a minor version may change public structs, so a program built against 0.y works with 0.y.z
// and the soname is libmwst.so.0.y). The top-level
// CMakeLists.txt refuses to configure if MWST_VERSION_STRING differs from its project() version.
#pragma once

#define MWST_VERSION_MAJOR 0
#define MWST_VERSION_MINOR 4
#define MWST_VERSION_PATCH 1
#define MWST_VERSION_STRING "0.4.1"

namespace mwst {

inline constexpr int kVersionMajor = MWST_VERSION_MAJOR;
inline constexpr int kVersionMinor = MWST_VERSION_MINOR;
inline constexpr int kVersionPatch = MWST_VERSION_PATCH;
inline constexpr const char* kVersionString = MWST_VERSION_STRING;  // "MAJOR.MINOR.PATCH"

}  // namespace mwst
