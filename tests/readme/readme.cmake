# The README's examples as users copy them (the fenced blocks marked `<!-- tested: NAME -->`):
# the C++ one compiled against the built library and run, the Python one run with the build tree's
# module; readme_examples.py checks what they print. Included at the end of the top directory
# (tests/CMakeLists.txt defers it): Python and the module are set up after tests/ is read.
# The C++ example is compiled when its test runs, not by the default build, so a README that no
# longer compiles fails a test instead of everyone's build.
if(NOT Python3_EXECUTABLE)
  message(STATUS "README examples: no Python 3 interpreter, not tested")
  return()
endif()
set(_readme ${PROJECT_SOURCE_DIR}/README.md)
set(_script ${CMAKE_CURRENT_LIST_DIR}/readme_examples.py)
set(_cpp ${PROJECT_BINARY_DIR}/tests/readme/readme_example.cpp)
add_custom_command(OUTPUT ${_cpp}
  COMMAND ${Python3_EXECUTABLE} ${_script} extract ${_readme} readme_example.cpp ${_cpp}
  DEPENDS ${_readme} ${_script}
  COMMENT "Extracting the README's C++ example")
add_executable(readme_example EXCLUDE_FROM_ALL ${_cpp})
target_link_libraries(readme_example PRIVATE thicket::thicket)
target_compile_options(readme_example PRIVATE ${THICKET_WARNINGS})
set_target_properties(readme_example PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/tests/readme)

add_test(NAME readme.cpp_build COMMAND ${THICKET_TEST_WRAPPER} ${CMAKE_COMMAND} --build ${PROJECT_BINARY_DIR} --target readme_example)
set_tests_properties(readme.cpp_build PROPERTIES FIXTURES_SETUP readme_cpp TIMEOUT 600)
add_test(NAME readme.cpp COMMAND ${THICKET_TEST_WRAPPER} ${Python3_EXECUTABLE} ${_script} run-cpp $<TARGET_FILE:readme_example>)
set_tests_properties(readme.cpp PROPERTIES FIXTURES_REQUIRED readme_cpp)
if(TARGET thicket_python)
  add_test(NAME readme.python
    COMMAND ${THICKET_TEST_WRAPPER} ${Python3_EXECUTABLE} ${_script} run-python ${_readme} ${PROJECT_BINARY_DIR}/python)
  set_tests_properties(readme.python PROPERTIES TIMEOUT 1200)  # a hang, not a loaded machine (python/CMakeLists.txt)
endif()
