# thicket_unity_by_folder(target [BATCH n]): compile target's sources as unity units, each made of
# files of one folder only (at most n of them, default 8), so that a unit parses the library's
# headers and instantiates their templates once for several files. Folders keep their files
# together because a folder is one concept (one structure, the scene loaders): file-local names of
# two structures never meet in one unit, and a folder's own files are written not to clash.
# Sources marked SKIP_UNITY_BUILD_INCLUSION (per-ISA kernels, files whose headers clash) stay alone.
# Off with -DTHICKET_UNITY=OFF, which checks that every file includes what it uses.
#
# Sources marked THICKET_COLD (code that runs once per load, never per ray or per primitive of a
# build: the JSON and glTF loaders) form units of their own, compiled at -O1 in optimized builds.
# A source with its own COMPILE_OPTIONS would leave its unit, so the option goes on the unit.
set(THICKET_COLD_OPT $<$<CONFIG:Release,RelWithDebInfo,MinSizeRel>:-O1>)
function(thicket_unity_by_folder target)
  cmake_parse_arguments(ARG "" "BATCH" "" ${ARGN})
  if(NOT ARG_BATCH)
    set(ARG_BATCH 8)
  endif()
  get_target_property(sources ${target} SOURCES)
  get_target_property(source_dir ${target} SOURCE_DIR)
  get_target_property(binary_dir ${target} BINARY_DIR)
  if(NOT THICKET_UNITY)
    foreach(source ${sources})
      get_source_file_property(cold ${source} THICKET_COLD)
      if(cold)
        set_source_files_properties(${source} PROPERTIES COMPILE_OPTIONS "${THICKET_COLD_OPT}")
      endif()
    endforeach()
    return()
  endif()
  set(cold_units)
  foreach(source ${sources})
    if(NOT source MATCHES "\\.cpp$")
      continue()
    endif()
    get_source_file_property(skip ${source} SKIP_UNITY_BUILD_INCLUSION)
    if(skip)
      continue()
    endif()
    if(NOT IS_ABSOLUTE ${source})
      set(source ${source_dir}/${source})
    endif()
    get_filename_component(folder ${source} DIRECTORY)
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
    set_source_files_properties(${source} PROPERTIES UNITY_GROUP "${key}_${batch}")
    if(cold)
      list(APPEND cold_units ${binary_dir}/CMakeFiles/${target}.dir/Unity/unity_${key}_${batch}_cxx.cxx)
    endif()
  endforeach()
  set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_MODE GROUP)
  # The path is where CMake writes a group's unit (unity_<group>_cxx.cxx); were it to move, the
  # cold units would compile at the target's level: slower to build, the same program.
  if(cold_units)
    list(REMOVE_DUPLICATES cold_units)
    set_source_files_properties(${cold_units} PROPERTIES COMPILE_OPTIONS "${THICKET_COLD_OPT}")
  endif()
endfunction()
