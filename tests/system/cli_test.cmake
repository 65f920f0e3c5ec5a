# CLI checks of the rcsim executable (run with cmake -P):
#   1. the same scenario run twice with --reproducible gives byte-identical report.json files;
#   2. a scenario with a misspelt key exits 2 and the message names file:line;
#   3. --rom with a file of the wrong size exits 2 and the message names the file.
# Variables: RCSIM (the executable), DATA (tests/system/data), WORK (a scratch directory).
foreach(v RCSIM DATA WORK)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "cli_test.cmake: -D${v}=... missing")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")

# 1. reproducibility
foreach(run a b)
  execute_process(COMMAND "${RCSIM}" run "${DATA}/short_three_ports.yaml" --out "${WORK}/${run}" --reproducible
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "run ${run}: exit ${rc}, expected 0\n${out}\n${err}")
  endif()
  if(NOT EXISTS "${WORK}/${run}/report.json")
    message(FATAL_ERROR "run ${run}: no report.json\n${out}")
  endif()
endforeach()
file(READ "${WORK}/a/report.json" ra)
file(READ "${WORK}/b/report.json" rb)
string(LENGTH "${ra}" na)
if(na LESS 100)
  message(FATAL_ERROR "report.json is suspiciously short (${na} bytes):\n${ra}")
endif()
if(NOT ra STREQUAL rb)
  execute_process(COMMAND diff "${WORK}/a/report.json" "${WORK}/b/report.json" OUTPUT_VARIABLE d)
  message(FATAL_ERROR "two --reproducible runs differ:\n${d}")
endif()
if(NOT ra MATCHES "\"wall_time_s\": *0")
  message(FATAL_ERROR "--reproducible: wall_time_s is not 0")
endif()

# 2. a misspelt key
execute_process(COMMAND "${RCSIM}" run "${DATA}/misspelt_key.yaml" --out "${WORK}/bad"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "misspelt key: exit ${rc}, expected 2\n${out}\n${err}")
endif()
string(FIND "${err}" "misspelt_key.yaml:4" at)
if(at EQUAL -1)
  message(FATAL_ERROR "misspelt key: the message does not name misspelt_key.yaml:4:\n${err}")
endif()
string(FIND "${err}" "duraton_s" at)
if(at EQUAL -1)
  message(FATAL_ERROR "misspelt key: the message does not name the key:\n${err}")
endif()

# 3. a ROM image of the wrong size
file(WRITE "${WORK}/short.rom" "not a 64 KB image")
execute_process(COMMAND "${RCSIM}" run "${DATA}/short_three_ports.yaml" --rom "${WORK}/short.rom"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "--rom wrong size: exit ${rc}, expected 2\n${out}\n${err}")
endif()
string(FIND "${err}" "short.rom" at)
if(at EQUAL -1)
  message(FATAL_ERROR "--rom wrong size: the message does not name the file:\n${err}")
endif()
message(STATUS "rcsim CLI: reproducible reports, exit 2 for a misspelt key and a wrong-size ROM")
