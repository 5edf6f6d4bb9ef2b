# cmake/check_layers.cmake — fails when a file includes a header of a higher layer.
#   cmake -DMWST_ROOT=<source tree> -P cmake/check_layers.cmake
#
# The layers, lowest first (docs/DESIGN.md):
#   0 support: include/mwst/{error,export,version}.hpp, src/support/
#   1 geometry: include/mwst/geometry/, src/geometry/
#   2 mesh: include/mwst/mesh/, src/mesh/
#   3 algorithms: include/mwst/algorithms/, src/algorithms/
#   4 io: include/mwst/io/, src/io/
#   5 experiments: src/experiments/
#   6 cli: src/cli/, and the umbrella header include/mwst/mwst.hpp
# A file may include its own layer and any lower one. The build runs this before it compiles a
# layer, so an upward include fails the build; tests/layers/ checks that it does.
cmake_minimum_required(VERSION 3.20)
if(NOT MWST_ROOT)
  message(FATAL_ERROR "usage: cmake -DMWST_ROOT=<source tree> -P check_layers.cmake")
endif()

set(_layers support geometry mesh algorithms io experiments cli)

# The layer of a path relative to the root (a file) or of an include spelling (a header), or -1.
function(_layer_of path out)
  set(rank -1)
  if(path MATCHES "^(include/)?mwst/(error|export|version)\\.hpp$" OR path MATCHES "^(src/)?support/")
    set(rank 0)
  elseif(path MATCHES "^(include/)?mwst/mwst\\.hpp$")
    set(rank 6)
  else()
    set(i 0)
    foreach(layer IN LISTS _layers)
      if(path MATCHES "^include/mwst/${layer}/" OR path MATCHES "^mwst/${layer}/"
         OR path MATCHES "^src/${layer}/" OR path MATCHES "^${layer}/")
        set(rank ${i})
      endif()
      math(EXPR i "${i} + 1")
    endforeach()
  endif()
  set(${out} ${rank} PARENT_SCOPE)
endfunction()

file(GLOB_RECURSE _files RELATIVE ${MWST_ROOT}
  ${MWST_ROOT}/src/*.cpp ${MWST_ROOT}/src/*.hpp ${MWST_ROOT}/include/*.hpp)
set(_violations "")
foreach(file IN LISTS _files)
  _layer_of("${file}" file_rank)
  if(file_rank EQUAL -1)
    list(APPEND _violations "${file}: not in any layer (see cmake/check_layers.cmake)")
    continue()
  endif()
  file(STRINGS ${MWST_ROOT}/${file} includes REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
  foreach(line IN LISTS includes)
    string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*\"([^\"]+)\".*$" "\\1" header "${line}")
    _layer_of("${header}" header_rank)
    if(header_rank EQUAL -1)
      # A header beside the file (same folder), e.g. "quadtree_tree.hpp".
      get_filename_component(dir ${file} DIRECTORY)
      if(EXISTS ${MWST_ROOT}/${dir}/${header})
        continue()
      endif()
      list(APPEND _violations "${file}: includes \"${header}\", which is in no layer")
    elseif(header_rank GREATER file_rank)
      list(GET _layers ${file_rank} from)
      list(GET _layers ${header_rank} to)
      list(APPEND _violations "${file}: the ${from} layer includes \"${header}\" of the higher ${to} layer")
    endif()
  endforeach()
endforeach()
if(_violations)
  list(JOIN _violations "\n  " text)
  message(FATAL_ERROR "layering violations:\n  ${text}")
endif()
