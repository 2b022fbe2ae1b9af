# clvis render's --attributes, --objects and --normals-space (CONVENTIONS.md "Vertex attributes",
# "Object ids"): refusals naming the flag before anything is written, files for each view of a
# views file, and the channel names of the attributes file (spot.obj's vt: uv.x, uv.y).
# Run by CTest as `cmake -P` with -DCLVIS=tool -DSCENES=scenes/ -DWORK=dir.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
set(failures "")
set(small --width 48 --height 36 -q)
set(views ${WORK}/in/views.json)
file(WRITE ${views} "{\"width\": 40, \"height\": 30, \"views\": [
  {\"eye\": [0, 0.3, 3], \"target\": [0, 0.2, 0], \"up\": [0, 1, 0], \"fov\": 45},
  {\"eye\": [2.5, 1, 1.5], \"target\": [0, 0.2, 0], \"up\": [0, 1, 0], \"fov\": 45}]}")

function(expect status regex)
  execute_process(COMMAND ${CLVIS} ${ARGN} RESULT_VARIABLE got OUTPUT_VARIABLE out ERROR_VARIABLE err
                  WORKING_DIRECTORY ${WORK})
  set(all "${err}${out}")
  if(NOT "${got}" STREQUAL "${status}" OR NOT all MATCHES "${regex}")
    string(REPLACE ";" " " command "${ARGN}")
    set(failures "${failures}\n  clvis ${command}: exit ${got} (expected ${status}), output '${all}'" PARENT_SCOPE)
  endif()
endfunction()

# Refusals, each before rendering: no file of the run is left behind.
expect(2 "--attributes: the scene has no vertex attributes" render ${SCENES}/stanford-bunny.obj ${small}
       --attributes a.exr --ids refused.tif)
expect(2 "--objects: object ids are resolved at one sample per pixel" render ${SCENES}/spot.obj ${small}
       --samples 4 --objects o.exr)
expect(2 "--attributes: attributes are resolved at one sample per pixel" render ${SCENES}/spot.obj ${small}
       --samples 4 --attributes a.exr)
expect(2 "--normals-space" render ${SCENES}/spot.obj ${small} --normals n.exr --normals-space eye)
expect(2 "--attributes.*no folder" render ${SCENES}/spot.obj ${small} --attributes missing/a.exr --ids refused.tif)
expect(2 "--attributes.*the formats written are .exr" render ${SCENES}/spot.obj ${small} --attributes a.png)
expect(2 "--objects.*put \\{view\\} in the name" render ${SCENES}/spot.obj --views ${views}
       --objects o.tif -q)
file(GLOB left LIST_DIRECTORIES false ${WORK}/*)
if(left)
  set(failures "${failures}\n  a refused run left files behind: ${left}")
endif()

# Every view of a views file: ids, objects, attributes and camera-space normals.
expect(0 "" render ${SCENES}/spot.obj ${SCENES}/suzanne.obj --views ${views} --path ray
       --objects o-{view}.tif --attributes a-{view}.exr --normals n-{view}.exr --normals-space camera -q)
foreach(f o-0.tif o-1.tif a-0.exr a-1.exr n-0.exr n-1.exr)
  if(NOT EXISTS ${WORK}/${f})
    set(failures "${failures}\n  views: ${f} was not written")
  endif()
endforeach()
if(EXISTS ${WORK}/a-0.exr)
  # OpenEXR's header holds the channel names as plain text.
  file(STRINGS ${WORK}/a-0.exr names REGEX "uv\\.[xy]")
  if(NOT names MATCHES "uv\\.x" OR NOT names MATCHES "uv\\.y")
    set(failures "${failures}\n  a-0.exr lacks the channels uv.x, uv.y")
  endif()
endif()
expect(0 "" render ${SCENES}/spot.obj ${small} --objects o.exr --path raster)
if(NOT EXISTS ${WORK}/o.exr)
  set(failures "${failures}\n  o.exr was not written")
else()
  file(STRINGS ${WORK}/o.exr names REGEX "object")
  if(NOT names)
    set(failures "${failures}\n  o.exr lacks the channel 'object'")
  endif()
endif()

if(failures)
  message(FATAL_ERROR "attributes_cli:${failures}")
endif()
