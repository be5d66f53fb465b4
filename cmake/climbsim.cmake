# climbsim_test(NAME SOURCES a.cc b.cc LIBS x y [LABELS l] [TIMEOUT s])
# One GoogleTest executable, registered test by test so ctest -j spreads them over cores.
# Tests find the source tree (mjcf/, examples/) through CLIMBSIM_SOURCE_DIR.
function(climbsim_test name)
  cmake_parse_arguments(T "" "TIMEOUT" "SOURCES;LIBS;LABELS" ${ARGN})
  add_executable(${name} ${T_SOURCES})
  # Unity only in the sanitized tree (run_asan.sh's build time); elsewhere an edit rebuilds a file.
  if(NOT CLIMBSIM_SANITIZE)
    set_target_properties(${name} PROPERTIES UNITY_BUILD OFF)
  endif()
  target_link_libraries(${name} PRIVATE ${T_LIBS} GTest::gtest GTest::gtest_main)
  target_compile_definitions(${name} PRIVATE
    CLIMBSIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    CLIMBSIM_BINARY_DIR="${PROJECT_BINARY_DIR}")
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 300)
  endif()
  gtest_discover_tests(${name}
    WORKING_DIRECTORY ${PROJECT_BINARY_DIR}
    PROPERTIES TIMEOUT ${T_TIMEOUT} LABELS "${T_LABELS}"
    DISCOVERY_TIMEOUT 60)
endfunction()

include(GoogleTest)

# climbsim_bench(NAME SOURCES a.cc LIBS x y): a Google Benchmark executable in build/bench/.
function(climbsim_bench name)
  cmake_parse_arguments(B "" "" "SOURCES;LIBS" ${ARGN})
  add_executable(${name} ${B_SOURCES})
  target_link_libraries(${name} PRIVATE ${B_LIBS} benchmark::benchmark)
  target_compile_definitions(${name} PRIVATE CLIMBSIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
endfunction()
