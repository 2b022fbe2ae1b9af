# Oclgrind 21.10's recycled-buffer bug and keep_buffers.c, the shim the oclgrind_tune entry
# preloads against it (recycled_buffer.c says what the bug is). Runs TOOL on Oclgrind with the
# uninitialised-value checker:
#   TOOL 0, no shim: clean (the reproducer itself is sound);
#   TOOL 1, no shim: Oclgrind reports the elements past the released buffer's size (the bug);
#   TOOL 1, SHIM preloaded: clean, and the shim says it kept the program's buffers.
# Where the second run is clean, this Oclgrind has lost the bug: the entry is reported skipped
# (CTest SKIP_REGULAR_EXPRESSION "OCLGRIND_RECYCLED_BUFFER_FIXED"), saying that the shim can go.
# -DTOOL= -DSHIM= -DVENDORS= (an OpenCL vendors folder that lists Oclgrind)
set(reports "Invalid (read|write)|[Dd]ata race|[Uu]ninitiali[sz]ed|divergence|Oclgrind - ") # the oclgrind entries' FAIL_REGULAR_EXPRESSION

# Runs TOOL with `arg` and the extra environment `ARGN`; sets <out> to its stdout and stderr, and
# <count> to the number of Oclgrind's reports in them; a non-zero exit is fatal.
function(run_tool arg out count)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env OCL_ICD_VENDORS=${VENDORS} OCLGRIND_UNINITIALIZED=1
                          OCLGRIND_DATA_RACES=1 OCLGRIND_CHECK_API=1 ${ARGN} ${TOOL} ${arg}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "recycled_buffer ${arg} ${ARGN} exited with ${rc}:\n${stdout}${stderr}")
  endif()
  string(REGEX MATCHALL "${reports}" found "${stdout}${stderr}")
  list(LENGTH found n)
  set(${out} "${stdout}${stderr}" PARENT_SCOPE)
  set(${count} ${n} PARENT_SCOPE)
endfunction()

run_tool(0 control control_reports)
if(NOT control_reports EQUAL 0)
  message(FATAL_ERROR "recycled_buffer 0 (no buffer released) reports on Oclgrind: the reproducer is wrong\n${control}")
endif()
message(STATUS "recycled_buffer 0, no shim: clean")

run_tool(1 bare bare_reports)
run_tool(1 shimmed shimmed_reports LD_PRELOAD=${SHIM} CLVIS_KEEP_BUFFERS_VERBOSE=1)
if(NOT shimmed_reports EQUAL 0)
  message(FATAL_ERROR "recycled_buffer 1 with keep_buffers preloaded still reports ${shimmed_reports} times:\n${shimmed}")
endif()
if(NOT shimmed MATCHES "keep_buffers: kept ([0-9]+) Oclgrind buffers" OR CMAKE_MATCH_1 LESS 3)
  message(FATAL_ERROR "keep_buffers did not keep the program's 3 Oclgrind buffers (was it preloaded?):\n${shimmed}")
endif()
message(STATUS "recycled_buffer 1, keep_buffers preloaded: clean (${CMAKE_MATCH_1} buffers kept)")

if(bare_reports EQUAL 0)
  message(STATUS "OCLGRIND_RECYCLED_BUFFER_FIXED: this Oclgrind keeps a recycled buffer's shadow memory right "
                 "(recycled_buffer 1 ran clean without the shim): the bug tests/oclgrind/keep_buffers.c works "
                 "around is fixed here; the oclgrind_tune entry's LD_PRELOAD and this check can go.")
  return()
endif()
message(STATUS "recycled_buffer 1, no shim: ${bare_reports} reports (Oclgrind's recycled-buffer bug, as expected)")
