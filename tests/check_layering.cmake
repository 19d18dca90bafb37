# Layering rules (DESIGN.md): libsph never includes geometry/, cardio/ or apps/; geometry never
# includes cardio/ or apps/; no public header includes a heavy third-party library.
# Run as: cmake -DSOURCE_DIR=<project> -P check_layering.cmake
set(violations "")

# Appends to `violations` every line of `files` that matches the include regex `pattern`.
function(find_includes pattern)
  foreach(f ${ARGN})
    file(STRINGS "${f}" lines REGEX "${pattern}")
    if(lines)
      list(APPEND violations "${f}: ${lines}")
    endif()
  endforeach()
  set(violations "${violations}" PARENT_SCOPE)
endfunction()

foreach(rule "libsph;geometry/|cardio/|apps/" "geometry;cardio/|apps/" "cardio;apps/")
  list(GET rule 0 folder)
  list(GET rule 1 forbidden)
  file(GLOB_RECURSE files "${SOURCE_DIR}/${folder}/*.hpp" "${SOURCE_DIR}/${folder}/*.cpp")
  find_includes("^#include \"(${forbidden})" ${files})
endforeach()
file(GLOB_RECURSE headers "${SOURCE_DIR}/libsph/*.hpp" "${SOURCE_DIR}/geometry/*.hpp" "${SOURCE_DIR}/cardio/*.hpp")
find_includes("^#include [<\"](CGAL/|assimp/|vtk|cvode/|sundials/|nvector/|toml)" ${headers})

if(violations)
  string(REPLACE ";" "\n" text "${violations}")
  message(FATAL_ERROR "layering violations:\n${text}")
endif()
message(STATUS "layering: no violations")
