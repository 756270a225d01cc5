# Precompiled headers: the headers nearly every unit of a target parses (Eigen, nlohmann/json,
# GoogleTest, CLI11: 100,000-200,000 lines a unit) are compiled once per target instead of once
# per unit. Parsing them was a third to a half of a unit's compile time, and CI builds most units
# twice (release, and the instrumented tree of the sanitizer and fuzz jobs). Configure with
# -DCMAKE_DISABLE_PRECOMPILE_HEADERS=ON to build without them (e.g. to check that every file
# includes what it uses).
set(SOFTBENCH_PCH_CORE <algorithm> <cmath> <memory> <string> <vector> <Eigen/Core>
    <Eigen/Geometry>)
set(SOFTBENCH_PCH_JSON ${SOFTBENCH_PCH_CORE} <nlohmann/json.hpp>)
set(SOFTBENCH_PCH_TEST ${SOFTBENCH_PCH_JSON} <gmock/gmock.h> <gtest/gtest.h>)

# softbench_add_library(NAME SOURCES... [PUBLIC_LINK ...] [PRIVATE_LINK ...] [PRECOMPILE ...])
# One library per folder: softbench_<name>, aliased softbench::<name>, includes rooted at the repo;
# PRECOMPILE: its precompiled headers (SOFTBENCH_PCH_CORE by default).
function(softbench_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_LINK;PRIVATE_LINK;PRECOMPILE" ${ARGN})
  add_library(softbench_${name} ${ARG_SOURCES})
  add_library(softbench::${name} ALIAS softbench_${name})
  target_include_directories(softbench_${name} PUBLIC ${PROJECT_SOURCE_DIR})
  target_link_libraries(softbench_${name} PUBLIC ${ARG_PUBLIC_LINK}
                        PRIVATE softbench::warnings ${ARG_PRIVATE_LINK})
  if(NOT ARG_PRECOMPILE)
    set(ARG_PRECOMPILE ${SOFTBENCH_PCH_CORE})
  endif()
  target_precompile_headers(softbench_${name} PRIVATE ${ARG_PRECOMPILE})
endfunction()

# softbench_test_compile_options(TARGET): the options every test unit compiles with, and so the
# shared precompiled header's host too (a header is only reused under the options it was built
# with).
function(softbench_test_compile_options target)
  # The tests' own code (meshes made in code, expected values, loops over cases) runs briefly;
  # the physics they check runs in the libraries, built as the preset says. At -O1 a test unit
  # compiles in about two thirds of the time -O3 takes (the tests are a third of the release
  # build), with the same floating-point results (no fast-math, no contraction).
  target_compile_options(${target} PRIVATE $<$<CONFIG:Release>:-O1>)
  # GCC 12's middle-end string warnings misfire on libstdc++'s inlined std::string code once
  # optimised (known false positives: a bound of 2^64 - 1, an offset past the 32-byte
  # small-string buffer), and through a precompiled header they are no longer taken for a
  # system header's. Off in the tests, which build strings of file contents everywhere; the
  # libraries keep them.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${target} PRIVATE -Wno-array-bounds -Wno-stringop-overflow
                                             -Wno-restrict)
  endif()
endfunction()

# softbench_add_test(NAME SOURCES... LINK ...): one GoogleTest executable, tests discovered by ctest
# and labelled with the executable's name (ctest -L models_test runs one executable's tests; the
# sanitizer job picks its executables so).
function(softbench_add_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LINK" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LINK} softbench_test_support GTest::gmock GTest::gtest_main
                        OpenMP::OpenMP_CXX softbench::warnings)
  softbench_test_compile_options(${name})
  # Worth its own compile (about as long as one unit's) only where several units share it.
  list(LENGTH ARG_SOURCES units)
  if(units GREATER_EQUAL 4)
    # One precompiled header for every test executable (softbench_test_pch in
    # tests/CMakeLists.txt): they compile with the same options, so a header per executable was
    # the same header built six times.
    target_precompile_headers(${name} REUSE_FROM softbench_test_pch)
    # Batches of units compiled as one: each test unit spends much of its compile instantiating
    # the same Eigen and GoogleTest templates, which a batch instantiates once. (So a test file's
    # file-local names must not repeat another's of the same executable.)
    set_target_properties(${name} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
  endif()
  gtest_discover_tests(${name} WORKING_DIRECTORY ${PROJECT_SOURCE_DIR} DISCOVERY_TIMEOUT 60
                       PROPERTIES LABELS ${name})
endfunction()

# softbench_add_bench(NAME SOURCES... LINK ... [SMOKE_FILTER REGEX]): one Google Benchmark
# executable, its JSON context carrying softbench's provenance (softbench_bench_context,
# bench/CMakeLists.txt), and its smoke test BenchSmoke.NAME (label bench_smoke): every benchmark
# once for a moment (bench/bench_smoke.h), so none can rot. SMOKE_FILTER (a --benchmark_filter,
# "-REGEX" to leave out) drops the sizes that only add time: the same code on a larger mesh.
function(softbench_add_bench name)
  cmake_parse_arguments(ARG "" "SMOKE_FILTER" "SOURCES;LINK" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LINK} softbench_bench_context softbench::harness
                        benchmark::benchmark_main softbench::warnings)
  set(smoke_arguments --benchmark_min_time=0.001 --benchmark_repetitions=1)
  if(ARG_SMOKE_FILTER)
    list(APPEND smoke_arguments "--benchmark_filter=${ARG_SMOKE_FILTER}")
  endif()
  add_test(NAME BenchSmoke.${name} COMMAND ${name} ${smoke_arguments}
           WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  # A benchmark that cannot run (SkipWithError: a blow-up, a missing mesh) still leaves the
  # executable with status 0: its console line fails the test.
  set_tests_properties(BenchSmoke.${name} PROPERTIES LABELS bench_smoke
                       ENVIRONMENT "SOFTBENCH_BENCH_SMOKE=1;OMP_NUM_THREADS=1"
                       FAIL_REGULAR_EXPRESSION "ERROR OCCURRED")
endfunction()

# softbench_add_provenance(TARGET): TARGET gets harness/build_revision.h (the git revision,
# refreshed at every build) and the version, build type defines that harness/provenance.cpp reads.
function(softbench_add_provenance target)
  set(generated "${PROJECT_BINARY_DIR}/generated")
  add_custom_target(softbench_build_revision
    COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${PROJECT_SOURCE_DIR}
            -DOUTPUT=${generated}/harness/build_revision.h
            -P ${PROJECT_SOURCE_DIR}/cmake/write_build_revision.cmake
    BYPRODUCTS ${generated}/harness/build_revision.h
    COMMENT "softbench: git revision")
  add_dependencies(${target} softbench_build_revision)
  target_include_directories(${target} PRIVATE ${generated})
  set(build_type "${CMAKE_BUILD_TYPE}")
  if(NOT build_type)
    set(build_type "unspecified")
  endif()
  target_compile_definitions(${target} PRIVATE SOFTBENCH_VERSION="${PROJECT_VERSION}"
                                               SOFTBENCH_BUILD_TYPE="${build_type}")
  target_link_libraries(${target} PRIVATE OpenMP::OpenMP_CXX)
endfunction()
