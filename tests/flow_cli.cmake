# clvis render --flow (CONVENTIONS.md "Motion between views (flow)"): with a views file of N views
# whose cameras may move items, N - 1 OpenEXR files named by {view}, on both paths, written all
# or none; a name without {view}, a run without --views and a views file naming an item the scene
# lacks are refused before anything is written.
# Run by CTest as `cmake -P` with -DCLVIS=tool -DMESH=scenes/spot.obj -DWORK=dir.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
set(failures "")

function(expect status regex)
  execute_process(COMMAND ${CLVIS} ${ARGN} RESULT_VARIABLE got OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(all "${err}${out}")
  set(why "")
  if(NOT "${got}" STREQUAL "${status}")
    set(why "exit status ${got}, expected ${status}")
  elseif(NOT all MATCHES "${regex}")
    set(why "output does not match '${regex}'")
  endif()
  if(why)
    string(REPLACE ";" " " command "${ARGN}")
    set(failures "${failures}\n  clvis ${command}: ${why}\n    ${all}" PARENT_SCOPE)
  endif()
endfunction()

set(move "[1,0,0,0.05, 0,1,0,0.02, 0,0,1,0, 0,0,0,1]")
file(WRITE ${WORK}/three.json "{\"width\": 48, \"height\": 32, \"views\": [
  {\"eye\": [0, 0.4, 3], \"target\": [0, 0.3, 0], \"fov\": 40},
  {\"eye\": [0.2, 0.4, 3], \"target\": [0, 0.3, 0], \"fov\": 40, \"items\": {\"0\": ${move}}},
  {\"eye\": [0.4, 0.4, 3], \"target\": [0, 0.3, 0], \"ortho\": 2}]}")
file(WRITE ${WORK}/far.json "{\"width\": 48, \"height\": 32, \"views\": [
  {\"eye\": [0, 0.4, 3], \"target\": [0, 0.3, 0]}, {\"eye\": [0, 0.4, 3], \"target\": [0, 0.3, 0], \"items\": {\"5\": ${move}}}]}")

expect(2 "--flow: .*must contain \\{view\\}" render ${MESH} --views ${WORK}/three.json --flow ${WORK}/flow.exr
       --ids ${WORK}/ids-{view}.tif)
expect(2 "--flow: needs --views" render ${MESH} --flow ${WORK}/flow-{view}.exr)
expect(2 "--flow: .*\\.png" render ${MESH} --views ${WORK}/three.json --flow ${WORK}/flow-{view}.png)
expect(2 "far.json: views\\[1\\]\\.items\\.5: no such item" render ${MESH} --views ${WORK}/far.json
       --flow ${WORK}/flow-{view}.exr)
file(GLOB left RELATIVE ${WORK} ${WORK}/*)
list(SORT left)
if(NOT left STREQUAL "far.json;three.json")
  set(failures "${failures}\n  refused runs left files: ${left}")
endif()

foreach(path raster ray)
  file(MAKE_DIRECTORY ${WORK}/${path})
  expect(0 "wrote ${WORK}/${path}/flow-0.exr.*wrote ${WORK}/${path}/flow-1.exr" render ${MESH} --path ${path}
         --views ${WORK}/three.json --flow ${WORK}/${path}/flow-{view}.exr --ids ${WORK}/${path}/ids-{view}.exr)
  file(GLOB written RELATIVE ${WORK}/${path} ${WORK}/${path}/*)
  list(SORT written)
  if(NOT written STREQUAL "flow-0.exr;flow-1.exr;ids-0.exr;ids-1.exr;ids-2.exr")
    set(failures "${failures}\n  render --path ${path} --flow: files ${written}")
  endif()
endforeach()

if(failures)
  message(FATAL_ERROR "flow_cli:${failures}")
endif()
