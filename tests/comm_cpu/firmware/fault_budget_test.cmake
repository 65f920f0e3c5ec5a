# The paper's rule under faults (docs/firmware.md "Faults and the rule"): with the shipped ROM,
# no interrupt service of any source lasts longer than the budget of docs/system.md -- one
# 9600 8E1 character (11 bits: 1145.833 us) shared by three ports, 381.944 us -- under a host
# BREAK (cases/break.yaml), line-status errors (cases/line_errors.yaml) and a chunk the main CPU
# does not consume in time (cases/chunk_timeout.yaml).  The DP-RAM handler sends its EOI and
# re-enables interrupts within its first instructions, so its wall time (RS-232 handlers nested)
# is not what it blocks: for it the test asserts the latencies (how long every source's requests
# waited), which its blocking would raise.  The failing case: the frozen all-C ROM, which resets
# the port inside the RS-232 handler, exceeds the budget on rs232_0 under the same BREAK.
# Variables: RCSIM (the executable), ROM_C (the frozen all-C ROM), CASES (cases/), WORK (scratch).
foreach(v RCSIM ROM_C CASES WORK)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "fault_budget_test.cmake: -D${v}=... missing")
  endif()
endforeach()
set(budget 381.944) # 11 bits / 9600 bps / 3 ports, docs/system.md "Timing budget"
set(sources rs232_0 rs232_1 rs232_2 dpram)
file(REMOVE_RECURSE "${WORK}")

# Runs CASE (with extra arguments) into WORK/OUT and reads report.json into REPORT.
function(run_case case out report)
  execute_process(COMMAND "${RCSIM}" run "${CASES}/${case}.yaml" --out "${WORK}/${out}" ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE o ERROR_VARIABLE e)
  if(NOT EXISTS "${WORK}/${out}/report.json")
    message(FATAL_ERROR "${out}: exit ${rc}, no report.json\n${o}\n${e}")
  endif()
  file(READ "${WORK}/${out}/report.json" r)
  set(${report} "${r}" PARENT_SCOPE)
endfunction()

# FIGURE (service_us or latency_us) max of SRC in REPORT -> VAR; fails if it was not measured.
function(figure report src fig var)
  string(JSON n ERROR_VARIABLE err GET "${report}" interrupts ${src} ${fig} count)
  if(err OR n EQUAL 0)
    message(FATAL_ERROR "interrupts.${src}.${fig}: not measured (${err})")
  endif()
  string(JSON m GET "${report}" interrupts ${src} ${fig} max)
  set(${var} ${m} PARENT_SCOPE)
endfunction()

# "a < b" for decimal figures (CMake compares integers only).
function(less a b var)
  execute_process(COMMAND awk "BEGIN { exit !(${a} < ${b}) }" RESULT_VARIABLE rc)
  if(rc EQUAL 0)
    set(${var} TRUE PARENT_SCOPE)
  else()
    set(${var} FALSE PARENT_SCOPE)
  endif()
endfunction()

# FIGURE (latency_us or service_us) max of SRC in REPORT must be under the budget; appends
# " SRC FIGURE VALUE" to the variable LINE (the case's status line).
function(under_budget report case src fig what line)
  figure("${report}" ${src} ${fig} v)
  less(${v} ${budget} ok)
  if(NOT ok)
    message(FATAL_ERROR "${case}: ${src} ${what} ${v} us, over the budget ${budget} us")
  endif()
  set(${line} "${${line}} ${src} ${fig} ${v}" PARENT_SCOPE)
endfunction()

# ports[PORT].KEY of REPORT must be at least AT_LEAST: the case hit what it is about.
function(hit report case port key at_least)
  string(JSON n GET "${report}" ports ${port} ${key})
  if(n LESS at_least)
    message(FATAL_ERROR "${case}: ports[${port}].${key} = ${n}, expected at least ${at_least}: the fault missed")
  endif()
endfunction()

foreach(case break line_errors chunk_timeout)
  run_case(${case} ${case} report --profile)
  if(case STREQUAL "break")
    hit("${report}" ${case} 0 break_detects 1)
  elseif(case STREQUAL "line_errors")
    hit("${report}" ${case} 0 parity_errors 1)
    hit("${report}" ${case} 0 framing_errors 1)
    hit("${report}" ${case} 1 framing_errors 1)
  endif()
  if(NOT case STREQUAL "line_errors")
    # the port reset ran, from the main loop (the profile: function, context, calls)
    file(STRINGS "${WORK}/${case}/profile.txt" reinit REGEX "^port_reinit +main +[1-9]")
    if(NOT reinit)
      message(FATAL_ERROR "${case}: no port_reinit from the main loop in profile.txt: the fault missed")
    endif()
  endif()
  set(line "${case}:")
  foreach(src ${sources})
    under_budget("${report}" ${case} ${src} latency_us "waited" line)
    if(src MATCHES "^rs232")
      under_budget("${report}" ${case} ${src} service_us "service took" line)
    endif()
  endforeach()
  message(STATUS "${line}")
endforeach()

run_case(break frozen report --rom "${ROM_C}")
figure("${report}" rs232_0 service_us svc)
less(${budget} ${svc} over)
if(NOT over)
  message(FATAL_ERROR "frozen all-C ROM under the BREAK: rs232_0 service ${svc} us, expected over ${budget} us")
endif()
message(STATUS "frozen all-C ROM, break: rs232_0 service ${svc} us (over the budget, as expected)")
