# clvis render --views with other tools' cameras (CONVENTIONS.md "Cameras from other tools"): a
# NeRF transforms.json, a COLMAP text model's folder and a glTF file's camera nodes write the same
# files as the clvis views file of the same cameras; a glTF without --width is refused naming it.
# Run by CTest as `cmake -P` with -DCLVIS=tool -DMESH=scenes/spot.obj -DWORK=dir -DWITH_IMAGE_IO=ON|OFF.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/colmap)
set(failures "")

function(run status regex)
  execute_process(COMMAND ${CLVIS} ${ARGN} RESULT_VARIABLE got OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT "${got}" STREQUAL "${status}" OR NOT "${err}${out}" MATCHES "${regex}")
    string(REPLACE ";" " " command "${ARGN}")
    set(failures "${failures}\n  clvis ${command}: exit ${got} (expected ${status}), output ${err}${out}" PARENT_SCOPE)
  endif()
endfunction()

# Two cameras looking at spot (about the unit cube around the origin): from (0, 0.4, 3) down -z,
# and from (0, -3, 0) up +y with -x up; both exact in COLMAP's quaternions too.
set(pose0 "[[1, 0, 0, 0], [0, 1, 0, 0.4], [0, 0, 1, 3], [0, 0, 0, 1]]")
set(pose1 "[[0, -1, 0, 0], [0, 0, -1, -3], [1, 0, 0, 0], [0, 0, 0, 1]]")
file(WRITE ${WORK}/transforms.json "{\"w\": 48, \"h\": 32, \"fl_x\": 40, \"fl_y\": 41, \"cx\": 24.5, \"cy\": 15.25,
  \"frames\": [{\"transform_matrix\": ${pose0}}, {\"transform_matrix\": ${pose1}}]}")
file(WRITE ${WORK}/same.json "{\"width\": 48, \"height\": 32, \"views\": [
  {\"pose\": [1, 0, 0, 0, 0, 1, 0, 0.4, 0, 0, 1, 3, 0, 0, 0, 1], \"intrinsics\": [40, 41, 24.5, 15.25]},
  {\"pose\": [0, -1, 0, 0, 0, 0, -1, -3, 1, 0, 0, 0, 0, 0, 0, 1], \"intrinsics\": [40, 41, 24.5, 15.25]}]}")
# COLMAP: world-to-camera [R | t] in OpenCV's axes, R's rows r, -u, f of each camera, t = -R eye:
# the first R = diag(1, -1, -1) (quaternion 0 1 0 0), t = (0, 0.4, 3); the second R's rows
# (0, 0, 1), (1, 0, 0), (0, 1, 0) (quaternion 0.5 0.5 0.5 0.5), t = (0, 0, 3). Listed out of order.
file(WRITE ${WORK}/colmap/cameras.txt "# one camera\n1 PINHOLE 48 32 40 41 24.5 15.25\n")
file(WRITE ${WORK}/colmap/images.txt "# two lines per image\n2 0.5 0.5 0.5 0.5 0 0 3 1 b.png\n\n1 0 1 0 0 0 0.4 3 1 a.png\n1.5 2.5 -1\n")
file(WRITE ${WORK}/cameras.gltf "{\"asset\": {\"version\": \"2.0\"}, \"cameras\": [{\"type\": \"perspective\",
  \"perspective\": {\"yfov\": 0.75, \"znear\": 0.5, \"zfar\": 9}}], \"nodes\": [{\"camera\": 0, \"translation\": [0, 0.4, 3]},
  {\"camera\": 0, \"translation\": [3, 0.2, 0], \"rotation\": [0, 0.70710678118654757, 0, 0.70710678118654757]}],
  \"scenes\": [{\"nodes\": [0, 1]}]}")

foreach(kind transforms.json same.json colmap)
  set(out ${WORK}/out-${kind})
  file(MAKE_DIRECTORY ${out})
  if(WITH_IMAGE_IO)
    run(0 "" render ${MESH} --views ${WORK}/${kind} --path ray -q --ids ${out}/ids-{view}.exr
        --visible ${out}/v-{view}.txt)
  else()
    run(0 "" render ${MESH} --views ${WORK}/${kind} --path ray -q --visible ${out}/v-{view}.txt)
  endif()
endforeach()
file(GLOB made RELATIVE ${WORK}/out-same.json ${WORK}/out-same.json/*)
list(LENGTH made count)
if(count LESS 2)
  set(failures "${failures}\n  the clvis views file wrote ${count} files")
endif()
# A file's bytes, in hex, without OpenEXR's capDate (the second it was written).
function(bytes_of path out)
  file(READ ${path} hex HEX)
  string(REGEX REPLACE "(6361704461746500737472696e6700........)[0-9a-f]+(6368616e6e656c7300)" "\\1\\2" hex "${hex}")
  set(${out} "${hex}" PARENT_SCOPE)
endfunction()
foreach(f ${made})
  bytes_of(${WORK}/out-same.json/${f} want)
  foreach(kind transforms.json colmap)
    if(NOT EXISTS ${WORK}/out-${kind}/${f})
      set(failures "${failures}\n  --views ${kind} did not write ${f}")
    else()
      bytes_of(${WORK}/out-${kind}/${f} got)
      if(NOT got STREQUAL want)
        set(failures "${failures}\n  --views ${kind}: ${f} differs from the clvis views file's")
      endif()
    endif()
  endforeach()
endforeach()
# The glTF file needs a size, and renders with one.
run(2 "cameras.gltf: glTF cameras give no image size: give --width" render ${MESH} --views ${WORK}/cameras.gltf
    --visible ${WORK}/g-{view}.txt)
run(0 "" render ${MESH} --views ${WORK}/cameras.gltf --width 48 --height 32 --path ray -q --visible ${WORK}/g-{view}.txt)
if(NOT EXISTS ${WORK}/g-1.txt)
  set(failures "${failures}\n  --views cameras.gltf --width 48 --height 32 wrote no g-1.txt")
endif()

if(failures)
  message(FATAL_ERROR "views_import_cli:${failures}")
endif()
