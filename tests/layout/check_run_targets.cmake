# `make run` builds only what it runs (issue #51 item 1): the Makefile's run target builds the
# rcsim target alone, and rcsim's dependencies, as the build system itself lists them
# (CMakeFiles/Makefile2 of the Unix Makefiles generator, custom-command dependencies included),
# hold the firmware ROM (comm_fw) and no target defined under tests/.
#
#   cmake -DBUILD=DIR [-DSOURCE=DIR] [-DMAKEFILE2=FILE] -P check_run_targets.cmake
# SOURCE: the clone whose Makefile is read (`make -n run`, nothing is built); MAKEFILE2 defaults
# to BUILD/CMakeFiles/Makefile2 (the fixture's is a stand-in). Exit 0 with one line
# "run targets: N targets, firmware comm_fw, no test target"; else an error naming what is wrong.
# Another generator (Ninja) has no Makefile2: the script says "not checked" (the test is skipped).
cmake_minimum_required(VERSION 3.25)
if(NOT MAKEFILE2)
  set(MAKEFILE2 ${BUILD}/CMakeFiles/Makefile2)
endif()

if(SOURCE)
  # Run from `make test`, the outer make's MAKEFLAGS (jobserver, variables) must not reach this one.
  execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=MAKEFLAGS --unset=MFLAGS --unset=MAKELEVEL
                          make -n --no-print-directory -C ${SOURCE} run BUILD=${BUILD}
    OUTPUT_VARIABLE plan ERROR_VARIABLE plan_err RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "make -n run failed (${rc}): ${plan_err}")
  endif()
  string(REGEX MATCHALL "cmake --build[^\n]*" builds "${plan}")
  if(NOT builds)
    message(FATAL_ERROR "make -n run builds nothing with cmake --build:\n${plan}")
  endif()
  foreach(line IN LISTS builds)
    if(NOT line MATCHES "--target rcsim$")
      message(FATAL_ERROR "make run: '${line}' builds more than the rcsim target")
    endif()
  endforeach()
endif()

if(NOT EXISTS ${MAKEFILE2})
  message("run targets: no ${MAKEFILE2} (not the Unix Makefiles generator): not checked")
  return()
endif()

# "DIR/CMakeFiles/T.dir/all: DIR2/CMakeFiles/T2.dir/all": T needs T2 built first.
file(STRINGS ${MAKEFILE2} edges REGEX "^[^ ]*CMakeFiles/[^/ ]+\\.dir/all: [^ ]*CMakeFiles/[^/ ]+\\.dir/all$")
set(seen "")
set(queue "scenarios/CMakeFiles/rcsim.dir")
while(queue)
  list(POP_FRONT queue node)
  if(node IN_LIST seen)
    continue()
  endif()
  list(APPEND seen ${node})
  foreach(edge IN LISTS edges)
    if(edge MATCHES "^${node}/all: (.*)/all$")
      list(APPEND queue ${CMAKE_MATCH_1})
    endif()
  endforeach()
endwhile()

set(firmware "")
foreach(node IN LISTS seen)
  if(node MATCHES "^tests/")
    message(FATAL_ERROR "make run builds a test target: ${node} (defined under tests/), needed by rcsim")
  endif()
  if(node STREQUAL "comm_cpu/firmware/CMakeFiles/comm_fw.dir")
    set(firmware comm_fw)
  endif()
endforeach()
if(NOT firmware)
  message(FATAL_ERROR "rcsim does not depend on the firmware ROM (comm_cpu/firmware comm_fw): make run would run without it")
endif()
list(LENGTH seen n)
message("run targets: ${n} targets, firmware ${firmware}, no test target")
