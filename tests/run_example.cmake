# Runs one example spec through the whole pipeline with the real LIGGGHTS (ctest, script mode):
#   cmake -DGRANSTACK=... -DEXAMPLE=... -DWORK=... -DCASES=N [-DOVERRIDES=a;b] -P run_example.cmake
# Each stage must succeed, reduce --json must print one line per case, and no case may carry
# a warning (e.g. an output sphere that has not separated).
function(step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${WORK})
step(${GRANSTACK} generate -o ${WORK} --config ${EXAMPLE} ${OVERRIDES})
step(${GRANSTACK} run -j 2 ${WORK})
step(${GRANSTACK} reduce --json ${WORK})
string(REGEX MATCHALL "\"output_fraction\":[0-9.e+-]+" fractions "${out}")
list(LENGTH fractions n)
if(NOT n EQUAL CASES)
  message(FATAL_ERROR "expected ${CASES} reduced cases, got ${n}:\n${out}")
endif()
string(REGEX MATCHALL "\"warnings\":\\[\\]" clean "${out}")
list(LENGTH clean n_clean)
if(NOT n_clean EQUAL CASES)
  message(FATAL_ERROR "a case has warnings:\n${out}")
endif()
step(${GRANSTACK} reduce ${WORK})
message("${out}")
