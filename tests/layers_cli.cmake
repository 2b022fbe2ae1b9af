# clvis render --layers K through the built tool (CONVENTIONS.md "Depth layers"): EXR channels
# L0.id .. and L0.Z ..; the raster path's layers and the ray path's in raster-rule coverage equal
# bit for bit (clvis compare per layer: every id and depth equal, none explained); the watertight
# ray path accepted by the referee on every layer; with MPIEXEC, --distribute scene on 3 ranks
# gives one process's layers; --bary, --attributes, --objects, --normals and --position of every
# layer (L0.u ..) checked by layers_files_check; refusals name the flag. Run by CTest as `cmake -P`
# with -DCLVIS=tool -DCHECK=layers_files_check -DMESH=scenes/spot.obj -DSUZANNE=scenes/suzanne.obj
# -DWORK=dir [-DMPIEXEC=mpirun].
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

# --path all with layers: the referee judges every layer (a line each), raster-rule bit-identical.
execute_process(COMMAND ${CLVIS} render ${MESH} ${cam} --layers 3 --path all --coverage raster-rule --json
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 0 OR NOT err MATCHES "layer 2: [0-9]+ equal, 0 explained, 0 errors")
  message(FATAL_ERROR "--path all --layers 3: status ${status}\n${err}")
endif()
string(JSON explained GET "${out}" compare explained)
if(NOT explained EQUAL 0)
  message(FATAL_ERROR "--path all --layers 3 in raster-rule coverage: ${explained} explained, not bit-identical\n${out}")
endif()
if(MPIEXEC)
  run(${MPIEXEC} --allow-run-as-root --oversubscribe -np 3 ${CLVIS} render ${MESH} ${cam} --layers 3 --path raster
      --distribute scene --ids ${WORK}/mpi.exr --depth ${WORK}/mpi-z.exr -q)
  check_layers(raster mpi TRUE)
endif()

# Barycentrics, attributes, object ids, normals and positions of every layer: two items (spot with
# uv, suzanne without), with one layer and with 3, raster and raster-rule ray, read back by
# layers_files_check (CHECK; its header lists the files and what it checks).
set(files ${WORK}/files)
file(MAKE_DIRECTORY ${files})
set(two ${MESH} ${SUZANNE} --eye 1.2,-0.4,-1.8 --target -1.2,0.7,2.2 --fov 45 --near 0.1 --far 20 --width 67
    --height 43) # suzanne behind spot: layers of both items behind the first
run(${CLVIS} render ${two} --layers 1 --path raster --bary ${files}/one-bary.exr --attributes
    ${files}/one-attr.exr --objects ${files}/one-obj.exr --normals ${files}/one-normals.exr --normals-space camera
    --position ${files}/one-position.exr -q)
run(${CLVIS} render ${two} --layers 3 --path raster --ids ${files}/k.exr --bary ${files}/k-bary.exr
    --attributes ${files}/k-attr.exr --objects ${files}/k-obj.exr --normals ${files}/k-normals.exr
    --normals-space camera --position ${files}/k-position.exr -q)
run(${CLVIS} render ${two} --layers 3 --path raster --objects ${files}/k-obj.tif -q)
run(${CLVIS} render ${two} --layers 3 --path ray --coverage raster-rule --bary ${files}/rule-bary.exr
    --attributes ${files}/rule-attr.exr --objects ${files}/rule-obj.exr -q)
run(${CHECK} ${files} 3 ${MESH} ${SUZANNE})

foreach(args "--layers;9" "--layers;2;--samples;4" "--layers;2;--visible;${WORK}/v.txt")
  execute_process(COMMAND ${CLVIS} render ${MESH} ${cam} ${args} --ids ${WORK}/x.exr
                  RESULT_VARIABLE status ERROR_VARIABLE err OUTPUT_VARIABLE out)
  if(status EQUAL 0 OR NOT err MATCHES "--(layers|visible)")
    message(FATAL_ERROR "render ${args}: status ${status}, not refused naming the flag:\n${err}")
  endif()
endforeach()
if(EXISTS ${WORK}/x.exr OR EXISTS ${WORK}/v.txt)
  message(FATAL_ERROR "a refused run left ${WORK}/x.exr or ${WORK}/v.txt")
endif()
