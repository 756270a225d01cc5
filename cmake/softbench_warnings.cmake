# INTERFACE target carrying the project's warning flags; linked PRIVATE by every target.
add_library(softbench_warnings INTERFACE)
add_library(softbench::warnings ALIAS softbench_warnings)
target_compile_options(softbench_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wconversion-null -Wcast-align
  -Wunused -Woverloaded-virtual -Wnull-dereference -Wimplicit-fallthrough)
if(SOFTBENCH_WARNINGS_AS_ERRORS)
  target_compile_options(softbench_warnings INTERFACE -Werror)
endif()
