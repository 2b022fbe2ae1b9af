# clvis render --layers K through the built tool (CONVENTIONS.md "Depth layers"): EXR channels
# L0.id .. and L0.Z ..; the raster path's layers and the ray path's in raster-rule coverage equal
# bit for bit (clvis compare per layer: every id and depth equal, none explained); the watertight
# ray path accepted by the referee on every layer; with MPIEXEC, --distribute scene on 3 ranks
# gives one process's layers; refusals name the flag. Run by CTest as `cmake -P` with
# -DCLVIS=tool -DMESH=scenes/spot.obj -DWORK=dir [-DMPIEXEC=mpirun].
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
include(${CMAKE_CURRENT_LIST_DIR}/same_pixels.cmake)
set(cam --eye 1.6,0.9,2.2 --target 0,0.3,0 --fov 40 --near 0.1 --far 20 --width 67 --height 43)

# Every layer of `a` and `b` has the same ids and depth bits (`exact`) or is acceptable.
function(check_layers a b exact)
  execute_process(COMMAND ${CLVIS} compare ${WORK}/${a}.exr ${WORK}/${b}.exr ${MESH} ${cam}
                  --depths ${WORK}/${a}-z.exr,${WORK}/${b}-z.exr --json
                  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "compare ${a} ${b}: status ${status}\n${out}${err}")
  endif()
  string(JSON layers LENGTH "${out}" layers)
  if(NOT layers EQUAL 3)
    message(FATAL_ERROR "compare ${a} ${b}: ${layers} layers reported, not 3\n${out}")
  endif()
  if(exact)
    string(JSON explained GET "${out}" explained)
    string(JSON zexplained GET "${out}" depths explained)
    if(NOT explained EQUAL 0 OR NOT zexplained EQUAL 0)
      message(FATAL_ERROR "compare ${a} ${b}: not bit-identical\n${out}")
    endif()
  endif()
endfunction()

run(${CLVIS} render ${MESH} ${cam} --layers 3 --path raster --ids ${WORK}/raster.exr --depth ${WORK}/raster-z.exr -q)
run(${CLVIS} render ${MESH} ${cam} --layers 3 --path ray --coverage raster-rule --ids ${WORK}/rule.exr
    --depth ${WORK}/rule-z.exr -q)
run(${CLVIS} render ${MESH} ${cam} --layers 3 --path ray --ids ${WORK}/ray.exr --depth ${WORK}/ray-z.exr -q)
check_layers(raster rule TRUE)
check_layers(raster ray FALSE)
if(MPIEXEC)
  run(${MPIEXEC} --allow-run-as-root --oversubscribe -np 3 ${CLVIS} render ${MESH} ${cam} --layers 3 --path raster
      --distribute scene --ids ${WORK}/mpi.exr --depth ${WORK}/mpi-z.exr -q)
  check_layers(raster mpi TRUE)
endif()

foreach(args "--layers;9" "--layers;2;--samples;4" "--layers;2;--bary;${WORK}/b.exr")
  execute_process(COMMAND ${CLVIS} render ${MESH} ${cam} ${args} --ids ${WORK}/x.exr
                  RESULT_VARIABLE status ERROR_VARIABLE err OUTPUT_VARIABLE out)
  if(status EQUAL 0 OR NOT err MATCHES "--(layers|bary)")
    message(FATAL_ERROR "render ${args}: status ${status}, not refused naming the flag:\n${err}")
  endif()
endforeach()
if(EXISTS ${WORK}/x.exr)
  message(FATAL_ERROR "a refused run left ${WORK}/x.exr")
endif()
