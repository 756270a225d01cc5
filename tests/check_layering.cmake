# Fails when a folder includes a header from a folder above it in the layering of
# docs/architecture.md (geometry; models and collision; scenes; harness), or when a library
# folder includes TetGen (AGPL: only meshgen/ and the CLI may).
set(forbidden
  "geometry:models/|collision/|scenes/|harness/|meshgen/|tetgen.h"
  "models:collision/|scenes/|harness/|meshgen/|tetgen.h"
  "collision:models/|scenes/|harness/|meshgen/|tetgen.h"
  "scenes:harness/|meshgen/|tetgen.h")
set(failures "")
foreach(rule IN LISTS forbidden)
  string(REPLACE ":" ";" parts "${rule}")
  list(GET parts 0 folder)
  list(GET parts 1 pattern)
  file(GLOB_RECURSE files "${SOURCE_DIR}/${folder}/*.h" "${SOURCE_DIR}/${folder}/*.cpp")
  foreach(file IN LISTS files)
    file(STRINGS "${file}" includes REGEX "^#include [\"<](${pattern})")
    if(includes)
      list(APPEND failures "${file}: ${includes}")
    endif()
  endforeach()
endforeach()
if(failures)
  string(REPLACE ";" "\n" message "${failures}")
  message(FATAL_ERROR "layering violated:\n${message}")
endif()
message(STATUS "layering ok")
