# Who may include whom in host/ (docs/architecture.md, "Floors"): scans every #include "x/..."
# of every source and header under HOST_DIR and fails naming file, line and include on each that
# breaks the table below. Public headers (<clvis/...>) and headers without a folder (the file's
# own folder, or host/'s loose ones) are free to all. Run by CTest (tests/CMakeLists.txt):
#   cmake -DHOST_DIR=<root>/host -P include_rule.cmake
# tests/include_rule/host/ is a fixture that breaks the rule, proving that the check sees it.

cmake_minimum_required(VERSION 3.16)

if(NOT HOST_DIR OR NOT IS_DIRECTORY "${HOST_DIR}")
  message(FATAL_ERROR "include_rule: HOST_DIR '${HOST_DIR}' is not a folder")
endif()

# Each folder of host/ and the folders it may include from besides shared/ (kernels/shared: plain
# C headers both compilers read) and clvis/ (the public headers), open to all. "loose" is host/.
set(may_loose   "")
set(may_runtime runtime)
set(may_scene   scene)
set(may_frame   frame runtime scene)             # the frame layer: never a path, never render/
set(may_raster  raster frame runtime scene)      # a path: the frame layer, never render/
set(may_ray     ray frame runtime scene)         # a path: the frame layer, never render/
set(may_render  render raster ray frame runtime scene)
set(may_query   query render ray frame runtime scene)
set(may_referee referee scene)
set(may_image   "")                              # public headers only
set(may_dist    "")
set(may_cli     "")

get_filename_component(host_dir "${HOST_DIR}" ABSOLUTE)
get_filename_component(parent "${host_dir}" DIRECTORY)
file(GLOB_RECURSE sources LIST_DIRECTORIES false "${host_dir}/*.cpp" "${host_dir}/*.hpp" "${host_dir}/*.h")
list(SORT sources)

set(broken 0)
foreach(source IN LISTS sources)
  file(RELATIVE_PATH shown "${parent}" "${source}")   # host/ray/x.cpp
  file(RELATIVE_PATH inside "${host_dir}" "${source}") # ray/x.cpp
  if(inside MATCHES "^([^/]+)/")
    set(folder "${CMAKE_MATCH_1}")
  else()
    set(folder loose)
  endif()
  set(floor "${folder}/")
  if(folder STREQUAL "loose")
    set(floor "host/ (loose)")
  endif()
  if(NOT DEFINED may_${folder})
    message("${shown}:1: host/${folder}/ is not in the table of tests/include_rule.cmake: add it with the folders it may include (docs/architecture.md)")
    math(EXPR broken "${broken} + 1")
    continue()
  endif()
  set(allowed ${may_${folder}})
  file(READ "${source}" text)
  # One list element per line: characters that a CMake list treats specially are masked first.
  string(REPLACE "\\" "/" text "${text}")
  string(REPLACE ";" "," text "${text}")
  string(REPLACE "[" "(" text "${text}")
  string(REPLACE "]" ")" text "${text}")
  string(REPLACE "\n" ";" lines "${text}")
  set(number 0)
  foreach(line IN LISTS lines)
    math(EXPR number "${number} + 1")
    if(NOT line MATCHES "^[ \t]*#[ \t]*include[ \t]*\"([^\"]*)\"")
      continue()
    endif()
    set(target "${CMAKE_MATCH_1}")
    if(target MATCHES "(^|/)\\.\\.(/|$)")
      message("${shown}:${number}: \"${target}\" climbs out of its folder: name the folder from host/ (\"x/...\")")
      math(EXPR broken "${broken} + 1")
    elseif(target MATCHES "^([^/]+)/")
      set(to "${CMAKE_MATCH_1}")
      if(NOT to STREQUAL "clvis" AND NOT to STREQUAL "shared" AND NOT to IN_LIST allowed)
        string(REPLACE ";" " " list "${allowed} shared clvis")
        string(STRIP "${list}" list)
        message("${shown}:${number}: ${floor} may not include ${target} (${floor} may include: ${list})")
        math(EXPR broken "${broken} + 1")
      endif()
    endif()
  endforeach()
endforeach()

list(LENGTH sources count)
if(broken GREATER 0)
  message(FATAL_ERROR "include_rule: ${broken} include(s) in ${count} files under ${host_dir} break the rule of docs/architecture.md")
endif()
message(STATUS "include_rule: ${count} files under ${host_dir} keep the rule")
