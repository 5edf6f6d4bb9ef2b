// mwst/export.hpp — MWST_API marks the functions and classes libmwst exports. The library is
// compiled with hidden symbols (-fvisibility=hidden), so a shared libmwst.so exports exactly the
// declarations of include/mwst/ that carry MWST_API and keeps its internals to itself.
// MWST_SHARED is defined for the library and its users when it is built shared (CMake and
// mwst.pc pass it on); MWST_BUILDING_LIBRARY only while compiling the library itself. On ELF
// platforms the same default visibility serves both; Windows needs dllexport / dllimport.
#pragma once

#if defined(_WIN32) || defined(__CYGWIN__)
#if defined(MWST_SHARED) && defined(MWST_BUILDING_LIBRARY)
#define MWST_API __declspec(dllexport)
#elif defined(MWST_SHARED)
#define MWST_API __declspec(dllimport)
#else
#define MWST_API
#endif
#elif defined(__GNUC__)
#define MWST_API __attribute__((visibility("default")))
#else
#define MWST_API
#endif

// The inline predicate filters of mwst/geometry/geometry.hpp rely on IEEE double arithmetic as written:
// -ffast-math (which reassociates and drops the error terms) would make their signs wrong.
#if defined(__FAST_MATH__)
#error "mwst's exact predicates need IEEE arithmetic: do not compile with -ffast-math"
#endif
