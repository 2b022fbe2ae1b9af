# clvis render --distribute frames under mpirun: every view's id and depth files, written by the
# rank that holds the view, hold the pixels of one process rendering the views file (idiff with
# no tolerance: the files differ only in their time stamps; spot's ids are exact as floats); rank
# 0 names every rank's time. Run by CTest as `cmake -P` with -DCLVIS=tool -DMPIEXEC=mpirun
# -DIDIFF=idiff -DRANKS=N -DMESH=scenes/spot.obj -DWORK=dir -DPATH_NAME=raster|ray.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
# Seven views around spot (its bounds lie within a unit of the origin), an odd image size.
set(views "")
foreach(eye "0,0.4,3" "2.5,1,1.5" "-2.5,0.5,1" "0,3,0.5" "1.5,-1,-2.5" "-2,1.5,-2" "3,0,0")
  string(REPLACE "," ", " eye "${eye}")
  list(APPEND views "{\"eye\": [${eye}], \"target\": [0, 0.3, 0], \"fov\": 40}")
endforeach()
string(REPLACE ";" ",\n  " views "${views}")
file(WRITE ${WORK}/views.json "{\"width\": 97, \"height\": 61, \"views\": [\n  ${views}\n]}\n")

include(${CMAKE_CURRENT_LIST_DIR}/same_pixels.cmake)

set(common ${MESH} --views ${WORK}/views.json --path ${PATH_NAME} -q)
run(${CLVIS} render ${common} --ids ${WORK}/one-{view}.tif --depth ${WORK}/one-{view}.exr)
run(${MPIEXEC} --allow-run-as-root --oversubscribe -np ${RANKS} ${CLVIS} render ${MESH} --views ${WORK}/views.json
    --path ${PATH_NAME} --distribute frames --ids ${WORK}/dist-{view}.tif --depth ${WORK}/dist-{view}.exr)
math(EXPR last_rank "${RANKS} - 1")
if(NOT said MATCHES "frames on ${RANKS} ranks" OR NOT said MATCHES "rank 0: [0-9.]+ ms"
   OR NOT said MATCHES "rank ${last_rank}: [0-9.]+ ms")
  message(FATAL_ERROR "rank 0 does not report every rank's time:\n${said}")
endif()
# Each rank says the files it wrote (its views').
if(NOT said MATCHES "rank 0 wrote ${WORK}/dist-0.tif" OR NOT said MATCHES "rank ${last_rank} wrote ${WORK}/dist-6.exr")
  message(FATAL_ERROR "the ranks do not say which files they wrote:\n${said}")
endif()
# All or none over the ranks: a file no rank can write refuses the run before rendering, and no
# rank leaves its files; so do several ranks without --distribute (they would share the names).
file(MAKE_DIRECTORY ${WORK}/none)
foreach(args "--distribute;frames;--views;${WORK}/views.json;--ids;${WORK}/none/n-{view}.tif;--depth;/no/such/dir/z-{view}.exr"
             "--ids;${WORK}/none/x.tif")
  execute_process(COMMAND ${MPIEXEC} --allow-run-as-root --oversubscribe -np ${RANKS} ${CLVIS} render ${MESH}
                  --path ${PATH_NAME} ${args} RESULT_VARIABLE status ERROR_VARIABLE err OUTPUT_VARIABLE out)
  if(status EQUAL 0 OR NOT err MATCHES "clvis: --(depth|distribute): ")
    message(FATAL_ERROR "render ${args} on ${RANKS} ranks: status ${status}, not refused naming the flag:\n${err}")
  endif()
endforeach()
file(GLOB left ${WORK}/none/*)
if(left)
  message(FATAL_ERROR "refused runs on ${RANKS} ranks left files: ${left}")
endif()
foreach(v RANGE 0 6)
  foreach(kind tif exr)
    same_pixels(${WORK}/one-${v}.${kind} ${WORK}/dist-${v}.${kind} "view ${v}, one process against ${RANKS} ranks")
  endforeach()
endforeach()
message(STATUS "frames on ${RANKS} ranks, ${PATH_NAME} path: 7 views' files equal to one process's")
