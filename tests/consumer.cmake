# Installs clvis into a private prefix and uses it there, as a user would: builds examples/ and
# tests/consumer/ as separate projects with find_package(clvis) (tests/consumer/ also with clang++,
# whose default standard is older than C++17, when it is found), runs them, and runs the installed
# clvis tool. Run by CTest as `cmake -P` with -DBUILD_DIR=... -DSOURCE_DIR=... -DMESH=...
# -DWITH_IMAGE_IO=... -DWITH_CLI=...
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

# Configures, builds and runs one consumer project; extra arguments go to its configure step.
function(consume name source)
  set(dir ${work}/${name})
  run(${CMAKE_COMMAND} -S ${source} -B ${dir} -G Ninja -DCMAKE_PREFIX_PATH=${prefix}
      -DCMAKE_BUILD_TYPE=Release ${ARGN})
  run(${CMAKE_COMMAND} --build ${dir})
endfunction()

run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

consume(examples ${SOURCE_DIR}/examples)
run(${work}/examples/minimal ${MESH} ${work}/examples/minimal)
run(${work}/examples/memory_sphere 20000)
if(NOT EXISTS ${work}/examples/minimal-raster.png AND WITH_IMAGE_IO)
  message(FATAL_ERROR "the minimal example wrote no image")
endif()

consume(consumer ${SOURCE_DIR}/tests/consumer)
run(${work}/consumer/opencl_first ${MESH})
run(${work}/consumer/clvis_first ${MESH})
# The build tree is a package as well (export() in the top CMakeLists.txt): clvis_DIR=<build>.
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer -B ${work}/consumer-build-tree -G Ninja
    -DCMAKE_BUILD_TYPE=Release -Dclvis_DIR=${BUILD_DIR} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
run(${CMAKE_COMMAND} --build ${work}/consumer-build-tree)
run(${work}/consumer-build-tree/clvis_first ${MESH})

find_program(CLANGXX clang++)
if(CLANGXX)
  consume(consumer-clang ${SOURCE_DIR}/tests/consumer -DCMAKE_CXX_COMPILER=${CLANGXX})
  run(${work}/consumer-clang/opencl_first ${MESH})
  run(${work}/consumer-clang/clvis_first ${MESH})
endif()

# The installed tool starts from its prefix (its RUNPATH finds the installed libraries) and works.
if(WITH_CLI)
  set(tool ${prefix}/bin/clvis)
  run(${tool} --version)
  run(${tool} info ${MESH})
  if(WITH_IMAGE_IO)
    run(${tool} render ${MESH} --width 64 --height 48 --path all --image ${work}/tool.png --quiet)
    foreach(path raster ray)
      if(NOT EXISTS ${work}/tool-${path}.png)
        message(FATAL_ERROR "the installed tool wrote no ${work}/tool-${path}.png")
      endif()
    endforeach()
  else()
    run(${tool} render ${MESH} --width 64 --height 48 --path all --quiet)
  endif()
endif()
