# The rusticl CTest: the tests tagged [rusticl] (the device suite and a subset of the agreement
# suite, both paths, both raster depth tests where offered) and the reference comparison
# ([.reference], reference_device_test.cpp) on Mesa's Rusticl (llvmpipe: no 64-bit atomics, no
# fp64). Skipped, saying why, only when no device of that platform exists.
# Run by CTest as `cmake -P` with -DTESTS=clvis_tests -DPLATFORM=rusticl; the environment
# (RUSTICL_ENABLE, CLVIS_DEVICE, CLVIS_REFERENCE_DEVICE) comes from the test's properties.
set(ENV{CLVIS_COUNT_PLATFORM} "${PLATFORM}")
execute_process(COMMAND ${TESTS} "[.count_devices]" OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR NOT out MATCHES "clvis devices on platform '[^']*': ([0-9]+)")
  message(FATAL_ERROR "counting the devices of platform '${PLATFORM}' failed (status ${rc}):\n${out}${err}")
endif()
if(CMAKE_MATCH_1 EQUAL 0)
  message("clvis-rusticl: SKIPPED: no OpenCL device on a platform named '${PLATFORM}' "
          "(RUSTICL_ENABLE=$ENV{RUSTICL_ENABLE}); Debian's mesa-opencl-icd provides one (scripts/setup.sh)")
  return()
endif()
set(failed "")
# FILTERS: Catch2 test specs separated by '|' (tests/CMakeLists.txt: the main entry and the extended one).
string(REPLACE "|" ";" filters "${FILTERS}")
foreach(filter IN LISTS filters)
  message("clvis-rusticl: clvis_tests ${filter} on CLVIS_DEVICE=$ENV{CLVIS_DEVICE}")
  execute_process(COMMAND ${TESTS} ${filter} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    set(failed "${failed} ${filter}")
  endif()
endforeach()
if(failed)
  message(FATAL_ERROR "clvis-rusticl: failed on ${PLATFORM}:${failed}")
endif()
