# Runs a command and passes only when it exits 0 AND its output (stdout and stderr, merged as
# ctest shows them) matches a regular expression. ctest's PASS_REGULAR_EXPRESSION alone ignores
# the exit status, so a program that prints the expected lines and then crashes would pass.
#   cmake -DEXPECT=REGEX -P expect_output.cmake -- PROGRAM ARG...
# (the command after `--`, not in a -D list: ctest splits an add_test argument at semicolons).
# The output is echoed either way, so a failure shows what the command said.
if(NOT DEFINED EXPECT OR EXPECT STREQUAL "")
  message(FATAL_ERROR "expect_output.cmake: -DEXPECT=... missing")
endif()
set(command)
set(after_dashes FALSE)
math(EXPR last "${CMAKE_ARGC} - 1")
foreach(i RANGE ${last})
  if(after_dashes)
    string(REPLACE ";" "\\;" arg "${CMAKE_ARGV${i}}") # one argument, even with a ; in it
    list(APPEND command "${arg}")
  elseif(CMAKE_ARGV${i} STREQUAL "--")
    set(after_dashes TRUE)
  endif()
endforeach()
if(NOT command)
  message(FATAL_ERROR "expect_output.cmake: no command after --")
endif()
execute_process(COMMAND ${command} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
message("${out}")
# rc is a number, or a text such as "Segmentation fault" when the program died of a signal.
if(NOT rc STREQUAL "0")
  message(FATAL_ERROR "expect_output: exit status '${rc}', expected 0")
endif()
if(NOT out MATCHES "${EXPECT}")
  message(FATAL_ERROR "expect_output: the output does not match '${EXPECT}'")
endif()
message("expect_output: exit 0 and the output matches")
