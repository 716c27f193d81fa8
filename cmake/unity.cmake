# thicket_unity_by_folder(target [BATCH n]): compile target's sources as unity units, each made of
# files of one folder only (at most n of them, default 8), so that a unit parses the library's
# headers and instantiates their templates once for several files. Folders keep their files
# together because a folder is one concept (one structure, the scene loaders): file-local names of
# two structures never meet in one unit, and a folder's own files are written not to clash.
# Sources marked SKIP_UNITY_BUILD_INCLUSION (per-ISA kernels, files whose headers clash) stay alone.
# Off with -DTHICKET_UNITY=OFF, which checks that every file includes what it uses.
#
# The units are written here rather than by CMake's UNITY_BUILD, which puts them in each build
# directory: a unit's path is part of what ccache hashes, so the same library compiled again in
# another tree (the add_subdirectory package test, `pip install .`) missed the cache on every unit
# and recompiled the library (~3 minutes of CI each). A unit is named by its contents' hash and
# written once, in THICKET_UNITY_DIR; trees that name the same directory compile the same files.
#
# Sources marked THICKET_COLD (code that runs once per load, never per ray or per primitive of a
# build: the JSON and glTF loaders) form units of their own, compiled at -O1 in optimized builds.
set(THICKET_COLD_OPT $<$<CONFIG:Release,RelWithDebInfo,MinSizeRel>:-O1>)
set(THICKET_UNITY_DIR "${PROJECT_BINARY_DIR}/unity" CACHE PATH
    "Where the unity units are written; build trees of the same sources that name one directory share ccache hits")
function(thicket_unity_by_folder target)
  cmake_parse_arguments(ARG "" "BATCH" "" ${ARGN})
  if(NOT ARG_BATCH)
    set(ARG_BATCH 8)
  endif()
  get_target_property(sources ${target} SOURCES)
  get_target_property(source_dir ${target} SOURCE_DIR)
  if(NOT THICKET_UNITY)
    foreach(source ${sources})
      get_source_file_property(cold ${source} THICKET_COLD)
      if(cold)
        set_source_files_properties(${source} PROPERTIES COMPILE_OPTIONS "${THICKET_COLD_OPT}")
      endif()
    endforeach()
    return()
  endif()
  set(groups)
  foreach(source ${sources})
    if(NOT source MATCHES "\\.cpp$")
      continue()
    endif()
    get_source_file_property(skip ${source} SKIP_UNITY_BUILD_INCLUSION)
    if(skip)
      continue()
    endif()
    set(path ${source})
    if(NOT IS_ABSOLUTE ${path})
      set(path ${source_dir}/${source})
    endif()
    get_filename_component(folder ${path} DIRECTORY)
    get_filename_component(folder_name ${folder} NAME)
    string(MAKE_C_IDENTIFIER "${folder_name}" key)
    get_source_file_property(cold ${source} THICKET_COLD)
    if(cold)
      set(key ${key}_cold)
    endif()
    if(NOT DEFINED count_${key})
      set(count_${key} 0)
    endif()
    math(EXPR batch "${count_${key}} / ${ARG_BATCH}")
    math(EXPR count_${key} "${count_${key}} + 1")
    set(group ${key}_${batch})
    if(NOT DEFINED members_${group})
      list(APPEND groups ${group})
      set(cold_${group} ${cold})
    endif()
    list(APPEND members_${group} ${path})
    # Still listed in the target (IDEs, dependency scanning), compiled through its unit only.
    set_source_files_properties(${source} PROPERTIES HEADER_FILE_ONLY ON)
  endforeach()
  file(MAKE_DIRECTORY ${THICKET_UNITY_DIR})
  foreach(group ${groups})
    set(text "/* Unity unit of ${target}, written by cmake/unity.cmake */\n")
    foreach(member ${members_${group}})
      string(APPEND text "#include \"${member}\"\n")
    endforeach()
    string(MD5 hash "${text}")
    string(SUBSTRING ${hash} 0 12 hash)
    set(unit ${THICKET_UNITY_DIR}/${target}_${group}_${hash}.cpp)
    if(NOT EXISTS ${unit})
      # Written aside and renamed: a tree configured at the same time sees the whole file or none.
      string(RANDOM LENGTH 8 tag)
      file(WRITE ${unit}.${tag} "${text}")
      file(RENAME ${unit}.${tag} ${unit})
    endif()
    target_sources(${target} PRIVATE ${unit})
    if(cold_${group})
      set_source_files_properties(${unit} PROPERTIES COMPILE_OPTIONS "${THICKET_COLD_OPT}")
    endif()
  endforeach()
endfunction()
