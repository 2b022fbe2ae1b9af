# Instances never expand (issue 34): the tool on a scene file of COUNT instances of MESH (the bunny:
# 400 of them are 28 M triangles, about 0.7 GB as an expansion) stays under LIMIT_MB of peak
# resident memory in every command that reads the whole scene: info (bounds), the ray path's ids,
# a shaded image, the raster path's ids, the brute path's ids (a few pixels: every triangle each),
# and the referee judging the two paths' ids (compare: it keeps set up what the image can show,
# where every triangle's set-up took 7.8 GB). Run by CTest as `cmake -P` with -DCLVIS=tool
# -DTIME=/usr/bin/time -DMESH=scenes/stanford-bunny.obj -DCOUNT=400 -DLIMIT_MB=400 -DWORK=dir.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

# A grid of instances, each turned about y by its own angle (a rotation exact in no float).
set(matrices "")
math(EXPR last "${COUNT} - 1")
foreach(k RANGE ${last})
  math(EXPR i "${k} % 20")
  math(EXPR j "${k} / 20")
  math(EXPR c "1000 - (${k} % 7) * 50")   # cos in thousandths, not normalised: a scale too
  math(EXPR s "(${k} % 5) * 100")
  set(m "[0.${c},0,0.${s},${i}.25, 0,1,0,${j}.25, -0.${s},0,0.${c},0, 0,0,0,1]")
  string(REPLACE "0.1000" "1.000" m "${m}")
  if(matrices)
    set(matrices "${matrices},${m}")
  else()
    set(matrices "${m}")
  endif()
endforeach()
file(WRITE ${WORK}/scene.json "{\"meshes\": [{\"file\": \"${MESH}\", \"instances\": [${matrices}]}]}\n")

set(failures "")
# peak(NAME args...): runs the tool under `time`, which writes its peak resident set in KiB.
function(peak name)
  execute_process(COMMAND ${TIME} -f %M -o ${WORK}/${name}.rss ${CLVIS} ${ARGN}
                  RESULT_VARIABLE got OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT got EQUAL 0)
    set(failures "${failures}\n  ${name}: exit status ${got}\n    ${err}${out}" PARENT_SCOPE)
    return()
  endif()
  file(STRINGS ${WORK}/${name}.rss lines)
  list(GET lines -1 kib)
  math(EXPR mib "${kib} / 1024")
  message(STATUS "${name}: peak ${mib} MiB")
  if(mib GREATER ${LIMIT_MB})
    set(failures "${failures}\n  ${name}: peak resident ${mib} MiB, more than ${LIMIT_MB} MiB" PARENT_SCOPE)
  endif()
endfunction()

peak(info info ${WORK}/scene.json)
peak(ray_ids render ${WORK}/scene.json --path ray --width 160 --height 120 --ids ${WORK}/ray.tif -q)
peak(ray_image render ${WORK}/scene.json --path ray --width 160 --height 120 --image ${WORK}/ray.png -q)
peak(raster_ids render ${WORK}/scene.json --path raster --width 160 --height 120 --ids ${WORK}/raster.tif -q)
peak(brute_ids render ${WORK}/scene.json --path brute --width 4 --height 3 --ids ${WORK}/brute.tif -q)
peak(compare compare ${WORK}/ray.tif ${WORK}/raster.tif ${WORK}/scene.json)

if(failures)
  message(FATAL_ERROR "the tool held more than an instanced scene needs:${failures}")
endif()
