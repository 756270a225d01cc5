# Writes OUTPUT (a header defining kBuildRevision) from `git describe --always --dirty` in
# SOURCE_DIR, or "unknown" outside a git checkout. Rewrites it only when the revision changed, so
# a build at the same revision recompiles nothing.
find_package(Git QUIET)
set(revision "unknown")
if(GIT_FOUND)
  execute_process(COMMAND "${GIT_EXECUTABLE}" describe --always --dirty
                  WORKING_DIRECTORY "${SOURCE_DIR}"
                  OUTPUT_VARIABLE described OUTPUT_STRIP_TRAILING_WHITESPACE
                  RESULT_VARIABLE failed ERROR_QUIET)
  if(NOT failed AND described)
    set(revision "${described}")
  endif()
endif()
set(content "// Generated at build time by cmake/write_build_revision.cmake.\n#pragma once\ninline constexpr const char* kBuildRevision = \"${revision}\";\n")
if(EXISTS "${OUTPUT}")
  file(READ "${OUTPUT}" previous)
endif()
if(NOT previous STREQUAL content)
  file(WRITE "${OUTPUT}" "${content}")
endif()
