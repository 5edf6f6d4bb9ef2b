# cmake/install.cmake — what `cmake --install` writes besides the library, the CLI and the headers:
#   lib/cmake/mwst/mwstConfig.cmake, mwstConfigVersion.cmake (SameMinorVersion before 1.0, then
#     SameMajorVersion, as the soname), mwstTargets.cmake
#     so that another project's find_package(mwst 0.4 CONFIG REQUIRED) gives the target mwst::mwst;
#   lib/pkgconfig/mwst.pc and mwst-draw.pc (the pictures) for builds without CMake.
include(CMakePackageConfigHelpers)

set(MWST_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/mwst)

install(TARGETS mwst mwst_draw mwst_cli EXPORT mwstTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT mwstTargets NAMESPACE mwst:: DESTINATION ${MWST_CMAKE_DIR})

# A static libmwst leaves GMP, its private dependency, to the program that links it:
# the config file then finds them the way the build did (pkg-config), under the same target names.
set(MWST_STATIC_LIBRARY ON)
if(BUILD_SHARED_LIBS)
  set(MWST_STATIC_LIBRARY OFF)
endif()
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/mwstConfig.cmake.in
  ${PROJECT_BINARY_DIR}/mwstConfig.cmake INSTALL_DESTINATION ${MWST_CMAKE_DIR})
if(PROJECT_VERSION_MAJOR EQUAL 0)
  set(MWST_VERSION_COMPATIBILITY SameMinorVersion)
else()
  set(MWST_VERSION_COMPATIBILITY SameMajorVersion)
endif()
write_basic_package_version_file(${PROJECT_BINARY_DIR}/mwstConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY ${MWST_VERSION_COMPATIBILITY})
install(FILES ${PROJECT_BINARY_DIR}/mwstConfig.cmake ${PROJECT_BINARY_DIR}/mwstConfigVersion.cmake
  DESTINATION ${MWST_CMAKE_DIR})

# mwst.pc names its prefix relative to its own place (${pcfiledir}), so that the file stays right
# for `cmake --install build --prefix ANYWHERE`.
file(RELATIVE_PATH MWST_PC_TO_PREFIX "/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/")
string(REGEX REPLACE "/$" "" MWST_PC_TO_PREFIX "${MWST_PC_TO_PREFIX}")
# mwst-draw.pc is the pictures' library (libmwst_draw) on top of mwst.pc; it loads cairo itself
# when it first draws (libcairo.so.2), so nothing links cairo.
if(BUILD_SHARED_LIBS)
  set(MWST_PC_REQUIRES "nlohmann_json")
  set(MWST_PC_REQUIRES_PRIVATE "gmp")
  set(MWST_DRAW_PC_REQUIRES "mwst")
  set(MWST_DRAW_PC_REQUIRES_PRIVATE "")
  set(MWST_PC_CFLAGS "-DMWST_SHARED")
else()
  # A static archive: `pkg-config --libs mwst` must name GMP even without --static.
  set(MWST_PC_REQUIRES "nlohmann_json gmp")
  set(MWST_PC_REQUIRES_PRIVATE "")
  set(MWST_DRAW_PC_REQUIRES "mwst")
  set(MWST_DRAW_PC_REQUIRES_PRIVATE "")
  set(MWST_PC_CFLAGS "")
endif()
configure_file(${PROJECT_SOURCE_DIR}/cmake/mwst.pc.in ${PROJECT_BINARY_DIR}/mwst.pc @ONLY)
configure_file(${PROJECT_SOURCE_DIR}/cmake/mwst-draw.pc.in ${PROJECT_BINARY_DIR}/mwst-draw.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/mwst.pc ${PROJECT_BINARY_DIR}/mwst-draw.pc
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
