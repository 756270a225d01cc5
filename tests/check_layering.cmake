# Fails when a folder includes a header from a folder above it in the layering of
# docs/architecture.md (geometry; models, collision and render; scenes; harness; viewer), or when a library
# folder includes TetGen (AGPL: only meshgen/ and the CLI may).
set(forbidden
  "geometry:models/|collision/|scenes/|harness/|meshgen/|tetgen.h|viewer/"
  "models:collision/|scenes/|harness/|meshgen/|tetgen.h|viewer/"
  "collision:models/|scenes/|harness/|meshgen/|tetgen.h|viewer/"
  "scenes:harness/|meshgen/|tetgen.h|viewer/"
  # The renderer draws meshes: geometry only, so the viewer and the commands share it.
  "render:models/|collision/|scenes/|harness/|meshgen/|tetgen.h|viewer/"
  # The fuzz targets drive the readers as the commands do, without the harness.
  "fuzz:harness/|meshgen/|tetgen.h|viewer/"
  # Inside the harness: the run core depends on no other part; the parts built on it
  # (stability, sweep, compare, calibrate, soak) on none of each other, but compare on calibrate (its
  # table B is every model calibrated); verify on the run core and
  # stability (it reuses the torture runs) only; reports on no command; and nothing but the
  # command line itself includes the command line.
  "harness/run:harness/soak/|harness/stability/|harness/sweep/|harness/compare/|harness/calibrate/|harness/verify/|harness/report/|harness/cli/|meshgen/|tetgen.h|viewer/"
  "harness/stability:harness/soak/|harness/sweep/|harness/compare/|harness/calibrate/|harness/verify/|harness/report/|harness/cli/|meshgen/|tetgen.h|viewer/"
  "harness/sweep:harness/soak/|harness/stability/|harness/compare/|harness/calibrate/|harness/verify/|harness/report/|harness/cli/|meshgen/|tetgen.h|viewer/"
  "harness/compare:harness/soak/|harness/stability/|harness/sweep/|harness/verify/|harness/report/|harness/cli/|meshgen/|tetgen.h|viewer/"
  "harness/calibrate:harness/soak/|harness/stability/|harness/sweep/|harness/compare/|harness/verify/|harness/report/|harness/cli/|meshgen/|tetgen.h|viewer/"
  "harness/verify:harness/soak/|harness/sweep/|harness/compare/|harness/calibrate/|harness/report/|harness/cli/|meshgen/|tetgen.h|viewer/"
  "harness/soak:harness/stability/|harness/sweep/|harness/compare/|harness/calibrate/|harness/verify/|harness/report/|harness/cli/|meshgen/|tetgen.h|viewer/"
  "harness/report:harness/cli/|meshgen/|tetgen.h|viewer/"
  # The viewer is built on the run core and the renderer; only the command line includes it.
  "viewer:harness/cli/|harness/soak/|harness/stability/|harness/sweep/|harness/compare/|harness/calibrate/|harness/verify/|meshgen/|tetgen.h")
# The files at the harness root are the vocabulary every part shares: they include no part.
file(GLOB root_files "${SOURCE_DIR}/harness/*.h" "${SOURCE_DIR}/harness/*.cpp")
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
foreach(file IN LISTS root_files)
  file(STRINGS "${file}" includes REGEX "^#include [\"<]harness/[a-z_]+/")
  if(includes)
    list(APPEND failures "${file}: ${includes}")
  endif()
endforeach()
if(failures)
  string(REPLACE ";" "\n" message "${failures}")
  message(FATAL_ERROR "layering violated:\n${message}")
endif()
message(STATUS "layering ok")
