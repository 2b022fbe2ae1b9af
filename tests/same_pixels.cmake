# Helpers of the scripts that run the built tool and compare its files (included, never run alone):
# run() fails on a non-zero exit status and leaves standard error in `said`; same_pixels() fails
# unless OpenImageIO's idiff (IDIFF) finds no pixel differing at all (files written at two times
# differ in their time stamps, so bytes cannot be compared).
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    string(REPLACE ";" " " command "${ARGN}")
    message(FATAL_ERROR "${command}: exit status ${status}\n${err}${out}")
  endif()
  set(said "${err}" PARENT_SCOPE)
endfunction()

function(same_pixels want got what)
  execute_process(COMMAND ${IDIFF} -fail 0 -warn 0 ${want} ${got} RESULT_VARIABLE differ OUTPUT_VARIABLE out
                  ERROR_VARIABLE out)
  if(NOT differ EQUAL 0)
    message(FATAL_ERROR "${what}: ${got} differs from ${want}:\n${out}")
  endif()
endfunction()
