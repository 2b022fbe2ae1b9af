# The clvis tool as users meet it: exit statuses and the first words of its messages for bad
# flags and values, the files it says it wrote, and scene files honoured by every subcommand.
# Run by CTest as `cmake -P` with -DCLVIS=tool -DMESH=scenes/spot.obj -DWORK=dir -DWITH_IMAGE_IO=ON|OFF.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
set(failures "")

# expect(STATUS REGEX args...): the tool exits with STATUS and its output (stderr, then stdout)
# matches REGEX; a status of 2 must also start its message with "clvis:".
function(expect status regex)
  execute_process(COMMAND ${CLVIS} ${ARGN} RESULT_VARIABLE got OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(all "${err}${out}")
  set(why "")
  if(NOT "${got}" STREQUAL "${status}")
    set(why "exit status ${got}, expected ${status}")
  elseif(NOT all MATCHES "${regex}")
    set(why "output does not match '${regex}'")
  elseif(status EQUAL 2 AND NOT err MATCHES "^clvis: ")
    set(why "the error does not start with 'clvis: '")
  endif()
  if(why)
    string(REPLACE ";" " " command "${ARGN}")
    set(failures "${failures}\n  clvis ${command}: ${why}\n    ${all}" PARENT_SCOPE)
  endif()
endfunction()

# Usage errors: flag parsing (CLI11) and values alike exit 2, start with clvis: and name the flag.
expect(2 "--width" render ${MESH} --width abc)
expect(2 "--width" render ${MESH} --width)
expect(2 "--bogus" render ${MESH} --bogus)
expect(2 "--path" render ${MESH} --path zbuffer)
expect(2 "--raster-atomics" render ${MESH} --raster-atomics sometimes)
expect(2 "--raster-mapping" render ${MESH} --raster-mapping tiles)
expect(2 "--ray-mapping" render ${MESH} --ray-mapping pixel)
expect(2 "--fov.*--ortho|--ortho.*--fov" render ${MESH} --fov 30 --ortho 2)
expect(2 "--repeat" render ${MESH} --repeat -1)
expect(2 "--repeat" bench --repeat 0)
expect(2 "--frames" bench --frames 0)
expect(2 "--views" bench --views 0)
expect(2 "--view-size.*--views" bench --view-size 64)
expect(2 "--views.*--rays|--rays.*--views" bench --views 4 --rays)
expect(2 "clvis: --eye: expected 3 numbers" render ${MESH} --eye 1,2 --target 0,0,0)
expect(2 "clvis: --target: is needed with --eye" render ${MESH} --eye 1,2,3)
expect(2 "clvis: --ortho: the view height must be > 0" render ${MESH} --ortho 0)
expect(2 "clvis: --fit: applies to the physical camera only" render ${MESH} --fit overscan)
expect(2 "clvis: --film-gate: is needed with --focal-length" render ${MESH} --focal-length 35)
expect(2 "clvis: --near: " render ${MESH} --near -1)
expect(2 "--width: must be positive" render ${MESH} --width 0)
expect(2 "missing-mesh.obj" render ${WORK}/missing-mesh.obj)
expect(2 "meshes" render)
expect(2 "--bogus" info ${MESH} --bogus)
expect(2 "--bogus" compare a.tif b.tif ${MESH} --bogus)
expect(2 "^clvis: " bogus-command)
# Several devices: what --devices cannot be combined with is refused, the flag named.
expect(2 "clvis: --devices renders one path" render ${MESH} --devices 0,0 --path all)
expect(2 "clvis: --devices renders one camera" render ${MESH} --devices 0,0 --device 0)
expect(2 "clvis: --devices: expected SPEC,SPEC" render ${MESH} --devices 0,,1)
expect(2 "clvis: --device-map: needs --devices" render ${MESH} --device-map ${WORK}/map.png)
expect(2 "--screen-tile" render ${MESH} --devices 0,0 --screen-tile 0)
expect(0 "render" --help)
# Every mesh format that load_mesh reads is listed.
foreach(command render info rays compare)
  expect(0 "OBJ, PLY, STL, glTF 2.0: .gltf, .glb" ${command} --help)
endforeach()
expect(0 "clvis [0-9]" --version)

set(size --width 64 --height 48 --quiet)
# --timings: what a one-off render pays before its first frame, phase by phase.
expect(0 "first frame: device open [0-9.]+ ms, renderer \\(upload\\) [0-9.]+ ms; raster: prepare \\(programs\\) [0-9.]+ ms, first frame [0-9.]+ ms, next [0-9.]+ ms"
       render ${MESH} --width 64 --height 48 --timings)
if(WITH_IMAGE_IO)
  # Unsupported extensions are refused before rendering, listing the formats written.
  expect(2 "--image: .*out.xyz.*\\.exr.*\\.png" render ${MESH} --image ${WORK}/out.xyz)
  expect(2 "--ids: .*\\.exr, \\.tif, \\.tiff" render ${MESH} --ids ${WORK}/ids.png)
  expect(2 "--depth: .*\\.exr" render ${MESH} --depth ${WORK}/z.tif)
  # Both paths: each file written is named.
  expect(0 "wrote ${WORK}/both-raster.png.*wrote ${WORK}/both-ray.png" render ${MESH} --path all
         --image ${WORK}/both.png --width 64 --height 48)
  foreach(file both-raster.png both-ray.png)
    if(NOT EXISTS ${WORK}/${file})
      set(failures "${failures}\n  render --path all --image: ${file} not written")
    endif()
  endforeach()
  # All of a run's files or none (CONVENTIONS.md "Output files"): a file that cannot be written is
  # refused before rendering, naming its flag, and the others are not written either; so is one
  # name for several views (without {view}), for two outputs, or for several MPI processes.
  file(MAKE_DIRECTORY ${WORK}/none)
  set(none ${WORK}/none)
  expect(2 "--depth: .*/no/such/dir/z.exr.*no folder" render ${MESH} ${size} --ids ${none}/ok.tif
         --depth /no/such/dir/z.exr)
  expect(2 "--depth: .*/no/such/dir/z-raster.exr" render ${MESH} ${size} --path all --ids ${none}/ok.tif
         --depth /no/such/dir/z.exr)
  expect(2 "--visible: .*\\.txt" render ${MESH} ${size} --ids ${none}/ok.tif --visible ${none}/ids.csv)
  expect(2 "--depth: .*also the file of --ids" render ${MESH} ${size} --ids ${none}/same.exr --depth ${none}/same.exr)
  file(WRITE ${none}/two.json "{\"width\": 32, \"height\": 24, \"views\": [
    {\"eye\": [0, 0.4, 3], \"target\": [0, 0.3, 0], \"fov\": 40}, {\"eye\": [3, 0, 0], \"target\": [0, 0.3, 0], \"fov\": 40}]}")
  expect(2 "--ids: .*out.tif' would be written 2 times.*\\{view\\}" render ${MESH} --views ${none}/two.json
         --ids ${none}/out.tif -q)
  set(ENV{OMPI_COMM_WORLD_SIZE} 2)
  expect(2 "--distribute: .*2 MPI processes" render ${MESH} ${size} --ids ${none}/x.tif)
  unset(ENV{OMPI_COMM_WORLD_SIZE})
  file(GLOB left ${none}/*)
  list(REMOVE_ITEM left ${none}/two.json)
  if(left)
    set(failures "${failures}\n  runs refused or failed left files behind: ${left}")
  endif()
  # Written under temporary names, renamed at the end: nothing else is left in the folder.
  expect(0 "wrote ${none}/v-0.tif.*wrote ${none}/v-1.exr" render ${MESH} --views ${none}/two.json
         --ids ${none}/v-{view}.tif --depth ${none}/v-{view}.exr --visible ${none}/v-{view}.txt)
  file(GLOB left RELATIVE ${none} ${none}/*)
  list(SORT left)
  if(NOT left STREQUAL "two.json;v-0.exr;v-0.tif;v-0.txt;v-1.exr;v-1.tif;v-1.txt")
    set(failures "${failures}\n  render --views: files left ${left}")
  endif()
endif()
# clvis rays: NumPy's default float64 rays are converted (the answers equal those of the same rays
# as float32 records); an answer file of no known format is refused; the file written is named.
# Bytes written by printf's octal escapes (sh): a .npy header of '<f8' (2, 8), and raw float32.
function(octal_of_hex hex out)
  string(REGEX MATCHALL ".." bytes "${hex}")
  set(text "")
  foreach(b ${bytes})
    math(EXPR v "0x${b}")
    math(EXPR d2 "${v} / 64")
    math(EXPR d1 "(${v} / 8) % 8")
    math(EXPR d0 "${v} % 8")
    string(APPEND text "\\${d2}${d1}${d0}")
  endforeach()
  set(${out} "${text}" PARENT_SCOPE)
endfunction()
set(header "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 8), }")
string(LENGTH "${header}" n)
math(EXPR pad "117 - ${n}") # 10 + 118 = 128 bytes before the data
string(REPEAT " " ${pad} spaces)
# ray (0, 0.3, 3), tmin 0, direction (0, 0, -1), tmax inf, twice: float64, then float32
set(ray64 "0000000000000000333333333333D33F00000000000008400000000000000000")
string(APPEND ray64 "00000000000000000000000000000000000000000000F0BF000000000000F07F")
set(ray32 "000000009A99993E00004040000000000000000000000000000080BF0000807F")
octal_of_hex("${ray64}${ray64}" data64)
octal_of_hex("${ray32}${ray32}" data32)
execute_process(COMMAND printf "\\223NUMPY\\001\\000\\166\\000${header}${spaces}\\n${data64}" OUTPUT_FILE ${WORK}/rays64.npy)
execute_process(COMMAND printf "${data32}" OUTPUT_FILE ${WORK}/rays32.bin)
expect(0 "wrote ${WORK}/hits64.npy" rays ${MESH} --rays ${WORK}/rays64.npy --hits ${WORK}/hits64.npy)
expect(0 "" rays ${MESH} --rays ${WORK}/rays32.bin --hits ${WORK}/hits32.npy -q)
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORK}/hits64.npy ${WORK}/hits32.npy RESULT_VARIABLE differ)
file(READ ${WORK}/hits32.npy hit OFFSET 132 LIMIT 4 HEX)
if(differ OR hit STREQUAL "ffffffff")
  set(failures "${failures}\n  rays: float64 rays do not give the float32 rays' hits (id ${hit})")
endif()
expect(2 "--hits: .*hits.txt.*\\.npy, \\.bin, \\.raw" rays ${MESH} --rays ${WORK}/rays32.bin --hits ${WORK}/hits.txt)
if(EXISTS ${WORK}/hits.txt)
  set(failures "${failures}\n  rays --hits hits.txt: written")
endif()
# clvis rays --query all: (N, K) hits whose first equals the closest hit, and the counts, written
# together; a refused --counts name leaves no --hits file (all or none); the flags need each other.
expect(0 "wrote ${WORK}/all.npy.*wrote ${WORK}/counts.npy" rays ${MESH} --rays ${WORK}/rays32.bin
       --hits ${WORK}/all.npy --query all --max-hits 3 --counts ${WORK}/counts.npy)
file(READ ${WORK}/all.npy all_head OFFSET 10 LIMIT 118) # past the magic and its NUL bytes
file(READ ${WORK}/all.npy all_first OFFSET 128 LIMIT 16 HEX)
file(READ ${WORK}/hits32.npy closest_first OFFSET 128 LIMIT 16 HEX)
if(NOT all_head MATCHES "'shape': \\(2, 3\\)" OR NOT all_first STREQUAL closest_first)
  set(failures "${failures}\n  rays --query all: not (2, 3) hits led by the closest hit (${all_first}, ${closest_first})")
endif()
expect(2 "--counts: .*counts.txt" rays ${MESH} --rays ${WORK}/rays32.bin --hits ${WORK}/all2.npy --query all
       --max-hits 2 --counts ${WORK}/counts.txt)
if(EXISTS ${WORK}/all2.npy)
  set(failures "${failures}\n  rays --query all with a refused --counts: --hits written")
endif()
expect(2 "--max-hits" rays ${MESH} --rays ${WORK}/rays32.bin --hits ${WORK}/all3.npy --query all)
expect(2 "--query all" rays ${MESH} --rays ${WORK}/rays32.bin --hits ${WORK}/all3.npy --max-hits 2)

# -q says nothing while kernels are compiled (cold caches: PoCL's Clang prints its warnings'
# count on standard error itself unless built with -w); --verbose prints each build log.
file(MAKE_DIRECTORY ${WORK}/cold-clvis ${WORK}/cold-pocl)
set(warm_clvis "$ENV{CLVIS_CACHE_DIR}")
set(warm_pocl "$ENV{POCL_CACHE_DIR}")
set(ENV{CLVIS_CACHE_DIR} ${WORK}/cold-clvis)
set(ENV{POCL_CACHE_DIR} ${WORK}/cold-pocl)
execute_process(COMMAND ${CLVIS} render ${MESH} ${size} --path ray RESULT_VARIABLE got ERROR_VARIABLE err)
if(NOT got EQUAL 0 OR NOT err STREQUAL "")
  set(failures "${failures}\n  render -q on cold caches: status ${got}, said: ${err}")
endif()
file(REMOVE_RECURSE ${WORK}/cold-clvis ${WORK}/cold-pocl)
file(MAKE_DIRECTORY ${WORK}/cold-clvis ${WORK}/cold-pocl)
expect(0 "clvis: built kernels/ray_trace[a-z_]*.cl for .* with '[^']*':" render ${MESH} ${size} --path ray --verbose)
foreach(var CLVIS_CACHE_DIR POCL_CACHE_DIR) # as they were: PoCL refuses an empty POCL_CACHE_DIR
  if(var STREQUAL "CLVIS_CACHE_DIR")
    set(value "${warm_clvis}")
  else()
    set(value "${warm_pocl}")
  endif()
  if(value STREQUAL "")
    unset(ENV{${var}})
  else()
    set(ENV{${var}} "${value}")
  endif()
endforeach()

# Flags are checked before any file is read, naming the flag.
expect(2 "--samples: .*1, 2, 4, 8 or 16, got 3" render ${WORK}/missing-mesh.obj --samples 3)
expect(2 "--tile: .*power of two" render ${WORK}/missing-mesh.obj --tile 12)
expect(2 "--leaf-size" render ${WORK}/missing-mesh.obj --leaf-size 0)
expect(2 "--ao: needs --image" render ${WORK}/missing-mesh.obj --ao 4)
expect(2 "--normals: attributes are resolved at one sample" render ${WORK}/missing-mesh.obj --samples 2
       --normals ${WORK}/n.exr)
expect(2 "--bary: for one device in one process" render ${WORK}/missing-mesh.obj --devices 0,0 --bary ${WORK}/b.exr)

# A scene file: its size and its (physical) camera are honoured by render, info and compare.
file(WRITE ${WORK}/scene.json "{\"meshes\": [{\"file\": \"${MESH}\"}], \"width\": 80, \"height\": 40,
  \"camera\": {\"eye\": [0.3, 0.8, 2.5], \"target\": [0, 0.6, 0], \"focal_length\": 35,
               \"film_gate\": [36, 24], \"fit\": \"overscan\"}}")
expect(0 "80x40.*--eye 0.3,0.8,2.5 --target 0,0.6,0" info ${WORK}/scene.json)
# Attributes: spot's vt are its "uv", listed by info for the file and for the scene file's mesh.
expect(0 "attributes uv \\(2\\)" info ${MESH})
expect(0 "5856 triangles, attributes uv \\(2\\)" info ${WORK}/scene.json)
expect(0 "\"height\": 40.*\"width\": 80" render ${WORK}/scene.json --path all --json --quiet)
# The raster path's depth test, chosen or resolved from the device, is reported.
expect(0 "\"raster_atomics\": \"off\"" render ${MESH} ${size} --raster-atomics off --json)
expect(0 "\"raster_atomics\": \"o[nf]f?\"" render ${MESH} ${size} --json)
# Auto as the frame drew it: spot's 5856 triangles over 400x300 keys are few enough for tile
# ownership on PoCL's CPU device (at most one a 16 keys), over 64x48 they are not.
expect(0 "\"raster_atomics\": \"off\"" render ${MESH} --width 400 --height 300 --quiet --json)
expect(0 "\"raster_atomics\": \"on\"" render ${MESH} ${size} --raster-atomics auto --json)
# The raster fine stage's mapping, chosen or measured, is reported with where it came from.
expect(0 "\"raster_mapping\": \"pixel\"" render ${MESH} ${size} --raster-mapping pixel --json)
expect(0 "\"raster_mapping\": \"square\",[ \n]+\"raster_mapping_source\": \"option\"" render ${MESH} ${size} --raster-mapping square --json)
expect(0 "\"raster_mapping\": \"(square|pixel)\",[ \n]+\"raster_mapping_ms\": {[^}]*\"pixel\"[^}]*},[ \n]+\"raster_mapping_source\": \"(measured|cache)\"" render ${MESH} ${size} --raster-mapping auto --json)
# auto: measured on first use (then cached), or forced by CLVIS_TUNE_RASTER_MAPPING.
set(ENV{CLVIS_TUNE_RASTER_MAPPING} pixel)
expect(0 "\"raster_mapping\": \"pixel\",[ \n]+\"raster_mapping_source\": \"forced\"" render ${MESH} ${size} --json)
set(ENV{CLVIS_TUNE_RASTER_MAPPING} tiles)
expect(2 "^clvis: .*CLVIS_TUNE_RASTER_MAPPING must name one of square, pixel, got 'tiles'" render ${MESH} ${size})
unset(ENV{CLVIS_TUNE_RASTER_MAPPING})
# The ray path's mapping, chosen or measured, is reported with where it came from; the single
# mapping renders.
expect(0 "\"ray_mapping\": \"single\",[ \n]+\"ray_mapping_source\": \"option\"" render ${MESH} ${size} --path ray --ray-mapping single --json)
expect(0 "\"ray_mapping\": \"packet\",[ \n]+\"ray_mapping_source\": \"option\"" render ${MESH} ${size} --path ray --ray-mapping packet --json)
expect(0 "\"ray_mapping\": \"(packet|single)\",[ \n]+\"ray_mapping_ms\": {[^}]*\"single\"[^}]*},[ \n]+\"ray_mapping_source\": \"(measured|cache)\"" render ${MESH} ${size} --path ray --ray-mapping auto --json)
expect(0 "\"ray_mapping\": \"auto\"" render ${MESH} ${size} --path raster --json)
set(ENV{CLVIS_TUNE_RAY_MAPPING} single)
expect(0 "\"ray_mapping\": \"single\",[ \n]+\"ray_mapping_source\": \"forced\"" render ${MESH} ${size} --path ray --json)
set(ENV{CLVIS_TUNE_RAY_MAPPING} rays)
expect(2 "^clvis: .*CLVIS_TUNE_RAY_MAPPING must name one of packet, single, got 'rays'" render ${MESH} ${size} --path ray)
unset(ENV{CLVIS_TUNE_RAY_MAPPING})
expect(2 "ray-mapping" render ${MESH} ${size} --path ray --ray-mapping rays)
if(WITH_IMAGE_IO)
  expect(0 "" render ${WORK}/scene.json --image ${WORK}/scene.png --ids ${WORK}/scene.tif --path raster --quiet)
  expect(0 "" render ${WORK}/scene.json --ids ${WORK}/scene-ray.tif --path ray --quiet)
  if(EXISTS ${WORK}/scene.png)
    file(READ ${WORK}/scene.png header OFFSET 16 LIMIT 8 HEX) # PNG IHDR: width, height (big-endian)
    if(NOT header STREQUAL "0000005000000028")
      set(failures "${failures}\n  render scene.json --image: PNG size ${header}, expected 80x40")
    endif()
  else()
    set(failures "${failures}\n  render scene.json --image: no PNG written")
  endif()
  expect(0 "3200 pixels" compare ${WORK}/scene.tif ${WORK}/scene-ray.tif ${WORK}/scene.json)
  expect(2 "--width: 81 does not match the buffers" compare ${WORK}/scene.tif ${WORK}/scene-ray.tif
         ${WORK}/scene.json --width 81)
  expect(0 "" render ${MESH} --ids ${WORK}/small.tif ${size})
  expect(2 "scene.json: width: 80 does not match the buffers" compare ${WORK}/small.tif ${WORK}/small.tif
         ${WORK}/scene.json)
endif()

if(failures)
  message(FATAL_ERROR "clvis tool checks failed:${failures}")
endif()
