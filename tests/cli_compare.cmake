# clvis compare through the built tool: buffers of both paths rendered with --cull front (which
# shows a closed mesh's inside), then judged. Every pixel is judged by default, so the same wrong
# answer in both buffers is an error; --differing-only lets it pass; --cull front makes it right;
# --depths judges depth buffers too, and the counts add up, in text and in JSON. Run by CTest as
# `cmake -P` with -DCLVIS=... -DMESH=... -DWORK=...
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
set(camera --width 64 --height 48 --eye 1.4,1.2,2.6 --target 0,0.3,0 --up 0,1,0 --fov 40 --near 1 --far 6)

# Runs the tool; fails unless it exits with `expect`; leaves stdout in `out`.
function(clvis expect)
  execute_process(COMMAND ${CLVIS} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE o ERROR_VARIABLE e)
  message(STATUS "clvis ${ARGN}\n-> ${rc}\n${o}${e}")
  if(NOT rc EQUAL expect)
    message(FATAL_ERROR "expected exit status ${expect}, got ${rc}: clvis ${ARGN}\n${o}${e}")
  endif()
  set(out "${o}" PARENT_SCOPE)
endfunction()

# Fails unless a + b + c == total.
function(sum_is what a b c total)
  math(EXPR sum "${a} + ${b} + ${c}")
  if(NOT sum EQUAL total)
    message(FATAL_ERROR "${what}: equal + explained + errors = ${sum}, not ${total} pixels")
  endif()
endfunction()

# Fails unless the text summary's counts add up (ids, and depths when `depths`).
function(adds_up text depths)
  if(NOT text MATCHES "([0-9]+) pixels, ([0-9]+) judged[^:]*: ([0-9]+) equal, ([0-9]+) explained, ([0-9]+) errors")
    message(FATAL_ERROR "no summary in: ${text}")
  endif()
  set(pixels ${CMAKE_MATCH_1})
  sum_is(ids ${CMAKE_MATCH_3} ${CMAKE_MATCH_4} ${CMAKE_MATCH_5} ${pixels})
  if(depths)
    if(NOT text MATCHES "depths: ([0-9]+) equal, ([0-9]+) explained, ([0-9]+) errors")
      message(FATAL_ERROR "no depth summary in: ${text}")
    endif()
    sum_is(depths ${CMAKE_MATCH_1} ${CMAKE_MATCH_2} ${CMAKE_MATCH_3} ${pixels})
  endif()
endfunction()

foreach(path raster ray)
  clvis(0 render ${MESH} ${camera} --cull front --path ${path} --ids ${WORK}/${path}.tif --depth ${WORK}/${path}.exr -q)
endforeach()
clvis(0 render ${MESH} ${camera} --path raster --ids ${WORK}/plain.tif --depth ${WORK}/plain.exr -q)

# Judged with the options they were rendered with: no error, ids and depths.
clvis(0 compare ${WORK}/raster.tif ${WORK}/ray.tif ${MESH} ${camera} --cull front
      --depths ${WORK}/raster.exr,${WORK}/ray.exr)
adds_up("${out}" TRUE)
if(NOT out MATCHES "3072 pixels, 3072 judged: [0-9]+ equal, [0-9]+ explained, 0 errors")
  message(FATAL_ERROR "expected every one of 3072 pixels judged, without error: ${out}")
endif()

# The same wrong answer in both (the inside shows where culling was not asked for): an error, since
# every pixel is judged; unjudged with --differing-only.
clvis(1 compare ${WORK}/raster.tif ${WORK}/raster.tif ${MESH} ${camera})
adds_up("${out}" FALSE)
if(NOT out MATCHES "\\[both\\]")
  message(FATAL_ERROR "expected errors of both buffers: ${out}")
endif()
clvis(0 compare ${WORK}/raster.tif ${WORK}/raster.tif ${MESH} ${camera} --differing-only)
adds_up("${out}" FALSE)

# Depths of another picture (the outside's) beside the inside's ids: depth errors only.
clvis(1 compare ${WORK}/raster.tif ${WORK}/ray.tif ${MESH} ${camera} --cull front
      --depths ${WORK}/raster.exr,${WORK}/plain.exr)
adds_up("${out}" TRUE)
if(NOT out MATCHES ": [0-9]+ equal, [0-9]+ explained, 0 errors" OR NOT out MATCHES "depths: [0-9]+ equal, [0-9]+ explained, [1-9][0-9]* errors \\(first 0, second [1-9]")
  message(FATAL_ERROR "expected depth errors of the second buffer only: ${out}")
endif()
if(NOT out MATCHES "wrong depth")
  message(FATAL_ERROR "expected the wrong depths described: ${out}")
endif()

# The JSON report says the same.
clvis(1 compare ${WORK}/raster.tif ${WORK}/ray.tif ${MESH} ${camera} --cull front
      --depths ${WORK}/raster.exr,${WORK}/plain.exr --json)
string(JSON pixels GET "${out}" pixels)
string(JSON equal GET "${out}" equal)
string(JSON explained GET "${out}" explained)
string(JSON errors GET "${out}" errors)
string(JSON depth_equal GET "${out}" depths equal)
string(JSON depth_explained GET "${out}" depths explained)
string(JSON depth_errors GET "${out}" depths errors)
sum_is("JSON ids" ${equal} ${explained} ${errors} ${pixels})
sum_is("JSON depths" ${depth_equal} ${depth_explained} ${depth_errors} ${pixels})
if(depth_errors EQUAL 0)
  message(FATAL_ERROR "JSON: no depth errors")
endif()

# A malformed --depths is unusable input.
clvis(2 compare ${WORK}/raster.tif ${WORK}/ray.tif ${MESH} ${camera} --depths ${WORK}/raster.exr)

# Four samples per pixel (--samples 4): files of channels id0..id3 and Z0..Z3 from both paths, every
# sample judged (64 x 48 x 4 = 12288), no error; a sample count that does not exist is refused.
foreach(path raster ray)
  clvis(0 render ${MESH} ${camera} --samples 4 --path ${path} --ids ${WORK}/ms-${path}.exr
        --depth ${WORK}/msz-${path}.exr --image ${WORK}/ms-${path}.png -q)
endforeach()
clvis(0 compare ${WORK}/ms-raster.exr ${WORK}/ms-ray.exr ${MESH} ${camera}
      --depths ${WORK}/msz-raster.exr,${WORK}/msz-ray.exr)
adds_up("${out}" TRUE)
if(NOT out MATCHES "12288 pixels, 12288 judged: [0-9]+ equal, [0-9]+ explained, 0 errors")
  message(FATAL_ERROR "expected every one of 12288 samples judged, without error: ${out}")
endif()
clvis(2 compare ${WORK}/ms-raster.exr ${WORK}/raster.tif ${MESH} ${camera})
execute_process(COMMAND ${CLVIS} render ${MESH} ${camera} --samples 3 -q RESULT_VARIABLE rc ERROR_VARIABLE e)
if(rc EQUAL 0 OR NOT e MATCHES "got 3")
  message(FATAL_ERROR "--samples 3 should be refused, naming 3: ${rc} ${e}")
endif()
