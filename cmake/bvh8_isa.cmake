# bvh8's per-ISA kernels (docs/bvh8.md): each src/bvh8/kernels_<isa>.cpp is compiled for its own
# instruction set; the rest of the library stays at the x86-64 baseline, and cpuid picks the
# kernels at run time. -ffp-contract=off: the kernels' results must be bitwise those of the
# scalar tests, so no multiply-add may be fused behind our back.
set(_bvh8_kernels kernels_scalar kernels_sse kernels_avx2 kernels_avx512)
list(TRANSFORM _bvh8_kernels PREPEND ${PROJECT_SOURCE_DIR}/src/bvh8/)
list(TRANSFORM _bvh8_kernels APPEND .cpp)
# Each kernel file opens its own ISA namespace and is compiled with its own flags: never in a unity unit.
set_source_files_properties(${_bvh8_kernels} PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
if(CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64|amd64" AND CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  set(_bvh8 ${PROJECT_SOURCE_DIR}/src/bvh8)
  # The scalar level is the reference the others are tested against and is never what detection
  # picks here (SSE2 is the x86-64 baseline): -O1 compiles it in 9 s instead of 24 s, and its
  # answers stay bitwise the same (no contraction at any level).
  set_source_files_properties(${_bvh8}/kernels_scalar.cpp PROPERTIES COMPILE_OPTIONS "-O1;-ffp-contract=off")
  set_source_files_properties(${_bvh8}/kernels_sse.cpp PROPERTIES COMPILE_OPTIONS "-ffp-contract=off")
  set_source_files_properties(${_bvh8}/kernels_avx2.cpp
    PROPERTIES COMPILE_OPTIONS "-mavx2;-mfma;-mbmi;-mbmi2;-mlzcnt;-mpopcnt;-ffp-contract=off")
  set_source_files_properties(${_bvh8}/kernels_avx512.cpp
    PROPERTIES COMPILE_OPTIONS "-mavx2;-mfma;-mbmi;-mbmi2;-mlzcnt;-mpopcnt;-mavx512f;-mavx512vl;-ffp-contract=off")

  if(THICKET_BUILD_TESTS)
    # The dispatch-trap check: no function outside thicket::bvh8_avx2/avx512 may hold an AVX
    # instruction. The fixture (an AVX unit that emits a shared inline function and std::sort's
    # helpers) proves the check fails when it should.
    # (Not with THICKET_NATIVE: -march=native puts AVX in every function on purpose.)
    find_program(THICKET_OBJDUMP objdump)
    if(THICKET_OBJDUMP AND NOT THICKET_NATIVE)
      add_library(thicket_bvh8_isa_trap STATIC ${PROJECT_SOURCE_DIR}/tests/bvh8/isa_trap_fixture.cpp)
      target_include_directories(thicket_bvh8_isa_trap PRIVATE ${PROJECT_SOURCE_DIR}/include)
      target_compile_options(thicket_bvh8_isa_trap PRIVATE -mavx2 -mfma ${THICKET_WARNINGS})
      if(TARGET thicket_test_programs)
        add_dependencies(thicket_test_programs thicket_bvh8_isa_trap)
      endif()
      set(_check ${THICKET_TEST_WRAPPER} ${PROJECT_SOURCE_DIR}/tests/bvh8/check_isa_confinement.sh)
      add_test(NAME bvh8.isa_confinement COMMAND ${_check} ${THICKET_OBJDUMP} clean $<TARGET_FILE:thicket>)
      add_test(NAME bvh8.isa_confinement_detects_trap
        COMMAND ${_check} ${THICKET_OBJDUMP} violation $<TARGET_FILE:thicket_bvh8_isa_trap> "(^| )thicket::hit_within_bounds[<(]")
      if(TARGET thicket_cli)
        add_test(NAME bvh8.isa_confinement_cli COMMAND ${_check} ${THICKET_OBJDUMP} clean-cli $<TARGET_FILE:thicket_cli>)
      endif()
    endif()
  endif()
endif()
