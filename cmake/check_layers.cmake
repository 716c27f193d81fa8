# Fails when a file includes a Thicket header (public, "thicket/<folder>/...", or private to src/,
# "<folder>/...") from a layer above its own, so the layers of
# docs/architecture.md stay a ladder, not a loop.
#   cmake -DROOT=<source tree> -P cmake/check_layers.cmake
# A folder is include/thicket/<folder> or src/<folder>; tools/ and tests/ sit on top and are not
# checked. A folder not named below is a structure (so a new structure's folder needs no entry).

cmake_minimum_required(VERSION 3.25)

set(layer_core core)
set(layer_util core util)
set(layer_geometry core geometry)
set(layer_prims core util geometry prims)
set(layer_scene core util geometry prims scene)
set(layer_accel core util geometry prims scene accel)
# The batch queries of the front ends: rows of floats or doubles to answers, point queries,
# crossings, hit columns. Above the interface they call, below nothing that needs them.
set(layer_query core util geometry prims scene accel query)
set(structure_layers core util geometry prims accel)   # plus the structure's own folder
# Instancing sits above the structures: its top level is a bvh8 tree walked by bvh8's kernels,
# whose leaves call a bvh8 bottom's kernel directly (no virtual call per instance).
set(layer_instances core util geometry prims scene accel query bvh8 instances)
set(layer_render core util geometry prims scene accel query instances render)
set(layer_bench core util geometry prims scene accel query instances render bench)
set(named_layers core util geometry prims scene accel query instances render bench)

# A structure built from another declares it here (uses_<folder>): a wide BVH collapses the
# binary one. Any other structure-to-structure include is a violation.
set(uses_bvh8 bvh)
set(uses_obb bvh)     # an OBB tree refits a BVH's topology
set(uses_tetra bvh)   # the tetrahedralization keeps what TetGen refuses in a BVH

# The one crossing the ladder allows: a subdivision surface keeps a BVH over its own patches.
set(exception_files "src/prims/subdivision.cpp:bvh")

if(NOT ROOT)
  message(FATAL_ERROR "usage: cmake -DROOT=<source tree> -P check_layers.cmake")
endif()
file(GLOB_RECURSE files RELATIVE ${ROOT} ${ROOT}/include/thicket/*.h ${ROOT}/src/*.h ${ROOT}/src/*.cpp)
list(LENGTH files file_count)
if(file_count EQUAL 0)
  message(FATAL_ERROR "no sources under ${ROOT}: nothing checked")
endif()

set(violations 0)
foreach(file ${files})
  if(file MATCHES "^include/thicket/([^/]+)/")
    set(folder ${CMAKE_MATCH_1})
  elseif(file MATCHES "^src/([^/]+)/")
    set(folder ${CMAKE_MATCH_1})
  else()
    continue()  # include/thicket/thicket.h: the umbrella header includes every layer
  endif()
  if(folder IN_LIST named_layers)
    set(allowed ${layer_${folder}})
  else()
    set(allowed ${structure_layers} ${folder} ${uses_${folder}})
  endif()
  # Public includes ("thicket/<folder>/...") and private ones ("<folder>/..." of src/, such as
  # "accel/dispatch.h") obey the same table; a public header may not include a private one (it is
  # not installed).
  file(STRINGS ${ROOT}/${file} lines REGEX "^[ \t]*#[ \t]*include[ \t]*\"[a-z0-9_]+/")
  foreach(line ${lines})
    if(line MATCHES "\"thicket/([^/\"]+)/")
      set(target ${CMAKE_MATCH_1})
    elseif(line MATCHES "\"([a-z0-9_]+)/")
      set(target ${CMAKE_MATCH_1})
      if(file MATCHES "^include/")
        message(SEND_ERROR "${file}: a public header may not include the private header of ${target}/ (${line})")
        math(EXPR violations "${violations} + 1")
        continue()
      endif()
    else()
      continue()
    endif()
    if(target IN_LIST allowed OR "${file}:${target}" IN_LIST exception_files)
      continue()
    endif()
    message(SEND_ERROR "${file}: layer '${folder}' may not include ${target}/ (${line})")
    math(EXPR violations "${violations} + 1")
  endforeach()
endforeach()
if(violations GREATER 0)
  message(FATAL_ERROR "${violations} include(s) against the layers (docs/architecture.md)")
endif()
message(STATUS "layers: ${file_count} files, every include points down")
