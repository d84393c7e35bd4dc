# The layering check (run by ctest as `layering`; see libiaa/CMakeLists.txt and docs/design.md).
#   cmake -DROOT=<source tree> -DLAYERS=<build>/iaa_layers.cmake -P tools/check_layers.cmake
# Fails, listing every offending line, when
#   - a file of libiaa/<module>/ includes a header of a module <module> does not depend on;
#   - a file of viz/ includes a header of tools/ (viz sits below the tools, beside them);
#   - a VTK header is included outside viz/, or a CGAL or OpenMesh header outside libiaa/mesh/;
#   - <mpi.h> is included outside libiaa/dist/;
#   - the iaa command (tools/iaa/) includes a header of viz/ other than viz/plugin_api.h: it does
#     not link VTK, and reaches viz/ through the plugin alone (tools/iaa/viz_plugin.h).
# Tests are not checked: a test may reach into any module.
cmake_minimum_required(VERSION 3.22)
if(NOT ROOT OR NOT LAYERS)
  message(FATAL_ERROR "usage: cmake -DROOT=<source tree> -DLAYERS=<iaa_layers.cmake> -P check_layers.cmake")
endif()
include(${LAYERS})

# The first component of a quoted include names its part of the tree: a library module, `app`,
# `viz`, or the tools: `iaa/...` (tools/ is an include root of the iaa command) or `tools/...`
# (the source tree is an include root of viz/).
set(tool_roots iaa tools)

file(GLOB_RECURSE files RELATIVE ${ROOT} ${ROOT}/libiaa/*.h ${ROOT}/libiaa/*.cpp ${ROOT}/viz/*.h
  ${ROOT}/viz/*.cpp ${ROOT}/tools/*.h ${ROOT}/tools/*.cpp)
set(errors "")
set(checked 0)
foreach(file ${files})
  # What this file may include.
  set(allowed "")
  set(area "")
  if(file MATCHES "^libiaa/([a-z_]+)/")
    set(area ${CMAKE_MATCH_1})
    if(NOT DEFINED IAA_LAYER_${area})
      string(APPEND errors "${file}: libiaa/${area}/ is not a module of libiaa/CMakeLists.txt\n")
      continue()
    endif()
    set(allowed ${IAA_LAYER_${area}})
  elseif(file MATCHES "^viz/")
    set(area viz)
    set(allowed ${IAA_LAYER_MODULES} viz)
  else()
    set(area tools)
  endif()
  math(EXPR checked "${checked} + 1")

  file(STRINGS ${ROOT}/${file} lines REGEX "^[ \t]*#[ \t]*include")
  foreach(line ${lines})
    if(line MATCHES "include[ \t]*\"([a-z_]+)/")
      set(part ${CMAKE_MATCH_1})
      if(file MATCHES "^tools/iaa/" AND part STREQUAL "viz" AND NOT line MATCHES "\"viz/plugin_api[.]h\"")
        string(APPEND errors "${file}: the iaa command reaches viz/ through its plugin only (viz/plugin_api.h): ${line}\n")
      endif()
      if(NOT area STREQUAL "tools")
        if(part IN_LIST tool_roots)
          string(APPEND errors "${file}: ${area} must not include the tools' headers: ${line}\n")
        elseif((part IN_LIST IAA_LAYER_MODULES OR part STREQUAL "viz") AND NOT part IN_LIST allowed)
          string(APPEND errors "${file}: ${area} does not depend on ${part}: ${line}\n")
        endif()
      endif()
    elseif(line MATCHES "include[ \t]*<vtk" AND NOT area STREQUAL "viz")
      string(APPEND errors "${file}: VTK is used only in viz/: ${line}\n")
    elseif(line MATCHES "include[ \t]*<(CGAL|OpenMesh)/" AND NOT area STREQUAL "mesh")
      string(APPEND errors "${file}: CGAL and OpenMesh are used only in libiaa/mesh/: ${line}\n")
    elseif(line MATCHES "include[ \t]*<mpi[.]h>" AND NOT area STREQUAL "dist")
      string(APPEND errors "${file}: MPI is used only in libiaa/dist/: ${line}\n")
    endif()
  endforeach()
endforeach()

if(checked EQUAL 0)
  message(FATAL_ERROR "layering: no source file found under ${ROOT}")
endif()
if(errors)
  message(FATAL_ERROR "layering: includes against the module graph (docs/design.md):\n${errors}")
endif()
message(STATUS "layering: ${checked} files follow the module graph")
