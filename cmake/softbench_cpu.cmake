# The instruction set a release build compiles for. softbench is built where it runs (scripts/setup
# builds from source), so by default a release build uses what this machine's CPU has beyond
# x86-64's SSE2 baseline: AVX2 and FMA (the x86-64-v3 level, every x86-64 CPU since about 2015).
# The models' batched kernels (rotations, element terms, block products) run on four doubles a
# vector instead of two: measured on the liver's corotational FEM step, 13-15% less CPU time.
#
# SOFTBENCH_CPU_LEVEL: "auto" (x86-64-v3 when the compiler and this CPU both have it, else the
# baseline), "baseline" (none: the binaries run on any x86-64), or an -march value
# (e.g. "native"). Every unit of the build gets the same level: Eigen's fixed-size types align
# to the vector width, so units built for different levels must not share them. Sanitizer and
# fuzz builds (SOFTBENCH_SANITIZE, SOFTBENCH_FUZZ) keep the baseline, as does any build type but
# Release. Results change at round-off only: the compiler fuses no a * b + c by itself (ISO C++
# mode: -ffp-contract=off), but Eigen's vectorised kernels use FMA instructions where the target
# has them (collision/CMakeLists.txt builds the units that must round as written without FMA).
set(SOFTBENCH_CPU_LEVEL "auto" CACHE STRING
    "Instruction set of a release build: auto, baseline, or an -march value")

function(softbench_cpu_level_flag out)
  set(${out} "" PARENT_SCOPE)
  if(NOT CMAKE_BUILD_TYPE STREQUAL "Release" OR SOFTBENCH_SANITIZE OR SOFTBENCH_FUZZ
     OR SOFTBENCH_CPU_LEVEL STREQUAL "baseline")
    return()
  endif()
  if(NOT SOFTBENCH_CPU_LEVEL STREQUAL "auto")
    set(${out} "-march=${SOFTBENCH_CPU_LEVEL}" PARENT_SCOPE)
    return()
  endif()
  if(NOT CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$" OR CMAKE_CROSSCOMPILING)
    return()
  endif()
  include(CheckCXXSourceRuns)
  set(CMAKE_REQUIRED_FLAGS "-march=x86-64-v3")
  check_cxx_source_runs([=[
    int main() {
      __builtin_cpu_init();
      return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")
             && __builtin_cpu_supports("bmi2") ? 0 : 1;
    }]=] SOFTBENCH_CPU_HAS_X86_64_V3)
  if(SOFTBENCH_CPU_HAS_X86_64_V3)
    set(${out} "-march=x86-64-v3" PARENT_SCOPE)
  endif()
endfunction()

softbench_cpu_level_flag(SOFTBENCH_CPU_FLAG)
if(SOFTBENCH_CPU_FLAG)
  message(STATUS "softbench: compiling for ${SOFTBENCH_CPU_FLAG}")
  add_compile_options(${SOFTBENCH_CPU_FLAG})
else()
  message(STATUS "softbench: compiling for the x86-64 baseline")
endif()
