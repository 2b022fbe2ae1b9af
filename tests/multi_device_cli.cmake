# clvis render --devices 0,1: the frame two devices drew (PoCL's CPU listed twice by the CTest
# entry) holds the pixels of one device's frame (idiff with no tolerance: the files differ only in
# their time stamps), by both paths, with odd tiles; each device's share is said. Run by CTest as
# `cmake -P` with -DCLVIS=tool -DIDIFF=idiff -DMESH=scenes/spot.obj -DWORK=dir.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

include(${CMAKE_CURRENT_LIST_DIR}/same_pixels.cmake)

set(view ${MESH} --width 203 --height 117 --eye 0.5,0.8,2.5 --target 0,0.3,0)
foreach(path raster ray)
  run(${CLVIS} render ${view} --path ${path} --device 0 -q --ids ${WORK}/one-${path}.tif --depth ${WORK}/one-${path}.exr)
  run(${CLVIS} render ${view} --path ${path} --devices 0,1 --screen-tile 37 --ids ${WORK}/two-${path}.tif
      --depth ${WORK}/two-${path}.exr --device-map ${WORK}/map-${path}.png)
  if(NOT said MATCHES "device 0 \\([^)]+\\): [0-9]+ tiles" OR NOT said MATCHES "device 1 \\([^)]+\\): [0-9]+ tiles")
    message(FATAL_ERROR "--devices does not say each device's share:\n${said}")
  endif()
  foreach(kind tif exr)
    same_pixels(${WORK}/one-${path}.${kind} ${WORK}/two-${path}.${kind} "${path} path, one device against two")
  endforeach()
endforeach()
# clvis devices marks only the device Device::open() picks, though both are named alike.
run(${CLVIS} devices)
execute_process(COMMAND ${CLVIS} devices OUTPUT_VARIABLE listed)
string(REGEX MATCHALL "\n[0-9]+\\*|^[0-9]+\\*" marked "${listed}")
list(LENGTH marked n)
if(NOT n EQUAL 1)
  message(FATAL_ERROR "clvis devices marks ${n} devices as the default, not 1:\n${listed}")
endif()
