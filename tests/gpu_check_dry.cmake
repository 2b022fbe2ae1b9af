# scripts/gpu-check.sh without a GPU (CTest gpu_check_dry): nvidia-smi and clinfo are stubs on the
# PATH, the build steps are echoed (GPU_CHECK_DRY_RUN=1), the built binaries stand in (each test
# step lists what its filter selects; each tool step checks its arguments). Three runs:
#   walk:     every step runs, in order, and says so; $OUT holds summary.txt and the tarball only;
#             no filter selects nothing, and the device suite holds no case excluded on purpose;
#             the sharded suites' shards, each named case by case, select exactly the filter's cases;
#   no_cl:    nvidia-smi sees a GPU that OpenCL does not list: a FAIL line, the GPU steps skipped;
#   deadline: a clinfo that hangs is cut by its timeout, and every step after the global deadline
#             is skipped, saying so; what ran is in $OUT.
# cmake -DSCRIPT=scripts/gpu-check.sh -DTESTS=clvis_tests -DCLI=clvis -DWORK=dir -P gpu_check_dry.cmake
foreach(var SCRIPT TESTS CLI WORK)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "gpu_check_dry.cmake: pass -D${var}=...")
  endif()
endforeach()
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/stubs)
file(WRITE ${WORK}/stubs/nvidia-smi [=[#!/bin/sh
case "$*" in
*--query-gpu*) echo "NVIDIA H200, 143771 MiB, 580.159.03" ;;
*) echo "GPU 0: NVIDIA H200 (stub of gpu_check_dry.cmake)" ;;
esac
]=])
file(WRITE ${WORK}/stubs/clinfo [=[#!/bin/sh
[ -z "$STUB_CLINFO_SLEEP" ] || sleep "$STUB_CLINFO_SLEEP"
echo "Platform #0: Portable Computing Language"
echo " \`-- Device #0: cpu (stub of gpu_check_dry.cmake)"
[ "$STUB_CLINFO_GPU" = 0 ] && exit 0
echo "Platform #1: NVIDIA CUDA"
echo " \`-- Device #0: NVIDIA H200"
]=])
execute_process(COMMAND chmod +x ${WORK}/stubs/nvidia-smi ${WORK}/stubs/clinfo)

# run NAME EXPECT_OK [VAR=VALUE...]: the script in a dry run; sets summary_<NAME> and out_<NAME>.
function(run name expect_ok)
  set(out ${WORK}/${name}/out)
  execute_process(
    COMMAND ${CMAKE_COMMAND} -E env "PATH=${WORK}/stubs:$ENV{PATH}" OUT=${out} GPU_CHECK_WORK=${WORK}/${name}/work
            GPU_CHECK_DRY_RUN=1 GPU_CHECK_TESTS=${TESTS} GPU_CHECK_CLI=${CLI} ${ARGN} bash ${SCRIPT}
    RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
  message(STATUS "gpu-check.sh (${name}) exited ${rc}:\n${stdout}${stderr}")
  if(expect_ok AND NOT rc EQUAL 0)
    message(FATAL_ERROR "${name}: gpu-check.sh should succeed in a dry run, it exited ${rc}")
  elseif(NOT expect_ok AND rc EQUAL 0)
    message(FATAL_ERROR "${name}: gpu-check.sh should report the failure, it exited 0")
  endif()
  # What comes back from the device machine: the summary and one tarball, nothing else.
  file(GLOB left RELATIVE ${out} ${out}/* ${out}/.*)
  list(SORT left)
  if(NOT left STREQUAL "gpu-check-logs.tar.gz;summary.txt")
    message(FATAL_ERROR "${name}: $OUT should hold summary.txt and gpu-check-logs.tar.gz only, it holds: ${left}")
  endif()
  file(READ ${out}/summary.txt summary)
  set(summary_${name} "${summary}" PARENT_SCOPE)
  set(out_${name} ${out} PARENT_SCOPE)
endfunction()

function(expect name pattern)
  if(NOT summary_${name} MATCHES "${pattern}")
    message(FATAL_ERROR "${name}: the summary lacks '${pattern}':\n${summary_${name}}")
  endif()
endfunction()

function(expect_not name pattern)
  if(summary_${name} MATCHES "${pattern}")
    message(FATAL_ERROR "${name}: the summary should not match '${pattern}':\n${summary_${name}}")
  endif()
endfunction()

# --- walk: every step, each with a START and an ok END ------------------------------------------
run(walk TRUE GPU_CHECK_SHARDS=3) # the sharded steps name each case of 3 shards; each shard lists its own
set(steps "clinfo" "configure" "build the tool \\(clvis_cli\\)" "build the tests \\(clvis_tests\\)" "clvis devices"
    "device suite on NVIDIA" "agreement suite on NVIDIA" "raster-rule cases on NVIDIA"
    "float-only exact fallback on NVIDIA" "keys on NVIDIA against PoCL's" "clvis bench --quick on NVIDIA"
    "clvis bench --rays --quick on NVIDIA"
    "1M-triangle sphere \\(make_uv_sphere\\) as PLY" "render sphere-1M 1920x1080 raster on NVIDIA"
    "render sphere-1M 1920x1080 ray on NVIDIA" "render bunny 1920x1080 raster square on NVIDIA"
    "render bunny 1920x1080 raster pixel on NVIDIA" "render bunny 1920x1080 ray packet on NVIDIA"
    "render bunny 1920x1080 ray single on NVIDIA" "slow device cases on NVIDIA" "device suite on PoCL"
    "clvis bench --quick on PoCL" "clvis bench --rays --quick on PoCL" "render bunny 1920x1080 raster on PoCL"
    "render bunny 1920x1080 ray on PoCL")
foreach(s IN LISTS steps)
  expect(walk "\\+[0-9]+s START ${s} \\(timeout [0-9]+ s\\)")
  expect(walk "\\+[0-9]+s END   ${s}: ok")
endforeach()
expect(walk "nvidia-smi: NVIDIA H200")
expect(walk "NVIDIA OpenCL driver: ")
expect(walk "result: ok")
expect(walk "END   device suite on NVIDIA: ok \\([0-9]+ s\\); [0-9]+ matching test cases, in 3 shards")
expect(walk "END   float-only exact fallback on NVIDIA: ok \\([0-9]+ s\\); [0-9]+ matching test cases, in 3 shards")
expect_not(walk "SKIP|FAIL|missing:")
# The START line precedes its END line.
string(FIND "${summary_walk}" "START device suite" start_at)
string(FIND "${summary_walk}" "END   device suite" end_at)
if(start_at GREATER end_at)
  message(FATAL_ERROR "walk: the device suite's END line comes before its START line")
endif()
# The tarball holds every step's log; the device suite's list holds none of the excluded cases.
execute_process(COMMAND tar -xzf ${out_walk}/gpu-check-logs.tar.gz -C ${WORK}/walk RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "walk: the tarball does not unpack")
endif()
foreach(log clinfo.txt clinfo-l.txt configure.log build-cli.log build-tests.log devices.txt device.log agree.log
        rule.log exact-float.log reference-pocl.log bench.log sphere.log render-sphere-raster.log
        render-bunny-ray-single.log slow.log device-pocl.log bench-pocl.log bench-rays.log bench-rays-pocl.log
        render-bunny-ray-pocl.log preflight.txt
        vendors/nvidia.icd)
  if(NOT EXISTS ${WORK}/walk/logs/${log})
    message(FATAL_ERROR "walk: the tarball lacks logs/${log}")
  endif()
endforeach()
file(READ ${WORK}/walk/logs/device.log device_list)
foreach(excluded "\\[pocl\\]" "\\[multi_device\\]" "\\[gltf\\]" "\\[slow\\]" "devices are picked by index")
  if(device_list MATCHES "${excluded}")
    message(FATAL_ERROR "walk: the device suite selects a case it excludes (${excluded})")
  endif()
endforeach()
if(NOT device_list MATCHES "\\[device\\]")
  message(FATAL_ERROR "walk: the device suite lists no [device] case:\n${device_list}")
endif()
# The float-only step runs the list of CTest's device_exact_float: at least a case per pattern.
file(STRINGS ${CMAKE_CURRENT_LIST_DIR}/exact_float_cases.txt exact_float_cases LIMIT_COUNT 1)
string(REPLACE "," ";" exact_float_cases "${exact_float_cases}")
list(LENGTH exact_float_cases exact_float_count)
file(READ ${WORK}/walk/logs/exact-float.log exact_float_list)
string(REGEX MATCH "([0-9]+) matching test case" _ "${exact_float_list}")
if(NOT CMAKE_MATCH_1 OR CMAKE_MATCH_1 LESS exact_float_count)
  message(FATAL_ERROR
          "walk: the float-only step selects fewer cases than its list's ${exact_float_count} patterns:\n${exact_float_list}")
endif()
file(READ ${WORK}/walk/logs/reference-pocl.log reference_list)
if(NOT reference_list MATCHES "a second device passes the referee")
  message(FATAL_ERROR "walk: the keys-against-PoCL step does not select reference_device_test.cpp's case")
endif()

# --- no_cl: a GPU that OpenCL does not list -----------------------------------------------------
run(no_cl FALSE STUB_CLINFO_GPU=0)
expect(no_cl "FAIL: nvidia-smi sees 'NVIDIA H200, 143771 MiB, 580.159.03' but OpenCL lists no NVIDIA device")
expect(no_cl "SKIP  device suite on NVIDIA: OpenCL lists no NVIDIA device")
expect(no_cl "SKIP  keys on NVIDIA against PoCL's: OpenCL lists no NVIDIA device")
expect(no_cl "SKIP  clvis bench --quick and the 1080p renders on NVIDIA: OpenCL lists no NVIDIA device")
expect(no_cl "result: FAILED: NVIDIA OpenCL device")
expect_not(no_cl "START device suite")

# --- deadline: a step cut by its timeout, the rest skipped -------------------------------------
run(deadline FALSE GPU_CHECK_DEADLINE_S=8 STUB_CLINFO_SLEEP=60)
expect(deadline "START clinfo \\(timeout [1-8] s\\)")
expect(deadline "END   clinfo: TIMEOUT after [1-8] s")
foreach(s "configure" "build the tests \\(clvis_tests\\)" "device suite on NVIDIA" "clvis bench --quick on NVIDIA"
        "slow device cases on NVIDIA")
  expect(deadline "SKIP  ${s}: the global deadline \\(8 s\\) has passed")
endforeach()
expect(deadline "SKIP  render sphere-1M 1920x1080 raster and ray on NVIDIA: no sphere-1M.ply")
expect(deadline "result: FAILED: clinfo")
message(STATUS "gpu_check_dry: the three dry runs walk, fail and skip as they should")
