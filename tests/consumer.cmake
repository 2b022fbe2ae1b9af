# Installs clvis into a private prefix, builds examples/ against it as a separate project with
# find_package(clvis), and runs both examples. Run by CTest as `cmake -P` with
# -DBUILD_DIR=... -DSOURCE_DIR=... -DMESH=...
set(prefix ${BUILD_DIR}/consumer-install)
set(work ${BUILD_DIR}/consumer-build)
file(REMOVE_RECURSE ${prefix} ${work})

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "${out}${err}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}")
  endif()
endfunction()

run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples -B ${work} -G Ninja -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_BUILD_TYPE=Release)
run(${CMAKE_COMMAND} --build ${work})
run(${work}/minimal ${MESH} ${work}/minimal)
run(${work}/memory_sphere 20000)
if(NOT EXISTS ${work}/minimal-raster.png AND WITH_IMAGE_IO)
  message(FATAL_ERROR "the minimal example wrote no image")
endif()
